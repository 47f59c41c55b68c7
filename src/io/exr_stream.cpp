// EXR writing through OpenEXR (Debian's libopenexr-dev): scanlines appended as strips arrive, so
// a streamed render never holds its frame, and OpenEXR's thread pool compresses the chunks of a
// strip in parallel. Reading stays with tinyexr (io/exr.cpp), fuzzed and hardened for inputs.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <ImfThreading.h>

#include <algorithm>
#include <mutex>
#include <thread>

#include <fmt/format.h>

#include "io/image_stream.h"
#include "io/io_util.h"

namespace anamorph {

namespace fs = std::filesystem;
using io_detail::fail;

namespace {

// Attributes OpenEXR writes itself: metadata may not use their names.
constexpr const char* kReserved[] = {"channels",
                                     "compression",
                                     "dataWindow",
                                     "displayWindow",
                                     "lineOrder",
                                     "pixelAspectRatio",
                                     "screenWindowCenter",
                                     "screenWindowWidth",
                                     "tiles",
                                     "name",
                                     "type",
                                     "version",
                                     "chunkCount"};

// OpenEXR's output stream over an AtomicFile (it seeks back to fill in the offset table).
class AtomicOStream : public Imf::OStream {
 public:
  AtomicOStream(AtomicFile& f, const fs::path& name) : Imf::OStream(name.c_str()), f_(f) {}
  void write(const char c[], int n) override { f_.write(c, size_t(n)); }
  uint64_t tellp() override { return f_.tell(); }
  void seekp(uint64_t pos) override { f_.seek(pos); }

 private:
  AtomicFile& f_;
};

struct Channel {
  std::string name;
  size_t layer, component;
};

}  // namespace

struct ExrStream::Impl {
  fs::path file;
  int width, height;
  std::vector<LayerSpec> layers;
  std::vector<Channel> channels;
  AtomicFile out;
  AtomicOStream stream;
  std::unique_ptr<Imf::OutputFile> exr;
  Impl(const fs::path& f, int w, int h)
      : file(f), width(w), height(h), out(f, AtomicFile::Access::Seeks), stream(out, f) {}
};

ExrStream::ExrStream(const fs::path& file, int width, int height,
                     const std::vector<LayerSpec>& layers,
                     const std::map<std::string, std::string>& metadata) {
  if (width <= 0 || height <= 0)
    fail("cannot write image", file, fmt::format("invalid size {}x{}", width, height));
  std::vector<Channel> channels;
  for (size_t l = 0; l < layers.size(); ++l)
    for (size_t c = 0; c < layers[l].channels.size(); ++c) {
      const std::string& comp = layers[l].channels[c];
      std::string name = layers[l].name.empty() ? comp : layers[l].name + "." + comp;
      if (comp.empty() || name.size() > 255)
        fail("cannot write EXR", file,
             fmt::format("invalid channel name '{}' (1-255 characters)", name));
      channels.push_back({std::move(name), l, c});
    }
  std::sort(channels.begin(), channels.end(),
            [](const Channel& a, const Channel& b) { return a.name < b.name; });
  for (size_t i = 1; i < channels.size(); ++i)
    if (channels[i].name == channels[i - 1].name)
      fail("cannot write EXR", file, fmt::format("duplicate channel '{}'", channels[i].name));
  Imf::Header header(width, height);
  header.compression() = Imf::ZIP_COMPRESSION;  // lossless
  header.lineOrder() = Imf::INCREASING_Y;
  for (const Channel& c : channels) header.channels().insert(c.name, Imf::Channel(Imf::FLOAT));
  for (const auto& [key, value] : metadata) {
    const bool reserved = std::any_of(std::begin(kReserved), std::end(kReserved),
                                      [&key = key](const char* r) { return key == r; });
    if (key.empty() || key.size() > 255 || key.find('\0') != std::string::npos || reserved)
      fail("cannot write EXR", file,
           fmt::format("metadata key '{}' is empty, too long or a standard EXR attribute", key));
    header.insert(key, Imf::StringAttribute(value));
  }
  // Once: OpenEXR's pool compresses a strip's chunks in parallel.
  static std::once_flag pool;
  std::call_once(pool, [] {
    Imf::setGlobalThreadCount(int(std::max(1u, std::thread::hardware_concurrency())));
  });
  impl_ = std::make_unique<Impl>(file, width, height);
  impl_->layers = layers;
  impl_->channels = std::move(channels);
  try {
    impl_->exr = std::make_unique<Imf::OutputFile>(impl_->stream, header, Imf::globalThreadCount());
  } catch (const std::exception& e) {
    fail("cannot write EXR", file, e.what());
  }
}

ExrStream::~ExrStream() = default;

void ExrStream::write_rows(const std::vector<const float*>& data, int rows) {
  Impl& m = *impl_;
  if (rows <= 0 || rows_ + rows > m.height || data.size() != m.layers.size())
    fail("cannot write EXR", m.file,
         fmt::format("rows {}..{} of a {}-row image", rows_, rows_ + rows, m.height));
  Imf::FrameBuffer fb;
  for (const Channel& c : m.channels) {
    const size_t nc = m.layers[c.layer].channels.size();
    const size_t xs = nc * sizeof(float), ys = xs * size_t(m.width);
    // OpenEXR addresses pixel (x, y) at base + x * xStride + y * yStride, y in image rows.
    const char* first = reinterpret_cast<const char*>(data[c.layer] + c.component);
    char* base = const_cast<char*>(first) - ptrdiff_t(ys) * rows_;
    fb.insert(c.name, Imf::Slice(Imf::FLOAT, base, xs, ys));
  }
  try {
    m.exr->setFrameBuffer(fb);
    m.exr->writePixels(rows);
  } catch (const ImageIoError&) {
    throw;
  } catch (const std::exception& e) {
    fail("cannot write EXR", m.file, e.what());
  }
  rows_ += rows;
}

void ExrStream::commit() { commit_as(impl_->file); }

void ExrStream::commit_as(const fs::path& other) {
  Impl& m = *impl_;
  if (rows_ != m.height)
    fail("cannot write EXR", m.file, fmt::format("{} of {} rows written", rows_, m.height));
  m.exr.reset();  // writes the offset table
  m.out.commit_as(other);
}

}  // namespace anamorph
