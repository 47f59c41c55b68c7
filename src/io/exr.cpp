// OpenEXR through tinyexr: 32-bit float channels "<layer>.<C>", metadata as string attributes.
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <memory>

#include <fmt/format.h>
#include <tinyexr.h>

#include "io/image_io.h"
#include "io/image_stream.h"
#include "io/io_util.h"

namespace anamorph {

namespace fs = std::filesystem;
using io_detail::fail;
using io_detail::fail_read;

namespace {

std::string take_error(const char* err, const char* fallback) {
  std::string msg = err ? err : fallback;
  if (err) FreeEXRErrorMessage(err);
  return msg;
}

// Owns a parsed header (and optionally its image); frees both the tinyexr way.
struct ParsedExr {
  EXRVersion version{};
  EXRHeader header{};
  EXRImage image{};
  bool has_header = false, has_image = false;
  std::vector<unsigned char> renamed;  // the file with its `type` attributes renamed, if any
  ~ParsedExr() {
    if (has_image) FreeEXRImage(&image);
    if (has_header) FreeEXRHeader(&header);
  }
};

// OpenEXR's chlist: per channel name\0, pixel type (int32: 0 uint, 1 half, 2 float), pLinear,
// 3 reserved bytes, x and y sampling (int32), then a terminating \0. tinyexr asserts on any
// other pixel type and on a header without channels (a zero-sized decode buffer), and does not
// read subsampled channels.
void check_channel_list(const std::vector<unsigned char>& b, size_t at, size_t size,
                        const fs::path& file) {
  const size_t end = at + size;
  int channels = 0;
  while (at < end && b[at] != 0) {
    const auto* name_end =
        static_cast<const unsigned char*>(std::memchr(b.data() + at, 0, end - at));
    if (!name_end || size_t(name_end - b.data()) + 1 + 16 > end) return;  // tinyexr's error
    at = size_t(name_end - b.data()) + 1;
    int32_t type = 0, xs = 0, ys = 0;
    std::memcpy(&type, b.data() + at, 4);
    std::memcpy(&xs, b.data() + at + 8, 4);
    std::memcpy(&ys, b.data() + at + 12, 4);
    at += 16;
    if (type < 0 || type > 2)
      fail_read(
          "cannot read EXR", file,
          fmt::format("channel {} has pixel type {} (0 uint, 1 half, 2 float)", channels, type));
    if (xs != 1 || ys != 1)
      fail_read("cannot read EXR", file,
                fmt::format("channel {} is subsampled ({} x {}): not supported", channels, xs, ys));
    ++channels;
  }
  if (channels == 0) fail_read("cannot read EXR", file, "its header lists no channels");
}

// The header's attributes that tinyexr 1.0 checks with assert() instead of an error (an abort
// in a release build: found by fuzz_image): `tiles` must be a 9-byte tiledesc, the channel list
// must be sound (check_channel_list), and `type` (an image's scanline or tiled, which tinyexr
// asserts is consistent with its own notion of tiled, set or not by attributes it may never
// reach in a damaged header) is taken out of its sight: returns the offsets of every attribute
// named `type`, which parse_header renames. Walks name\0 type\0 size data... up to the empty
// name or to where the header is cut short (tinyexr converts a failed header too).
std::vector<size_t> check_header_attributes(const std::vector<unsigned char>& b,
                                            const fs::path& file) {
  size_t at = 8;  // magic and version
  const auto text = [&](std::string* out) {
    if (at >= b.size()) return false;
    const auto* end =
        static_cast<const unsigned char*>(std::memchr(b.data() + at, 0, b.size() - at));
    if (!end) return false;
    out->assign(reinterpret_cast<const char*>(b.data() + at), size_t(end - (b.data() + at)));
    at = size_t(end - b.data()) + 1;
    return true;
  };
  std::vector<size_t> type_names;
  for (;;) {
    std::string name, type;
    const size_t name_at = at;
    if (!text(&name) || name.empty()) break;
    if (!text(&type) || at + 4 > b.size()) break;
    uint32_t size = 0;
    std::memcpy(&size, b.data() + at, 4);  // little-endian, as every host we build for
    at += 4;
    if (size > b.size() - at) break;
    if (name == "tiles" && size != 9)
      fail_read("cannot read EXR", file,
                fmt::format("its tiles attribute has {} bytes, not 9", size));
    if (name == "channels") check_channel_list(b, at, size, file);
    if (name == "type") {
      type_names.push_back(name_at);
      std::string value(reinterpret_cast<const char*>(b.data() + at), size);
      value = value.substr(0, value.find('\0'));
      if (!value.empty() && value != "scanlineimage" && value != "tiledimage")
        fail_read("cannot read EXR", file,
                  "its type attribute is neither scanlineimage nor tiledimage (deep or damaged)");
    }
    at += size;
  }
  return type_names;
}

// What tinyexr reads instead of a `type` attribute (same length, so no offset moves).
constexpr char kRenamedType[] = "tyqe";

// Parses the header; returns the bytes tinyexr is to read the image from (b, or a copy with the
// `type` attributes renamed, see check_header_attributes).
const std::vector<unsigned char>& parse_header(ParsedExr& exr, const std::vector<unsigned char>& b,
                                               const fs::path& file) {
  if (ParseEXRVersionFromMemory(&exr.version, b.data(), b.size()) != TINYEXR_SUCCESS)
    fail_read("cannot read EXR", file, "not a valid OpenEXR file");
  if (exr.version.multipart || exr.version.non_image)
    fail_read("cannot read EXR", file, "multi-part and deep EXR files are not supported");
  const std::vector<size_t> type_names = check_header_attributes(b, file);
  const std::vector<unsigned char>* bytes = &b;
  if (!type_names.empty()) {
    exr.renamed = b;
    for (size_t at : type_names) std::memcpy(exr.renamed.data() + at, kRenamedType, 4);
    bytes = &exr.renamed;
  }
  InitEXRHeader(&exr.header);
  const char* err = nullptr;
  const int parsed =
      ParseEXRHeaderFromMemory(&exr.header, &exr.version, bytes->data(), bytes->size(), &err);
  // tinyexr 1.0 converts what it parsed into the header even when parsing failed (channels,
  // attributes: malloc'd), so the header is ours to free either way; not freeing it leaked a
  // little per bad file, which fuzz_image's million inputs turned into 3 GB.
  exr.has_header = true;
  if (parsed != TINYEXR_SUCCESS)
    fail_read("cannot read EXR", file, take_error(err, "invalid header"));
  return *bytes;
}

}  // namespace

void write_exr(const fs::path& file, const OutputImage& img) {
  io_detail::check_output(img, file);
  std::vector<LayerSpec> layers;
  std::vector<const float*> data;
  for (const ImageLayer& l : img.layers) {
    layers.push_back({l.name, l.channels});
    data.push_back(l.data.data());
  }
  ExrStream exr(file, img.width, img.height, layers, img.metadata);
  exr.write_rows(data, img.height);
  exr.commit();
}

io_detail::ExrChannels io_detail::load_exr(const std::vector<unsigned char>& b,
                                           const fs::path& file) {
  ParsedExr exr;
  const std::vector<unsigned char>& bytes = parse_header(exr, b, file);
  EXRHeader& h = exr.header;
  for (int c = 0; c < h.num_channels; ++c)
    if (h.pixel_types[c] == TINYEXR_PIXELTYPE_HALF)
      h.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
  check_read_size(file, int64_t(h.data_window.max_x) - h.data_window.min_x + 1,
                  int64_t(h.data_window.max_y) - h.data_window.min_y + 1, b.size());
  InitEXRImage(&exr.image);
  const char* err = nullptr;
  // Not freed on failure: tinyexr 1.0's DecodeEXRImage frees the image itself on a failed chunk
  // but leaves the pointers set, so FreeEXRImage here would free them twice.
  if (LoadEXRImageFromMemory(&exr.image, &h, bytes.data(), bytes.size(), &err) != TINYEXR_SUCCESS)
    fail_read("cannot read EXR", file, take_error(err, "invalid image data"));
  exr.has_image = true;

  ExrChannels out;
  out.width = exr.image.width;
  out.height = exr.image.height;
  const size_t w = size_t(out.width), pixels = w * size_t(out.height);
  for (int c = 0; c < h.num_channels; ++c) {
    // After loading, pixel types are the requested ones: FLOAT, or UINT left as is.
    const bool is_uint = h.requested_pixel_types[c] == TINYEXR_PIXELTYPE_UINT;
    auto value = [&](const unsigned char* plane, size_t i) {
      return is_uint ? float(reinterpret_cast<const uint32_t*>(plane)[i])
                     : reinterpret_cast<const float*>(plane)[i];
    };
    std::vector<float> plane(pixels);
    if (h.tiled) {
      for (int t = 0; t < exr.image.num_tiles; ++t) {
        const EXRTile& tile = exr.image.tiles[t];
        if (tile.level_x != 0 || tile.level_y != 0) continue;
        const size_t x0 = size_t(tile.offset_x) * size_t(h.tile_size_x);
        const size_t y0 = size_t(tile.offset_y) * size_t(h.tile_size_y);
        for (size_t y = 0; y < size_t(tile.height); ++y)
          for (size_t x = 0; x < size_t(tile.width); ++x)
            plane[(y0 + y) * w + x0 + x] = value(tile.images[c], y * size_t(h.tile_size_x) + x);
      }
    } else {
      for (size_t i = 0; i < pixels; ++i) plane[i] = value(exr.image.images[c], i);
    }
    out.channels[h.channels[c].name] = std::move(plane);
  }
  return out;
}

std::map<std::string, std::string> io_detail::exr_metadata(const std::vector<unsigned char>& b,
                                                           const fs::path& file) {
  ParsedExr exr;
  parse_header(exr, b, file);
  std::map<std::string, std::string> meta;
  for (int i = 0; i < exr.header.num_custom_attributes; ++i) {
    const EXRAttribute& a = exr.header.custom_attributes[i];
    if (std::strcmp(a.type, "string") != 0 || std::strcmp(a.name, kRenamedType) == 0) continue;
    std::string value(reinterpret_cast<const char*>(a.value), size_t(std::max(a.size, 0)));
    if (value == std::string(1, '\0')) value.clear();  // tinyexr's form of an empty string
    meta[a.name] = std::move(value);
  }
  return meta;
}

}  // namespace anamorph
