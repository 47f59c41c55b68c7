// The "aniso" and "bicubic" warp textures (warp/warp_texture.h) over the OpenImageIO plugin
// (plugins/oiio_texture.h), loaded on first use: beside the program, else where the build made it.
// The MIP-mapped copy is a temporary file this side owns (registered, so an interrupted warp
// removes it too).
#include "warp/warp_texture.h"

#include <dlfcn.h>
#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <stdexcept>
#include <vector>

#include "io/temporary_files.h"
#include "plugins/oiio_texture.h"

namespace anamorph {

namespace fs = std::filesystem;

namespace {

struct Plugin {
  decltype(&anamorph_oiio_texture_open) open = nullptr;
  decltype(&anamorph_oiio_texture_lookup) lookup = nullptr;
  decltype(&anamorph_oiio_texture_close) close = nullptr;
};

std::vector<fs::path> plugin_places() {
  std::vector<fs::path> places;
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) places.push_back(self.parent_path() / kOiioTexturePlugin);
#ifdef ANAMORPH_OIIO_PLUGIN_BUILT
  places.emplace_back(ANAMORPH_OIIO_PLUGIN_BUILT);
#endif
  return places;
}

// The plugin's functions; throws naming the places looked in when it cannot be loaded.
const Plugin& plugin() {
  static const Plugin p = [] {
    std::string tried;
    for (const fs::path& place : plugin_places()) {
      void* h = ::dlopen(place.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (!h) {
        tried += fmt::format("\n  {}: {}", place.string(), ::dlerror());
        continue;
      }
      Plugin q;
      q.open = reinterpret_cast<decltype(q.open)>(::dlsym(h, "anamorph_oiio_texture_open"));
      q.lookup = reinterpret_cast<decltype(q.lookup)>(::dlsym(h, "anamorph_oiio_texture_lookup"));
      q.close = reinterpret_cast<decltype(q.close)>(::dlsym(h, "anamorph_oiio_texture_close"));
      if (q.open && q.lookup && q.close) return q;
      tried += fmt::format("\n  {}: not anamorph's texture plugin", place.string());
    }
    throw std::runtime_error(fmt::format(
        "warp filters through OpenImageIO in {}, which could not be loaded (install it beside "
        "anamorph, and libopenimageio2.4):{}",
        kOiioTexturePlugin, tried));
  }();
  return p;
}

fs::path temporary_texture() {
  static std::atomic<int> counter{0};
  return fs::temp_directory_path() /
         fmt::format("anamorph-warp-{}-{}.tx.exr", ::getpid(), counter.fetch_add(1));
}

class OiioTexture final : public WarpTexture {
 public:
  OiioTexture(const Image& image, bool wrap_u, TextureFilter filter, int threads) {
    const Plugin& p = plugin();
    file_ = temporary_texture();
    slot_ = register_temporary(file_);
    const int mode = filter == TextureFilter::Aniso ? kOiioFilterAniso : kOiioFilterBicubic;
    char error[512] = "";
    texture_ = p.open(image.pixels.data(), image.width, image.height, image.channels, file_.c_str(),
                      wrap_u, mode, threads, error, sizeof error);
    if (!texture_) {
      drop();
      throw std::runtime_error(error);
    }
  }
  ~OiioTexture() override { drop(); }
  OiioTexture(const OiioTexture&) = delete;
  OiioTexture& operator=(const OiioTexture&) = delete;

  void lookup(Vec2 uv, Vec2 duv_dx, Vec2 duv_dy, float rgba[4]) const override {
    const float st[2] = {float(uv.x), float(uv.y)};
    const float footprint[4] = {float(duv_dx.x), float(duv_dx.y), float(duv_dy.x), float(duv_dy.y)};
    char error[512] = "";
    if (!plugin().lookup(texture_, st, footprint, rgba, error, sizeof error))
      throw std::runtime_error(error);
  }

 private:
  void drop() {
    if (texture_) plugin().close(texture_);
    texture_ = nullptr;
    std::error_code ignored;
    if (!file_.empty()) fs::remove(file_, ignored);
    if (slot_ >= 0) unregister_temporary(slot_);
    slot_ = -1;
  }
  fs::path file_;
  int slot_ = -1;
  void* texture_ = nullptr;
};

}  // namespace

std::unique_ptr<WarpTexture> make_oiio_texture(const Image& image, bool wrap_u,
                                               TextureFilter filter, int threads) {
  return std::make_unique<OiioTexture>(image, wrap_u, filter, threads);
}

}  // namespace anamorph
