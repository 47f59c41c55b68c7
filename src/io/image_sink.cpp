#include "io/image_sink.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <deque>
#include <mutex>
#include <stdexcept>

#include "io/image_io.h"
#include "io/io_util.h"
#include "math/user_text.h"

namespace anamorph {

namespace fs = std::filesystem;

#define ANAMORPH_SINK(kind, file) extern const SinkKind kind;
#include "io/sink_list.h"
#undef ANAMORPH_SINK

namespace {

std::mutex& registry_mutex() {
  static std::mutex mu;
  return mu;
}

// Kinds registered at run time (a deque: their addresses stay put).
std::deque<SinkKind>& registered() {
  static std::deque<SinkKind> kinds;
  return kinds;
}

std::string lower_extension(const fs::path& file) {
  std::string ext = file.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

bool takes_every_layer(const SinkKind& kind, const std::vector<LayerSpec>& layers) {
  const std::vector<LayerRequest> taken = kind.takes(layers);
  return std::all_of(layers.begin(), layers.end(), [&](const LayerSpec& l) {
    return std::any_of(taken.begin(), taken.end(),
                       [&](const LayerRequest& r) { return r.layer == l.name; });
  });
}

const LayerSpec& layer_named(const std::vector<LayerSpec>& layers, const std::string& name) {
  for (const LayerSpec& l : layers)
    if (l.name == name) return l;
  throw std::invalid_argument(
      fmt::format("a sink asks for a layer '{}' the render does not have", printable(name)));
}

}  // namespace

const char* encoding_name(Encoding e) { return e == Encoding::Srgb8 ? "srgb8" : "float32"; }

size_t values_per_pixel(const LayerSpec& layer, Encoding encoding) {
  return encoding == Encoding::Srgb8 ? 4 : layer.channels.size();
}

size_t bytes_per_value(Encoding encoding) { return encoding == Encoding::Srgb8 ? 1 : 4; }

std::vector<const SinkKind*> sink_kinds() {
  std::vector<const SinkKind*> kinds = {
#define ANAMORPH_SINK(kind, file) &kind,
#include "io/sink_list.h"
#undef ANAMORPH_SINK
  };
  const std::lock_guard<std::mutex> lock(registry_mutex());
  for (const SinkKind& k : registered()) kinds.push_back(&k);
  return kinds;
}

void register_sink_kind(const SinkKind& kind) {
  for (const SinkKind* k : sink_kinds())
    for (const std::string& e : k->extensions)
      if (std::find(kind.extensions.begin(), kind.extensions.end(), e) != kind.extensions.end())
        throw std::logic_error(
            fmt::format("sink '{}': the extension {} is the '{}' sink's", kind.name, e, k->name));
  const std::lock_guard<std::mutex> lock(registry_mutex());
  registered().push_back(kind);
}

const SinkKind* find_sink_kind(const fs::path& file) {
  const std::string ext = lower_extension(file);
  const std::vector<const SinkKind*> kinds = sink_kinds();
  if (ext.empty() && AtomicFile::writes_directly(file)) return kinds.front();
  for (const SinkKind* k : kinds)
    if (std::find(k->extensions.begin(), k->extensions.end(), ext) != k->extensions.end()) return k;
  return nullptr;
}

const SinkKind* find_sink_kind_named(std::string_view name) {
  for (const SinkKind* k : sink_kinds())
    if (k->name == name) return k;
  return nullptr;
}

std::string unsupported_extension(const fs::path& file) {
  std::string supported;
  for (const SinkKind* k : sink_kinds())
    for (const std::string& e : k->extensions) supported += (supported.empty() ? "" : ", ") + e;
  const std::string ext = file.extension().string();
  return ext.empty()
             ? fmt::format("no extension to choose the format by (supported: {})", supported)
             : fmt::format("unsupported extension '{}' (supported: {})", printable(ext), supported);
}

const SinkKind& sink_kind(const fs::path& file) {
  if (const SinkKind* k = find_sink_kind(file)) return *k;
  io_detail::fail("cannot write image", file, unsupported_extension(file));
}

std::vector<fs::path> output_files(const fs::path& file, const std::vector<LayerSpec>& layers) {
  std::vector<fs::path> files{file};
  if (takes_every_layer(sink_kind(file), layers)) return files;
  for (const SinkKind* k : sink_kinds())
    if (!k->extensions.empty() && takes_every_layer(*k, layers)) {
      files.push_back(fs::path(file).replace_extension(k->extensions.front()));
      break;
    }
  return files;
}

std::unique_ptr<ImageSink> make_file_sink(const SinkSpec& spec) {
  return sink_kind(spec.file).make(spec);
}

size_t strip_bytes_per_pixel(const std::vector<fs::path>& files,
                             const std::vector<LayerSpec>& layers) {
  size_t bytes = 0;
  for (const fs::path& f : files) {
    const SinkKind& kind = sink_kind(f);
    size_t planes = 0;
    for (const LayerRequest& r : kind.takes(layers))
      planes +=
          values_per_pixel(layer_named(layers, r.layer), r.encoding) * bytes_per_value(r.encoding);
    bytes += planes * kind.strip_copies;
  }
  return bytes;
}

}  // namespace anamorph
