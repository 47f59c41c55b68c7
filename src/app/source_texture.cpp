#include "app/source_texture.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/texture.h>
#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <stdexcept>

#include "io/temporary_files.h"

namespace anamorph::app {

namespace fs = std::filesystem;

struct SourceTexture::State {
  fs::path file;
  int slot = -1;
  OIIO::TextureSystem* ts = nullptr;
  OIIO::ustring name;
  OIIO::TextureOpt options;
  TextureFilter filter = TextureFilter::Aniso;
  ~State() {
    if (ts) OIIO::TextureSystem::destroy(ts);
    std::error_code ignored;
    if (!file.empty()) fs::remove(file, ignored);
    if (slot >= 0) unregister_temporary(slot);
  }
};

namespace {

fs::path temporary_texture() {
  static std::atomic<int> counter{0};
  return fs::temp_directory_path() /
         fmt::format("anamorph-warp-{}-{}.tx.exr", ::getpid(), counter.fetch_add(1));
}

}  // namespace

SourceTexture::SourceTexture(const Image& image, bool wrap_u, TextureFilter filter)
    : state_(std::make_unique<State>()) {
  State& s = *state_;
  s.filter = filter;
  OIIO::ImageSpec spec(image.width, image.height, image.channels, OIIO::TypeDesc::FLOAT);
  // (ImageBuf wraps the pixels without copying; make_texture only reads them.)
  const OIIO::ImageBuf buf(spec, const_cast<float*>(image.pixels.data()));
  s.file = temporary_texture();
  s.slot = register_temporary(s.file);
  OIIO::ImageSpec config;
  config.attribute("wrapmodes", wrap_u ? "periodic,clamp" : "black,black");
  if (!OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, buf, s.file.string(),
                                        config))
    throw std::runtime_error("making the MIP-mapped texture: " + OIIO::geterror());
  s.ts = OIIO::TextureSystem::create(false);
  s.ts->attribute("max_memory_MB", 1024.0f);
  s.name = OIIO::ustring(s.file.string());
  OIIO::TextureOpt& o = s.options;
  o.swrap = wrap_u ? OIIO::TextureOpt::WrapPeriodic : OIIO::TextureOpt::WrapBlack;
  o.twrap = wrap_u ? OIIO::TextureOpt::WrapClamp : OIIO::TextureOpt::WrapBlack;
  o.firstchannel = 0;
  if (filter == TextureFilter::Aniso) {
    o.mipmode = OIIO::TextureOpt::MipModeAniso;
    o.interpmode = OIIO::TextureOpt::InterpSmartBicubic;
  } else {
    o.mipmode = OIIO::TextureOpt::MipModeNoMIP;
    o.interpmode = filter == TextureFilter::Bilinear ? OIIO::TextureOpt::InterpBilinear
                                                     : OIIO::TextureOpt::InterpBicubic;
  }
}

SourceTexture::~SourceTexture() = default;

void SourceTexture::lookup(Vec2 uv, Vec2 duv_dx, Vec2 duv_dy, float rgba[4]) const {
  OIIO::TextureOpt o = state_->options;  // (texture() may write into its options)
  const bool footprint = state_->filter == TextureFilter::Aniso;
  if (!state_->ts->texture(state_->name, o, float(uv.x), float(uv.y),
                           footprint ? float(duv_dx.x) : 0.0f, footprint ? float(duv_dx.y) : 0.0f,
                           footprint ? float(duv_dy.x) : 0.0f, footprint ? float(duv_dy.y) : 0.0f,
                           4, rgba))
    throw std::runtime_error("texture lookup: " + state_->ts->geterror());
}

}  // namespace anamorph::app
