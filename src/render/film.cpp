#include "render/film.h"

#include <limits>

#include "math/parallel.h"

namespace anamorph {

Film::Film(int width, int height, std::vector<Aov> aovs, int tile_size)
    : grid_(width, height, tile_size), aovs_(std::move(aovs)), tiles_(grid_.count()) {}

TileBuffer& Film::tile(size_t index) {
  if (!tiles_[index]) tiles_[index] = std::make_unique<TileBuffer>(grid_.rect(index), aovs_);
  return *tiles_[index];
}

void Film::clear() {
  for (auto& t : tiles_) t.reset();
}

const PixelSum* Film::sum(int x, int y) const {
  const TileBuffer* t = tiles_[grid_.index_of(x, y)].get();
  return t ? &t->at(x, y) : nullptr;
}

uint32_t Film::samples(int x, int y) const {
  const PixelSum* p = sum(x, y);
  return p ? p->spp : 0;
}

double Film::standard_error(int x, int y) const {
  const TileBuffer* t = tiles_[grid_.index_of(x, y)].get();
  return t ? t->standard_error(x, y) : kInf;
}

Color Film::pixel(int x, int y) const {
  const PixelSum* p = sum(x, y);
  if (!p || p->n == 0) return {};
  return Color{p->rgb[0], p->rgb[1], p->rgb[2]} / double(p->n);
}

double Film::alpha(int x, int y) const {
  const PixelSum* p = sum(x, y);
  return p && p->n ? double(p->alpha) / p->n : 0.0;
}

std::vector<unsigned char> Film::output_rgba8() const {
  std::vector<unsigned char> out(size_t(width()) * size_t(height()) * 4);
  const OutputImage img = output();  // small frames only: the streamed path never comes here
  const std::vector<float>& f = img.layers[0].data;
  parallel_for_each(0, height(), [&](int y) {
    for (size_t i = size_t(y) * size_t(width()); i < size_t(y + 1) * size_t(width()); ++i)
      encode_rgba8(&f[i * 4], &out[i * 4]);
  });
  return out;
}

OutputImage Film::output() const {
  OutputImage out;
  out.width = width();
  out.height = height();
  const size_t n = size_t(width()) * size_t(height()), nf = aov_floats(aovs_);
  ImageLayer beauty;
  beauty.channels = {"R", "G", "B", "A"};
  beauty.data.assign(n * 4, 0.0f);
  std::vector<float> aov(n * nf);
  // A tile never rendered is transparent, and its AOVs say "nothing here".
  const TileBuffer empty(TileRect{0, 0, 1, 1}, aovs_);
  std::vector<float> none(nf);
  empty.aov_values(0, 0, none.data());
  parallel_for_each(0, int(grid_.count()), [&](int ti) {
    const TileBuffer* t = tiles_[size_t(ti)].get();
    const TileRect r = grid_.rect(size_t(ti));
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x) {
        const size_t i = size_t(y) * size_t(width()) + size_t(x);
        if (t) t->beauty_rgba(x, y, &beauty.data[i * 4]);
        if (nf == 0) continue;
        if (t)
          t->aov_values(x, y, &aov[i * nf]);
        else
          std::copy(none.begin(), none.end(), aov.begin() + ptrdiff_t(i * nf));
      }
  });
  out.layers.push_back(std::move(beauty));
  size_t off = 0;
  for (Aov k : aovs_) {
    const AovInfo& info = aov_info(k);
    ImageLayer l;
    l.name = info.name;
    l.channels = info.channels;
    const size_t nc = info.channels.size();
    l.data.resize(n * nc);
    for (size_t i = 0; i < n; ++i)
      for (size_t c = 0; c < nc; ++c) l.data[i * nc + c] = aov[i * nf + off + c];
    off += nc;
    out.layers.push_back(std::move(l));
  }
  return out;
}

}  // namespace anamorph
