// The C interface of the OpenImageIO texture plugin (plugins/oiio_texture.cpp), which
// app/source_texture.cpp loads with dlopen when `anamorph warp` runs.
#pragma once

#include <cstddef>

inline constexpr int kOiioFilterAniso = 0, kOiioFilterBilinear = 1, kOiioFilterBicubic = 2;
inline constexpr const char* kOiioTexturePlugin = "libanamorph-oiio.so";

extern "C" {
// Makes the MIP-mapped tiled copy of `pixels` (float, `channels` per pixel, rows top down) in
// `mip_file` (on `threads` threads, 0: all cores) and opens it. Null on failure, with the reason
// in `error`.
void* anamorph_oiio_texture_open(const float* pixels, int width, int height, int channels,
                                 const char* mip_file, int wrap_u, int filter, int threads,
                                 char* error, size_t error_size);
// RGBA at st (t from the top); footprint = ds/dx, dt/dx, ds/dy, dt/dy. 0 on failure.
int anamorph_oiio_texture_lookup(const void* texture, const float st[2], const float footprint[4],
                                 float rgba[4], char* error, size_t error_size);
void anamorph_oiio_texture_close(void* texture);
}
