// Helpers shared by the image I/O files (not part of the public interface).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "io/image_io.h"

namespace anamorph::io_detail {

// ImageIoError with the file named first: "<what> '<file>': <reason>".
[[noreturn]] void fail(std::string_view what, const std::filesystem::path& file,
                       std::string_view reason);
// The same as an ImageReadError: the input is at fault, not the machine.
[[noreturn]] void fail_read(std::string_view what, const std::filesystem::path& file,
                            std::string_view reason);

// The temporary a write of `name` goes through, beside it: ".NAME.tmp-PID-RANDOM" (hex).
std::string temporary_name(const std::string& name, uint64_t random);
// Removes, in the folder `dirfd`, temporaries of `name` whose process is no longer running (one
// killed in the middle of a write).
void remove_stale_temporaries_at(int dirfd, const std::string& name);

// The whole file; throws ImageIoError naming the file (and strerror) when it cannot be read.
std::vector<unsigned char> read_file_bytes(const std::filesystem::path& file);

// The largest image read, in pixels: 2^27, e.g. a 16384 x 8192 planet map (2 GiB as linear float
// RGBA before its mip levels). A few bytes of compressed data can claim far more; the size is
// checked from the header before any pixel is decoded.
inline constexpr uint64_t kMaxReadPixels = uint64_t(1) << 27;
// Beyond kMaxReadPixels, an image must also fit its file: no format anamorph reads packs more
// than about 8,256 pixels into a byte (deflate's 1032:1 on 1-bit PNG rows), so a file declaring
// more than kMaxPixelsPerByte per byte of itself (and more than kSmallImagePixels) is damaged or
// a decompression bomb, refused before decoding (an 86-byte file would otherwise decode to
// 1.6 GB).
inline constexpr uint64_t kMaxPixelsPerByte = 8300;
inline constexpr uint64_t kSmallImagePixels = uint64_t(1) << 22;
void check_read_size(const std::filesystem::path& file, int64_t width, int64_t height,
                     size_t file_bytes);

inline constexpr unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
bool is_png(const std::vector<unsigned char>& bytes);

// A value in [0, 1] as an 8-bit code, rounded; NaN and negatives give 0, values above 1 give 255.
unsigned char unit_to_byte(float v);
bool is_exr(const std::vector<unsigned char>& bytes);

// Size and per-layer value counts of an image about to be written; throws naming the file.
void check_output(const OutputImage& img, const std::filesystem::path& file);

// PNG text chunks (tEXt, zTXt, iTXt) as UTF-8; `file` only names errors.
std::map<std::string, std::string> png_metadata(const std::vector<unsigned char>& bytes,
                                                const std::filesystem::path& file);

// Every channel of a single-part EXR, converted to float.
struct ExrChannels {
  int width = 0, height = 0;
  std::map<std::string, std::vector<float>> channels;
};
ExrChannels load_exr(const std::vector<unsigned char>& bytes, const std::filesystem::path& file);
std::map<std::string, std::string> exr_metadata(const std::vector<unsigned char>& bytes,
                                                const std::filesystem::path& file);

}  // namespace anamorph::io_detail
