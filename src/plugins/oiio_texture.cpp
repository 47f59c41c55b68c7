// The OpenImageIO half of `anamorph warp`'s source texture (app/source_texture.h), built as a
// plugin the program loads only when it warps. Why a plugin: OpenImageIO brings about 250 shared
// libraries (its readers' codecs, DICOM's logging, ffmpeg); linked into `anamorph` they made every
// command start in 270 ms instead of 14 and started four threads before main (log4cplus), ahead
// of the signal handlers. A C interface, so nothing but plain data crosses the boundary.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/texture.h>

#include <cstddef>
#include <cstring>
#include <string>

#include "plugins/oiio_texture.h"

namespace {

struct Texture {
  OIIO::TextureSystem* ts = nullptr;
  OIIO::ustring name;
  OIIO::TextureOpt options;
  bool footprint = false;
  // The process's shared texture system, never destroyed here: OpenImageIO 2.4's
  // TextureSystem::destroy deletes through a type of another size (AddressSanitizer's
  // new-delete-type-mismatch). Each texture's own file is dropped from its cache instead.
  ~Texture() {
    if (ts) ts->invalidate(name, true);
  }
};

void say(char* error, size_t size, const std::string& text) {
  if (!error || size == 0) return;
  const size_t n = std::min(size - 1, text.size());
  std::memcpy(error, text.data(), n);
  error[n] = 0;
}

void choose_filter(OIIO::TextureOpt& o, int wrap_u, int filter) {
  o.swrap = wrap_u ? OIIO::TextureOpt::WrapPeriodic : OIIO::TextureOpt::WrapBlack;
  o.twrap = wrap_u ? OIIO::TextureOpt::WrapClamp : OIIO::TextureOpt::WrapBlack;
  o.firstchannel = 0;
  if (filter == kOiioFilterAniso) {
    o.mipmode = OIIO::TextureOpt::MipModeAniso;
    o.interpmode = OIIO::TextureOpt::InterpSmartBicubic;
  } else {
    o.mipmode = OIIO::TextureOpt::MipModeNoMIP;
    o.interpmode = filter == kOiioFilterBilinear ? OIIO::TextureOpt::InterpBilinear
                                                 : OIIO::TextureOpt::InterpBicubic;
  }
}

}  // namespace

extern "C" void* anamorph_oiio_texture_open(const float* pixels, int width, int height,
                                            int channels, const char* mip_file, int wrap_u,
                                            int filter, int threads, char* error,
                                            size_t error_size) {
  try {
    OIIO::attribute("threads", threads);
    OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::FLOAT);
    // (ImageBuf wraps the pixels without copying; make_texture only reads them.)
    const OIIO::ImageBuf buf(spec, const_cast<float*>(pixels));
    OIIO::ImageSpec config;
    config.attribute("wrapmodes", wrap_u ? "periodic,clamp" : "black,black");
    if (!OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, buf, mip_file,
                                          config)) {
      say(error, error_size, "making the MIP-mapped texture: " + OIIO::geterror());
      return nullptr;
    }
    auto* t = new Texture;
    t->ts = OIIO::TextureSystem::create(true);
    t->ts->attribute("max_memory_MB", 1024.0f);
    t->name = OIIO::ustring(mip_file);
    t->footprint = filter == kOiioFilterAniso;
    choose_filter(t->options, wrap_u, filter);
    return t;
  } catch (const std::exception& e) {
    say(error, error_size, e.what());
    return nullptr;
  }
}

extern "C" int anamorph_oiio_texture_lookup(const void* texture, const float st[2],
                                            const float footprint[4], float rgba[4], char* error,
                                            size_t error_size) {
  const auto* t = static_cast<const Texture*>(texture);
  OIIO::TextureOpt o = t->options;  // (texture() may write into its options)
  const float* f = footprint;
  const float none[4] = {0, 0, 0, 0};
  if (!t->footprint) f = none;
  if (t->ts->texture(t->name, o, st[0], st[1], f[0], f[1], f[2], f[3], 4, rgba)) return 1;
  say(error, error_size, "texture lookup: " + t->ts->geterror());
  return 0;
}

extern "C" void anamorph_oiio_texture_close(void* texture) {
  delete static_cast<Texture*>(texture);
}
