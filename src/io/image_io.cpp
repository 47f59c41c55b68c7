// Reading any supported image into linear RGBA, dispatch of writes by extension and of metadata
// reads by file signature, the sRGB transfer functions and shared helpers.
#include "io/image_io.h"

#include "math/user_text.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>
#include <stb_image.h>

#include "io/io_util.h"
#include "io/read_file.h"

namespace anamorph {

namespace fs = std::filesystem;

namespace io_detail {

void fail(std::string_view what, const fs::path& file, std::string_view reason) {
  throw ImageIoError(fmt::format("{} '{}': {}", what, printable(file.native()), reason));
}

void fail_read(std::string_view what, const fs::path& file, std::string_view reason) {
  throw ImageReadError(fmt::format("{} '{}': {}", what, printable(file.native()), reason));
}

void check_read_size(const fs::path& file, int64_t width, int64_t height, size_t file_bytes) {
  if (width <= 0 || height <= 0)
    fail_read("cannot read image", file, fmt::format("invalid size {} x {}", width, height));
  const uint64_t pixels = uint64_t(width) * uint64_t(height);
  if (pixels > kMaxReadPixels)
    fail_read("cannot read image", file,
              fmt::format("{} x {} pixels is more than the {} million pixels anamorph reads", width,
                          height, kMaxReadPixels / 1000000));
  if (pixels > kSmallImagePixels && pixels / kMaxPixelsPerByte > file_bytes)
    fail_read("cannot read image", file,
              fmt::format("the {}-byte file declares {} x {} pixels, more than {} per byte any "
                          "image format packs: a damaged file or a decompression bomb",
                          file_bytes, width, height, kMaxPixelsPerByte));
}

std::vector<unsigned char> read_file_bytes(const fs::path& file) {
  if (has_nul(file.native()))
    fail_read("cannot read", file, nul_in_path_message(file.native(), false));
  std::vector<unsigned char> bytes;
  if (const auto failure = read_whole_file(file, &bytes, kImageInput))
    fail_read("cannot read image", file, failure->reason);
  return bytes;
}

bool is_png(const std::vector<unsigned char>& b) {
  return b.size() >= 8 && std::memcmp(b.data(), kPngSignature, 8) == 0;
}

unsigned char unit_to_byte(float v) {
  // NaN and negatives become 0; the clamp keeps out-of-gamut values from wrapping.
  const float c = v > 0.0f ? std::min(v, 1.0f) : 0.0f;
  return static_cast<unsigned char>(std::lround(c * 255.0f));
}

bool is_exr(const std::vector<unsigned char>& b) {
  return b.size() >= 4 && b[0] == 0x76 && b[1] == 0x2f && b[2] == 0x31 && b[3] == 0x01;
}

void check_output(const OutputImage& img, const fs::path& file) {
  if (img.width <= 0 || img.height <= 0)
    fail("cannot write image", file, fmt::format("invalid size {}x{}", img.width, img.height));
  if (img.layers.empty()) fail("cannot write image", file, "no layers to write");
  const size_t pixels = size_t(img.width) * size_t(img.height);
  for (const ImageLayer& l : img.layers) {
    if (l.channels.empty())
      fail("cannot write image", file, fmt::format("layer '{}' has no channels", l.name));
    if (l.data.size() != pixels * l.channels.size())
      fail("cannot write image", file,
           fmt::format("layer '{}' holds {} values, expected {}x{}x{} = {}", l.name, l.data.size(),
                       img.width, img.height, l.channels.size(), pixels * l.channels.size()));
  }
}

}  // namespace io_detail

using io_detail::fail;
using io_detail::fail_read;

float linear_to_srgb(float v) {
  const double x = v;
  return float(x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055);
}

namespace {

// The code 8-bit output has traditionally been: the encoded value clamped and rounded.
unsigned char srgb8_reference(float v) { return io_detail::unit_to_byte(linear_to_srgb(v)); }

// t[k]: the smallest float whose code is at least k (k = 1..255), found by bisection on the bit
// patterns of [0, 1] (the reference is monotonic; checked for every float in [0, 1]).
std::array<float, 256> srgb8_thresholds() {
  std::array<float, 256> t{};
  for (int k = 1; k <= 255; ++k) {
    uint32_t lo = 0, hi = 0x3f800000u;  // the bits of 0.0f and 1.0f
    while (lo < hi) {
      const uint32_t mid = lo + (hi - lo) / 2;
      if (srgb8_reference(std::bit_cast<float>(mid)) >= k)
        hi = mid;
      else
        lo = mid + 1;
    }
    t[size_t(k)] = std::bit_cast<float>(lo);
  }
  return t;
}

// The code of a float in [2^-13, 1) from its bits: buckets of the exponent and the top 8
// mantissa bits hold at most one threshold each (the steepest part of the curve, at 2^-13,
// climbs 0.002 codes per bucket; the widest buckets, just below 1, 0.3 codes), so the code at a
// bucket's start plus one comparison is exact. Below 2^-13 every code is 0 (t[1] is 1.5e-4).
struct Srgb8Table {
  static constexpr uint32_t kLowBits = 0x39000000u;  // 2^-13
  static constexpr int kShift = 15;                  // keep 8 of the 23 mantissa bits
  static constexpr size_t kBuckets = (0x3f800000u - kLowBits) >> kShift;
  std::array<float, 257> t;  // thresholds, t[256] = infinity
  std::array<uint8_t, kBuckets> start;

  Srgb8Table() {
    const std::array<float, 256> th = srgb8_thresholds();
    std::copy(th.begin(), th.end(), t.begin());
    t[256] = std::numeric_limits<float>::infinity();
    if (!(t[1] >= std::bit_cast<float>(kLowBits)))
      throw std::logic_error("sRGB table: code 1 starts below 2^-13");
    int code = 0;
    for (size_t b = 0; b < kBuckets; ++b) {
      const float first = std::bit_cast<float>(kLowBits + (uint32_t(b) << kShift));
      const float last = std::bit_cast<float>(kLowBits + (uint32_t(b + 1) << kShift) - 1);
      while (first >= t[size_t(code) + 1]) ++code;
      start[b] = uint8_t(code);
      if (code < 255 && last >= t[size_t(code) + 2])
        throw std::logic_error("sRGB table: two code boundaries in one bucket");
    }
  }
};

const Srgb8Table& srgb8_table() {
  static const Srgb8Table T;
  return T;
}

inline unsigned char srgb8(const Srgb8Table& T, float v) {
  if (!(v >= std::bit_cast<float>(Srgb8Table::kLowBits))) return 0;  // NaN, negative, tiny
  if (v >= 1.0f) return 255;
  const uint32_t b = (std::bit_cast<uint32_t>(v) - Srgb8Table::kLowBits) >> Srgb8Table::kShift;
  const int code = T.start[b];
  return static_cast<unsigned char>(code + (v >= T.t[size_t(code) + 1] ? 1 : 0));
}

// unit_to_byte without the libm call: floor(x + 0.5) in double is exact for x = c * 255 in
// [0, 255], and equals lround there.
inline unsigned char unit_byte(float v) {
  const float c = v > 0.0f ? std::min(v, 1.0f) : 0.0f;
  return static_cast<unsigned char>(double(c * 255.0f) + 0.5);
}

}  // namespace

unsigned char linear_to_srgb8(float v) { return srgb8(srgb8_table(), v); }

void encode_rgba8(const float* rgba, size_t n, unsigned char* out) {
  const Srgb8Table& T = srgb8_table();
  for (size_t i = 0; i < n; ++i, rgba += 4, out += 4) {
    for (int c = 0; c < 3; ++c) out[c] = srgb8(T, rgba[c]);
    out[3] = unit_byte(rgba[3]);
  }
}

float srgb_to_linear(float v) {
  const double x = v;
  return float(x <= 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4));
}

namespace {

// srgb_to_linear of each 8-bit code c, taken at float(c) * (1.0f / 255.0f) as the decoder did.
const std::array<float, 256>& srgb8_to_linear_table() {
  static const std::array<float, 256> T = [] {
    std::array<float, 256> t{};
    for (int c = 0; c < 256; ++c) t[size_t(c)] = srgb_to_linear(float(c) * (1.0f / 255.0f));
    return t;
  }();
  return T;
}

}  // namespace

namespace {

Image from_exr(io_detail::ExrChannels exr, const fs::path& file) {
  auto find = [&](const char* name) -> const std::vector<float>* {
    const auto it = exr.channels.find(name);
    return it == exr.channels.end() ? nullptr : &it->second;
  };
  const std::vector<float>* rgb[3] = {find("R"), find("G"), find("B")};
  if (!rgb[0] || !rgb[1] || !rgb[2]) {
    // Luminance, or a lone data channel such as "Z", is shown as grey.
    const std::vector<float>* y = find("Y");
    if (!y && exr.channels.size() == 1) y = &exr.channels.begin()->second;
    if (!y) {
      std::string names;
      for (const auto& [name, plane] : exr.channels) names += (names.empty() ? "" : ", ") + name;
      fail_read("cannot read image", file,
                fmt::format("no R, G, B or Y channels to show (channels: {})", names));
    }
    rgb[0] = rgb[1] = rgb[2] = y;
  }
  const std::vector<float>* alpha = find("A");
  Image img;
  img.width = exr.width;
  img.height = exr.height;
  const size_t n = size_t(img.width) * size_t(img.height);
  img.pixels.resize(n * 4);
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) img.pixels[i * 4 + c] = (*rgb[c])[i];
    img.pixels[i * 4 + 3] = alpha ? (*alpha)[i] : 1.0f;
  }
  return img;
}

// The scanlines a Radiance HDR file holds (header, then new-style RLE or flat RGBE lines), -1
// when its layout is not recognised, kHdrCorrupt for a run of length zero. stb_image reads past
// the end of a cut file as zeros, so a truncated sky would load as a partly black one without
// this check; and its decoder never advances past a zero-length run (a 178-byte file hung it,
// found by fuzz_image).
constexpr int kHdrCorrupt = -2;
int hdr_scanlines_present(const std::vector<unsigned char>& b, int width, int height) {
  size_t at = 0;
  const auto line = [&] {
    const size_t start = at;
    while (at < b.size() && b[at] != '\n') ++at;
    std::string l(b.begin() + long(start), b.begin() + long(at));
    if (at < b.size()) ++at;
    return l;
  };
  if (line().rfind("#?", 0) != 0) return -1;
  while (at < b.size() && !line().empty()) {
  }
  if (line().find(" +X ") == std::string::npos) return -1;  // only the usual "-Y H +X W"
  for (int y = 0; y < height; ++y) {
    const bool rle = width >= 8 && width < 32768 && at + 4 <= b.size() && b[at] == 2 &&
                     b[at + 1] == 2 && ((b[at + 2] << 8) | b[at + 3]) == width;
    if (!rle) {
      if (b.size() - at < size_t(width) * 4) return y;
      at += size_t(width) * 4;
      continue;
    }
    at += 4;
    for (int c = 0; c < 4; ++c)
      for (int x = 0; x < width;) {
        if (at >= b.size()) return y;
        const int n = b[at++];
        const bool run = n > 128;
        const int count = run ? n - 128 : n;
        if (count == 0) return kHdrCorrupt;  // stb_image would loop on it forever
        const size_t bytes = run ? 1 : size_t(count);
        if (b.size() - at < bytes) return y;
        at += bytes;
        x += count;
      }
  }
  return height;
}

struct StbFree {
  void operator()(void* p) const { stbi_image_free(p); }
};

}  // namespace

Image read_image(const fs::path& file, bool srgb) {
  return decode_image(io_detail::read_file_bytes(file), srgb, file);
}

Image decode_image(const std::vector<unsigned char>& bytes, bool srgb, const fs::path& file) {
  if (io_detail::is_exr(bytes)) return from_exr(io_detail::load_exr(bytes, file), file);

  if (bytes.size() > size_t(INT_MAX)) fail_read("cannot read image", file, "file too large");
  const auto* data = bytes.data();
  const int len = int(bytes.size());
  int w = 0, h = 0, n = 0;
  Image img;
  auto stb_fail = [&] {
    const char* why = stbi_failure_reason();
    fail_read("cannot read image", file,
              fmt::format("not a readable PNG, JPEG, BMP, TGA, HDR or EXR image ({})",
                          why ? why : "unknown reason"));
  };
  auto finish = [&](auto* pixels, float scale, bool linearize) {
    img.width = w;
    img.height = h;
    img.pixels.resize(size_t(w) * size_t(h) * 4);
    // 8-bit codes through a table of the same values srgb_to_linear gives (one pow per code,
    // not per sample: it was 8 % of a 4K warp).
    if constexpr (sizeof(*pixels) == 1)
      if (linearize) {
        const std::array<float, 256>& T = srgb8_to_linear_table();
        for (size_t i = 0; i < img.pixels.size(); ++i)
          img.pixels[i] = i % 4 != 3 ? T[pixels[i]] : float(pixels[i]) * scale;
        return;
      }
    for (size_t i = 0; i < img.pixels.size(); ++i) {
      const float v = float(pixels[i]) * scale;
      img.pixels[i] = linearize && i % 4 != 3 ? srgb_to_linear(v) : v;  // alpha is linear
    }
  };
  if (!stbi_info_from_memory(data, len, &w, &h, &n)) stb_fail();
  io_detail::check_read_size(file, w, h, bytes.size());
  // Asking stb for 4 components expands grey to RGB and adds opaque alpha.
  if (stbi_is_hdr_from_memory(data, len)) {
    const int present = hdr_scanlines_present(bytes, w, h);
    if (present == kHdrCorrupt)
      fail_read("cannot read image", file,
                "the HDR file's run-length data is corrupt (a run of length zero)");
    if (present >= 0 && present < h)
      fail_read(
          "cannot read image", file,
          fmt::format("the HDR file is cut short: {} of its {} scanlines are present", present, h));
    std::unique_ptr<float, StbFree> p(stbi_loadf_from_memory(data, len, &w, &h, &n, 4));
    if (!p) stb_fail();
    finish(p.get(), 1.0f, false);
  } else if (stbi_is_16_bit_from_memory(data, len)) {
    std::unique_ptr<stbi_us, StbFree> p(stbi_load_16_from_memory(data, len, &w, &h, &n, 4));
    if (!p) stb_fail();
    finish(p.get(), 1.0f / 65535.0f, srgb);
  } else {
    std::unique_ptr<stbi_uc, StbFree> p(stbi_load_from_memory(data, len, &w, &h, &n, 4));
    if (!p) stb_fail();
    finish(p.get(), 1.0f / 255.0f, srgb);
  }
  return img;
}

std::map<std::string, std::string> read_metadata(const fs::path& file) {
  const std::vector<unsigned char> bytes = io_detail::read_file_bytes(file);
  if (io_detail::is_png(bytes)) return io_detail::png_metadata(bytes, file);
  if (io_detail::is_exr(bytes)) return io_detail::exr_metadata(bytes, file);
  fail_read("cannot read metadata", file, "metadata can be read from PNG and EXR files only");
}

std::map<std::string, std::vector<float>> read_exr_channels(const fs::path& file, int* width,
                                                            int* height) {
  const std::vector<unsigned char> bytes = io_detail::read_file_bytes(file);
  if (!io_detail::is_exr(bytes)) fail_read("cannot read EXR", file, "not an OpenEXR file");
  io_detail::ExrChannels exr = io_detail::load_exr(bytes, file);
  if (width) *width = exr.width;
  if (height) *height = exr.height;
  return std::move(exr.channels);
}

}  // namespace anamorph
