// Output sinks: where a rendered image goes, strip by strip from the top. A sink says which of the
// render's layers it takes and in which encoding (8-bit sRGB RGBA, 32-bit float); the renderer
// resolves each tile to exactly those and never names a file format (render/frame_output.h
// gathers tiles into strips and hands them to the sinks). Sinks that write files are kinds,
// chosen by the file's extension here and nowhere else; the built-in ones are listed one line
// each in io/sink_list.h. Other sinks (the editor's preview) are made by their owner.
#pragma once

#include <any>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace anamorph {

enum class Encoding : uint8_t {
  // A colour layer (RGB or RGBA; alpha 1 when absent) as a PNG stores it: 8-bit sRGB-encoded
  // colour and linear alpha, always 4 values a pixel (io/image_io.h: encode_rgba8).
  Srgb8,
  Float32,  // the layer's channels as 32-bit floats, linear
};
const char* encoding_name(Encoding e);  // "srgb8", "float32"

// One layer of an image with its channels' names. The render's layers are the beauty RGBA, named
// "" (its channels bare in an EXR: "R"), then each AOV's ("albedo": "albedo.R", ...).
struct LayerSpec {
  std::string name;
  std::vector<std::string> channels;
};

// A layer in an encoding: what a sink takes, and what a resolved tile or a strip holds.
struct LayerRequest {
  std::string layer;  // a LayerSpec's name ("" the beauty)
  Encoding encoding = Encoding::Float32;
  bool operator==(const LayerRequest&) const = default;
};
// Values a pixel of `layer` has in `encoding` (Srgb8: 4).
size_t values_per_pixel(const LayerSpec& layer, Encoding encoding);
size_t bytes_per_value(Encoding encoding);

// One layer's values in one encoding over a rectangle of pixels, row by row, channels
// interleaved; only the vector of its encoding is used.
struct Plane {
  std::vector<unsigned char> u8;  // Srgb8
  std::vector<float> f32;         // Float32
  bool operator==(const Plane&) const = default;
};

// Rows of the image for one sink: planes[i] holds its requests()[i] over the strip's rows (the
// image's full width). `prepared` is what the sink's prepare() made of them.
struct Strip {
  int rows = 0;
  std::vector<Plane> planes;
  std::any prepared;
};

// What a sink writes: its file (none for a sink that writes no file), the image's size, the
// layers the render has, and the metadata (version, command line, scene, camera).
struct SinkSpec {
  std::filesystem::path file;
  int width = 0, height = 0;
  std::vector<LayerSpec> layers;
  std::map<std::string, std::string> metadata;
};

class ImageSink {
 public:
  virtual ~ImageSink() = default;
  // The layers and encodings it takes, in the order of each strip's planes; fixed for its life.
  virtual const std::vector<LayerRequest>& requests() const = 0;
  // A complete strip, on any thread and in any order, before append(): the work that needs no
  // order (PNG filters and deflates its band here) and the planes it no longer needs freed.
  virtual void prepare(Strip& strip) const = 0;
  // The next strip from the top; one caller at a time. One strip may be appended several times in
  // a row (an empty one, for the rows of tiles that never came).
  virtual void append(const Strip& strip) = 0;
  // Every row appended: the image appears under its name, or under `as` (an interrupted render's
  // image so far, beside it). Nothing appears when the sink is destroyed without either.
  virtual void commit() = 0;
  virtual void commit_as(const std::filesystem::path& as) = 0;
};

// A sink that writes a file, chosen by the file's extension.
struct SinkKind {
  std::string name;                     // "png": in messages and checkpoint identities
  std::vector<std::string> extensions;  // lower case with the dot: {".png"}
  // What it takes of a render with `layers` (layers[0] the beauty). A kind that does not take
  // every layer leaves the rest to output_files()'s second file.
  std::vector<LayerRequest> (*takes)(const std::vector<LayerSpec>& layers) = nullptr;
  std::unique_ptr<ImageSink> (*make)(const SinkSpec& spec) = nullptr;
  // How many copies of a strip's planes it holds at most while it waits to be appended (PNG: the
  // strip and its deflated band, 2), for memory estimates.
  unsigned strip_copies = 1;
  // Its media type (HTTP's Content-Type, for the editor's downloads) and a name for people.
  const char* media_type = "application/octet-stream";
  const char* label = "";
};
// The kind named `name` ("png"); null when none is.
const SinkKind* find_sink_kind_named(std::string_view name);

// Every kind: the built-in ones (io/sink_list.h) in their order, then any registered since.
std::vector<const SinkKind*> sink_kinds();
// Adds a kind (a test's, a plugin's). An extension another kind has already: std::logic_error.
void register_sink_kind(const SinkKind& kind);
// The kind that writes `file`, by its extension in any case; null when none does. A name without
// an extension that is written directly (a device, a FIFO, the standard output:
// AtomicFile::writes_directly) gets the first kind (PNG).
const SinkKind* find_sink_kind(const std::filesystem::path& file);
// Why no kind writes `file`: "unsupported extension '.tif' (supported: .png, .exr)" (the one
// message, wherever a name is checked).
std::string unsupported_extension(const std::filesystem::path& file);
// find_sink_kind, or ImageIoError "cannot write image 'FILE': unsupported extension ...".
const SinkKind& sink_kind(const std::filesystem::path& file);
// The files an output named `file` becomes for a render with `layers`: the file itself, and when
// its kind does not take every layer, the same name with the extension of the first kind that
// does (out.png with AOVs: out.png and out.exr). Throws as sink_kind().
std::vector<std::filesystem::path> output_files(const std::filesystem::path& file,
                                                const std::vector<LayerSpec>& layers);
// The sink for `spec.file`, by its kind.
std::unique_ptr<ImageSink> make_file_sink(const SinkSpec& spec);
// Bytes a pixel of a strip costs the sinks of these files, their copies included.
size_t strip_bytes_per_pixel(const std::vector<std::filesystem::path>& files,
                             const std::vector<LayerSpec>& layers);

}  // namespace anamorph
