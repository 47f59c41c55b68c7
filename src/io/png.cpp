// PNG: our encoder (row filters, zlib in parallel bands) writes, stb decodes; metadata goes into
// tEXt/iTXt chunks after IHDR.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <optional>
#include <string_view>

#include <fmt/format.h>
#include <stb_image.h>
#include <zlib.h>
#include "math/parallel.h"

#include "io/image_io.h"
#include "io/image_stream.h"
#include "io/io_util.h"

namespace anamorph {

namespace fs = std::filesystem;
using io_detail::fail;
using io_detail::fail_read;

namespace {

// CRC-32 (ISO 3309, polynomial 0xedb88320) as PNG chunks use it.
constexpr std::array<uint32_t, 256> kCrcTable = [] {
  std::array<uint32_t, 256> t{};
  for (uint32_t n = 0; n < 256; ++n) {
    uint32_t c = n;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xedb88320u ^ (c >> 1) : c >> 1;
    t[n] = c;
  }
  return t;
}();

uint32_t crc32(const unsigned char* p, size_t n) {
  uint32_t c = 0xffffffffu;
  for (size_t i = 0; i < n; ++i) c = kCrcTable[(c ^ p[i]) & 0xff] ^ (c >> 8);
  return c ^ 0xffffffffu;
}

uint32_t read_be32(const unsigned char* p) {
  return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | uint32_t(p[3]);
}

void write_be32(unsigned char* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<unsigned char>(v >> (24 - 8 * i));
}

// length, type, data, CRC of type and data.
std::vector<unsigned char> make_chunk(const char type[4], const std::string& data) {
  std::vector<unsigned char> c(data.size() + 12);
  write_be32(c.data(), uint32_t(data.size()));
  std::memcpy(c.data() + 4, type, 4);
  std::memcpy(c.data() + 8, data.data(), data.size());
  write_be32(c.data() + 8 + data.size(), crc32(c.data() + 4, data.size() + 4));
  return c;
}

// UTF-8 to code points; false on malformed input.
bool decode_utf8(std::string_view s, std::u32string* out) {
  out->clear();
  for (size_t i = 0; i < s.size();) {
    const auto b = static_cast<unsigned char>(s[i]);
    const int extra = b < 0x80         ? 0
                      : (b >> 5) == 6  ? 1
                      : (b >> 4) == 14 ? 2
                      : (b >> 3) == 30 ? 3
                                       : -1;
    if (extra < 0 || i + size_t(extra) >= s.size()) return false;
    char32_t cp = extra == 0 ? b : b & (0x3f >> extra);
    for (int k = 1; k <= extra; ++k) {
      const auto c = static_cast<unsigned char>(s[i + size_t(k)]);
      if ((c & 0xc0) != 0x80) return false;
      cp = cp << 6 | (c & 0x3f);
    }
    static constexpr char32_t kMin[4] = {0, 0x80, 0x800, 0x10000};
    if (cp < kMin[extra] || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) return false;
    out->push_back(cp);
    i += size_t(extra) + 1;
  }
  return true;
}

// The Latin-1 bytes of a UTF-8 string, or nothing if it has characters beyond U+00FF.
std::optional<std::string> utf8_to_latin1(std::string_view s) {
  std::u32string cps;
  if (!decode_utf8(s, &cps)) return std::nullopt;
  std::string out;
  for (char32_t cp : cps) {
    if (cp > 0xff) return std::nullopt;
    out.push_back(static_cast<char>(cp));
  }
  return out;
}

std::string latin1_to_utf8(std::string_view s) {
  std::string out;
  for (char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x80) {
      out.push_back(ch);
    } else {
      out.push_back(static_cast<char>(0xc0 | c >> 6));
      out.push_back(static_cast<char>(0x80 | (c & 0x3f)));
    }
  }
  return out;
}

// PNG keywords: 1-79 printable Latin-1 characters, no leading, trailing or double spaces.
bool valid_keyword(const std::string& k) {
  if (k.empty() || k.size() > 79 || k.front() == ' ' || k.back() == ' ') return false;
  if (k.find("  ") != std::string::npos) return false;
  return std::all_of(k.begin(), k.end(), [](char ch) {
    const auto c = static_cast<unsigned char>(ch);
    return (c >= 32 && c <= 126) || c >= 161;
  });
}

// tEXt when the value is Latin-1 (every reader understands it), iTXt (uncompressed UTF-8)
// otherwise. Length alone does not choose iTXt: uncompressed iTXt is no smaller than tEXt.
std::vector<unsigned char> text_chunk(const std::string& key, const std::string& value,
                                      const fs::path& file) {
  const std::optional<std::string> k = utf8_to_latin1(key);
  if (!k || !valid_keyword(*k))
    fail("cannot write PNG", file,
         fmt::format("metadata key '{}' must be 1-79 printable Latin-1 characters", key));
  std::u32string cps;
  if (value.find('\0') != std::string::npos || !decode_utf8(value, &cps))
    fail("cannot write PNG", file,
         fmt::format("value of metadata key '{}' is not NUL-free UTF-8 text", key));
  if (const std::optional<std::string> v = utf8_to_latin1(value))
    return make_chunk("tEXt", *k + '\0' + *v);
  // keyword NUL, compression flag 0, method 0, empty language tag NUL, empty translation NUL.
  return make_chunk("iTXt", *k + std::string("\0\0\0\0\0", 5) + value);
}

// PNG row filters 0 (none), 1 (sub) and 2 (up) for RGBA8; each row takes the one with the
// smallest sum of absolute signed bytes (libpng's heuristic), which compresses renders as well
// as trying all five.
void filter_row(const unsigned char* row, const unsigned char* prev, size_t n, unsigned char* out) {
  const auto cost = [](unsigned char b) { return b < 128 ? unsigned(b) : 256u - b; };
  unsigned best = ~0u;
  int best_f = 0;
  for (int f = 0; f < 3; ++f) {
    if (f == 2 && !prev) break;
    unsigned sum = 0;
    for (size_t i = 0; i < n && sum < best; ++i) {
      const unsigned char left = i >= 4 ? row[i - 4] : 0, up = prev ? prev[i] : 0;
      sum += cost(static_cast<unsigned char>(row[i] - (f == 1 ? left : f == 2 ? up : 0)));
    }
    if (sum < best) best = sum, best_f = f;
  }
  out[0] = static_cast<unsigned char>(best_f);
  for (size_t i = 0; i < n; ++i) {
    const unsigned char left = i >= 4 ? row[i - 4] : 0, up = prev ? prev[i] : 0;
    out[1 + i] = static_cast<unsigned char>(row[i] - (best_f == 1 ? left : best_f == 2 ? up : 0));
  }
}

std::string inflate(const unsigned char* p, size_t n, const fs::path& file) {
  int len = 0;
  std::unique_ptr<char, decltype(&std::free)> out(
      stbi_zlib_decode_malloc(reinterpret_cast<const char*>(p), int(n), &len), &std::free);
  if (!out) fail_read("corrupt PNG", file, "cannot decompress a text chunk");
  return std::string(out.get(), size_t(len));
}

}  // namespace

void encode_rgba8(const float* rgba, unsigned char* out) { encode_rgba8(rgba, 1, out); }

void write_png(const fs::path& file, const OutputImage& img) {
  io_detail::check_output(img, file);
  const ImageLayer& beauty = img.layers[0];
  const size_t nc = beauty.channels.size();
  if (nc != 3 && nc != 4)
    fail("cannot write PNG", file,
         fmt::format("the first layer must be RGB or RGBA, it has {} channels", nc));

  // Straight (un-premultiplied) colour, as the film stores it and PNG expects. Colour is
  // sRGB-encoded; alpha is linear coverage and is not. Rows in parallel: at 1080p the encoding
  // is a visible part of a quick render.
  Rgba8Image out;
  out.width = img.width;
  out.height = img.height;
  out.metadata = img.metadata;
  out.rgba.resize(size_t(img.width) * size_t(img.height) * 4);
  parallel_for_each(0, img.height, [&](int y) {
    for (size_t i = size_t(y) * size_t(img.width); i < size_t(y + 1) * size_t(img.width); ++i) {
      const float* src = &beauty.data[i * nc];
      const float px[4] = {src[0], src[1], src[2], nc == 4 ? src[3] : 1.0f};
      encode_rgba8(px, &out.rgba[i * 4]);
    }
  });
  write_png(file, out);
}

void write_png(const fs::path& file, const Rgba8Image& img) {
  if (img.width <= 0 || img.height <= 0)
    fail("cannot write image", file, fmt::format("invalid size {}x{}", img.width, img.height));
  if (img.rgba.size() != size_t(img.width) * size_t(img.height) * 4)
    fail("cannot write image", file,
         fmt::format("{} bytes for a {}x{} RGBA image", img.rgba.size(), img.width, img.height));
  // Bands of 64 rows encoded in parallel (about 4x faster than stb's encoder at 1080p, for
  // smaller files), appended in order.
  constexpr int kBandRows = 64;
  const int bands = (img.height + kBandRows - 1) / kBandRows;
  std::vector<PngStream::Band> encoded(static_cast<size_t>(bands));
  const auto rows_of = [&](int b) { return std::min(kBandRows, img.height - b * kBandRows); };
  parallel_for_each(0, bands, [&](int b) {
    encoded[size_t(b)] =
        PngStream::encode(&img.rgba[size_t(b) * kBandRows * img.width * 4], img.width, rows_of(b));
  });
  PngStream png(file, img.width, img.height, img.metadata);
  for (int b = 0; b < bands; ++b) png.append(encoded[size_t(b)], rows_of(b));
  png.commit();
}

PngStream::PngStream(const fs::path& file, int width, int height,
                     const std::map<std::string, std::string>& metadata)
    : file_(file), width_(width), height_(height), adler_(adler32(0, nullptr, 0)) {
  if (width <= 0 || height <= 0 || width > (1 << 24) || height > (1 << 24))
    fail("cannot write image", file, fmt::format("invalid size {}x{}", width, height));
  unsigned char h[13];
  write_be32(h, uint32_t(width));
  write_be32(h + 4, uint32_t(height));
  h[8] = 8;   // bits per channel
  h[9] = 6;   // RGBA
  h[10] = 0;  // deflate
  h[11] = 0;  // adaptive row filters
  h[12] = 0;  // no interlace
  std::vector<std::vector<unsigned char>> chunks;
  chunks.push_back(make_chunk("IHDR", std::string(reinterpret_cast<const char*>(h), 13)));
  for (const auto& [key, value] : metadata) chunks.push_back(text_chunk(key, value, file));
  out_ = std::make_unique<AtomicFile>(file);
  out_->write(io_detail::kPngSignature, 8);
  for (const auto& c : chunks) out_->write(c.data(), c.size());
}

PngStream::~PngStream() = default;

PngStream::Band PngStream::encode(const unsigned char* rgba, int width, int rows) {
  const size_t stride = size_t(width) * 4, line = stride + 1;
  std::vector<unsigned char> filtered(line * size_t(rows));
  for (int y = 0; y < rows; ++y)
    filter_row(rgba + size_t(y) * stride, y > 0 ? rgba + size_t(y - 1) * stride : nullptr, stride,
               &filtered[size_t(y) * line]);
  Band band;
  band.raw_bytes = filtered.size();
  band.adler = adler32(adler32(0, nullptr, 0), filtered.data(), uInt(filtered.size()));
  z_stream z{};
  if (deflateInit2(&z, 3, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw ImageIoError("cannot write PNG: deflateInit failed");
  band.deflated.resize(deflateBound(&z, uLong(filtered.size())) + 16);
  z.next_in = filtered.data();
  z.avail_in = uInt(filtered.size());
  z.next_out = reinterpret_cast<unsigned char*>(band.deflated.data());
  z.avail_out = uInt(band.deflated.size());
  const int r = deflate(&z, Z_FULL_FLUSH);
  const bool ok = r == Z_OK && z.avail_in == 0;
  band.deflated.resize(band.deflated.size() - z.avail_out);
  deflateEnd(&z);
  if (!ok) throw ImageIoError("cannot write PNG: deflate failed");
  return band;
}

void PngStream::append(const Band& band, int rows) {
  if (rows_ + rows > height_)
    fail("cannot write PNG", file_,
         fmt::format("{} rows for a {}-row image", rows_ + rows, height_));
  // The zlib header (deflate, 32 KiB window, "fast" level) leads the first IDAT chunk.
  std::string data = rows_ == 0 ? std::string("\x78\x5e", 2) : std::string();
  data += band.deflated;
  const auto chunk = make_chunk("IDAT", data);
  out_->write(chunk.data(), chunk.size());
  adler_ = adler32_combine(adler_, band.adler, z_off_t(band.raw_bytes));
  rows_ += rows;
}

void PngStream::finish() {
  if (rows_ != height_)
    fail("cannot write PNG", file_, fmt::format("{} of {} rows written", rows_, height_));
  // An empty final block (fixed Huffman, end of block) closes the deflate stream.
  std::string tail("\x03\x00", 2);
  unsigned char a[4];
  write_be32(a, uint32_t(adler_));
  tail.append(reinterpret_cast<const char*>(a), 4);
  for (const auto& c : {make_chunk("IDAT", tail), make_chunk("IEND", "")})
    out_->write(c.data(), c.size());
}

void PngStream::commit() {
  finish();
  out_->commit();
}

void PngStream::commit_as(const fs::path& other) {
  finish();
  out_->commit_as(other);
}

std::map<std::string, std::string> io_detail::png_metadata(const std::vector<unsigned char>& b,
                                                           const fs::path& file) {
  std::map<std::string, std::string> meta;
  auto corrupt = [&](const std::string& why) { fail_read("corrupt PNG", file, why); };
  for (size_t pos = 8; pos + 12 <= b.size();) {
    const uint32_t len = read_be32(&b[pos]);
    if (len > b.size() - pos - 12) corrupt("a chunk runs past the end of the file");
    const std::string type(reinterpret_cast<const char*>(&b[pos + 4]), 4);
    const unsigned char* data = &b[pos + 8];
    if (crc32(&b[pos + 4], size_t(len) + 4) != read_be32(data + len))
      corrupt(fmt::format("CRC mismatch in a {} chunk", type));
    pos += size_t(len) + 12;
    if (type == "IEND") break;
    if (type != "tEXt" && type != "zTXt" && type != "iTXt") continue;

    const std::string body(reinterpret_cast<const char*>(data), len);
    const size_t key_end = body.find('\0');
    if (key_end == std::string::npos) corrupt(fmt::format("malformed {} chunk", type));
    const std::string key = latin1_to_utf8(body.substr(0, key_end));
    const size_t rest = key_end + 1;
    if (type == "tEXt") {
      meta[key] = latin1_to_utf8(body.substr(rest));
    } else if (type == "zTXt") {
      if (rest + 1 > body.size()) corrupt("malformed zTXt chunk");
      meta[key] = latin1_to_utf8(inflate(data + rest + 1, len - rest - 1, file));
    } else {  // iTXt: flag, method, language NUL, translated keyword NUL, UTF-8 text
      const size_t lang_end = rest + 2 <= body.size() ? body.find('\0', rest + 2) : body.npos;
      const size_t trans_end = lang_end == body.npos ? body.npos : body.find('\0', lang_end + 1);
      if (trans_end == body.npos) corrupt("malformed iTXt chunk");
      const bool compressed = body[rest] != 0;
      meta[key] = compressed ? inflate(data + trans_end + 1, len - trans_end - 1, file)
                             : body.substr(trans_end + 1);
    }
  }
  return meta;
}

}  // namespace anamorph
