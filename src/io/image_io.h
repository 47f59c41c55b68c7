// Image files. Reading: PNG/JPEG/BMP/TGA/HDR (stb) and EXR (tinyexr) into linear float RGBA.
// Writing: PNG (8-bit sRGB + alpha, metadata in tEXt chunks) and EXR (32-bit float, linear,
// several layers, metadata as string attributes). Every write is atomic: a temporary file in the
// target directory, then rename(2), so a failed or interrupted write never leaves a truncated
// file where a good one was.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/image.h"

namespace anamorph {

struct ImageIoError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// An image that cannot be read: missing, unreadable, corrupt, too large (bad input, exit 2);
// other ImageIoErrors are failures to write (exit 1).
struct ImageReadError : ImageIoError {
  using ImageIoError::ImageIoError;
};

// 8-bit sources are treated as sRGB-encoded and linearized unless `srgb` is false (data maps
// such as normal or metallic-roughness textures). Returns 4 channels (alpha 1 when absent).
Image read_image(const std::filesystem::path& file, bool srgb = true);
// read_image of bytes already in memory (an image embedded in a model); `name` for messages.
Image decode_image(const std::vector<unsigned char>& bytes, bool srgb,
                   const std::filesystem::path& name);

// One named layer of an EXR: channel names are "<layer>.<c>" (or bare "<c>" for the unnamed
// beauty layer), e.g. "albedo.R". `channels` names the components, e.g. {"R","G","B","A"}.
struct ImageLayer {
  std::string name;                   // "" for the main RGBA layer
  std::vector<std::string> channels;  // component names
  std::vector<float> data;            // width * height * channels.size(), interleaved
};

struct OutputImage {
  int width = 0, height = 0;
  std::vector<ImageLayer> layers;               // layers[0] is the beauty RGBA
  std::map<std::string, std::string> metadata;  // e.g. "anamorph.camera", "anamorph.command"
};

// An 8-bit RGBA image as a PNG holds it: sRGB-encoded colour, straight linear alpha.
struct Rgba8Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgba;              // width * height * 4
  std::map<std::string, std::string> metadata;  // as OutputImage
};
// One RGBA pixel (straight colour, linear) as a PNG stores it.
void encode_rgba8(const float* rgba, unsigned char* out);
// `n` pixels at once, the same bytes (one call per row: the table is looked up once).
void encode_rgba8(const float* rgba, size_t n, unsigned char* out);

// Through the sink the file's extension chooses (io/image_sink.h): PNG takes only layers[0], EXR
// every layer. An extension no sink writes: ImageIoError listing the ones that are.
void write_image(const std::filesystem::path& file, const OutputImage& img);
void write_png(const std::filesystem::path& file, const OutputImage& img);
// The same file from pixels already in 8 bits (a render's beauty without a float layer first).
void write_png(const std::filesystem::path& file, const Rgba8Image& img);
void write_exr(const std::filesystem::path& file, const OutputImage& img);

// Read back metadata (PNG tEXt / EXR string attributes), for tests and `anamorph info`.
std::map<std::string, std::string> read_metadata(const std::filesystem::path& file);
// Read every EXR channel by full name ("R", "albedo.R", ...), for tests.
std::map<std::string, std::vector<float>> read_exr_channels(const std::filesystem::path& file,
                                                            int* width, int* height);

// A file written in pieces and made visible all at once: a temporary file beside the target,
// renamed over it by commit(). Destroyed without commit(), the target is untouched and the
// temporary removed. A symbolic link as the target is followed; an existing device, FIFO or
// socket, or the file that standard output or error is, is written directly; a read-only file
// is refused; temporaries left by killed processes are removed. Throws ImageIoError naming the
// file.
class AtomicFile {
 public:
  // Whether the format seeks back (tell/seek): then a target that cannot seek, a pipe, is fed
  // from a spool file at commit() instead of as the bytes come.
  enum class Access { Sequential, Seeks };
  explicit AtomicFile(const std::filesystem::path& file, Access access = Access::Sequential);
  // Whether `file` is written directly rather than replaced: an existing device, FIFO or socket,
  // or the file the process's standard output or error is.
  static bool writes_directly(const std::filesystem::path& file);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  void write(const void* bytes, size_t size);
  // Position in the file and moving it (formats that fill in an offset table at the end).
  uint64_t tell() const;
  void seek(uint64_t offset);
  void commit();
  // The file renamed to `other` (in the same directory as the target) instead.
  void commit_as(const std::filesystem::path& other);

 private:
  void open_direct(const std::filesystem::path& file, int stream, Access access);
  void copy_spool();
  std::filesystem::path target_, dir_, tmp_;
  int fd_ = -1;    // where write() goes: the temporary, the direct target or its spool
  int sink_ = -1;  // a direct target
  int slot_ = -1;  // the temporary's registration (io/temporary_files.h)
  bool direct_ = false, committed_ = false;
};

// Writes `bytes` to `file` through an AtomicFile. Throws ImageIoError.
void write_file_atomic(const std::filesystem::path& file, const void* bytes, size_t size);

// sRGB transfer functions.
float linear_to_srgb(float v);
float srgb_to_linear(float v);
// The 8-bit sRGB code of a linear value, clamped to [0, 1] (NaN and negatives give 0): exactly
// round(255 * linear_to_srgb(clamp(v))), by a search in the 255 linear thresholds between codes
// instead of a pow per value.
unsigned char linear_to_srgb8(float v);

}  // namespace anamorph
