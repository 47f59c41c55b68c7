#include "render/film.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "math/parallel.h"

namespace anamorph {

const std::vector<AovInfo>& aov_table() {
  static const std::vector<AovInfo> t = {
      {Aov::Albedo, "albedo", {"R", "G", "B"}},
      {Aov::Normal, "normal", {"X", "Y", "Z"}},
      {Aov::Depth, "depth", {"Z"}},
      {Aov::Position, "position", {"X", "Y", "Z"}},
      {Aov::Id, "id", {"id"}},
      {Aov::Uv, "uv", {"U", "V"}},
      {Aov::Spp, "spp", {"N"}},
  };
  return t;
}

const AovInfo& aov_info(Aov a) {
  for (const auto& i : aov_table())
    if (i.aov == a) return i;
  throw std::logic_error("unknown AOV");
}

std::vector<Aov> parse_aovs(const std::string& list) {
  std::vector<Aov> out;
  size_t s = 0;
  while (s <= list.size() && !list.empty()) {
    size_t e = list.find(',', s);
    if (e == std::string::npos) e = list.size();
    const std::string name = list.substr(s, e - s);
    bool found = false;
    for (const auto& i : aov_table())
      if (name == i.name) {
        out.push_back(i.aov);
        found = true;
      }
    if (!found) {
      std::string valid;
      for (const auto& i : aov_table()) valid += std::string(valid.empty() ? "" : ", ") + i.name;
      throw std::invalid_argument("unknown AOV '" + name + "' (valid: " + valid + ")");
    }
    s = e + 1;
  }
  return out;
}

Film::Film(int width, int height, std::vector<Aov> aovs)
    : w_(width), h_(height), aovs_(std::move(aovs)), pixels_(size_t(width) * height) {
  for (Aov a : aovs_) aov_floats_ += aov_info(a).channels.size();
  aov_.assign(pixels_.size() * aov_floats_, 0.0);
  clear();
}

void Film::reset(int x, int y) {
  px(x, y) = Pixel{};
  clear_aovs(x, y);
}

void Film::clear_aovs(int x, int y) {
  if (aov_floats_ > 0)
    std::fill_n(aov_.begin() + long((size_t(y) * w_ + x) * aov_floats_), aov_floats_, 0.0);
}

void Film::clear() {
  parallel_for_each(0, h_, [&](int y) {
    const auto row = pixels_.begin() + ptrdiff_t(y) * w_;
    std::fill(row, row + w_, Pixel{});
  });
  std::fill(aov_.begin(), aov_.end(), 0.0);
}

void Film::set(int x, int y, const Color& L, double alpha, uint32_t spp, const AovSample& a) {
  Pixel& p = px(x, y);
  p = Pixel{};
  p.rgb[0] = L.x;
  p.rgb[1] = L.y;
  p.rgb[2] = L.z;
  p.alpha = alpha;
  p.n = 1;
  p.spp = spp;
  clear_aovs(x, y);
  add_aovs(x, y, a, true);
}

double Film::standard_error(int x, int y) const {
  const Pixel& p = px(x, y);
  if (p.n < 2) return kInf;
  const double n = p.n;
  const double mean = luminance({p.rgb[0], p.rgb[1], p.rgb[2]}) / n;
  const double var = std::max(0.0, (p.lum2 - n * mean * mean) / (n - 1));
  return std::sqrt(var / n);
}

void Film::add_aovs(int x, int y, const AovSample& a, bool first_sample) {
  Pixel& p = px(x, y);
  if (aov_floats_ == 0 || !a.hit) return;
  p.hits++;
  double* v = &aov_[(size_t(y) * w_ + x) * aov_floats_];
  for (Aov k : aovs_) {
    switch (k) {
      case Aov::Albedo:
        v[0] += a.albedo.x, v[1] += a.albedo.y, v[2] += a.albedo.z, v += 3;
        break;
      case Aov::Normal:
        v[0] += a.normal.x, v[1] += a.normal.y, v[2] += a.normal.z, v += 3;
        break;
      case Aov::Position:
        v[0] += a.position.x, v[1] += a.position.y, v[2] += a.position.z, v += 3;
        break;
      case Aov::Depth:
        v[0] += a.depth, v += 1;
        break;
      case Aov::Id:
        // An average of ids means nothing: keep the id seen by the first sample.
        if (first_sample) v[0] = a.id + 1;  // stored +1 so 0 means "nothing"
        v += 1;
        break;
      case Aov::Uv:
        v[0] += a.uv.x, v[1] += a.uv.y, v += 2;
        break;
      case Aov::Spp:
        v += 1;
        break;  // read from the pixel's sample count at output
    }
  }
}

Color Film::pixel(int x, int y) const {
  const Pixel& p = px(x, y);
  if (p.n == 0) return {};
  return Color{p.rgb[0], p.rgb[1], p.rgb[2]} / double(p.n);
}

double Film::alpha(int x, int y) const {
  const Pixel& p = px(x, y);
  return p.n ? p.alpha / p.n : 0.0;
}

void Film::beauty_rgba(const Pixel& p, float* out) {
  const double n = p.n ? double(p.n) : 1.0;
  const double a = p.alpha / n;
  // Straight (un-premultiplied) colour: no-ray samples are transparent, not black.
  const double inv = p.alpha > 0 ? 1.0 / p.alpha : 0.0;
  for (int c = 0; c < 3; ++c) out[c] = float(p.rgb[c] * inv);
  out[3] = float(a);
}

std::vector<unsigned char> Film::output_rgba8() const {
  std::vector<unsigned char> out(pixels_.size() * 4);
  parallel_for_each(0, h_, [&](int y) {
    for (size_t i = size_t(y) * size_t(w_); i < size_t(y + 1) * size_t(w_); ++i) {
      float px[4];
      beauty_rgba(pixels_[i], px);
      encode_rgba8(px, &out[i * 4]);
    }
  });
  return out;
}

OutputImage Film::output() const {
  OutputImage out;
  out.width = w_;
  out.height = h_;
  ImageLayer beauty;
  beauty.channels = {"R", "G", "B", "A"};
  beauty.data.resize(pixels_.size() * 4);
  // Rows in parallel (first touch of the new layer included): a visible share of a quick render.
  const auto rows = [this](auto&& per_pixel) {
    parallel_for_each(0, h_, [&](int y) {
      for (size_t i = size_t(y) * size_t(w_); i < size_t(y + 1) * size_t(w_); ++i) per_pixel(i);
    });
  };
  rows([&](size_t i) { beauty_rgba(pixels_[i], &beauty.data[i * 4]); });
  out.layers.push_back(std::move(beauty));
  size_t off = 0;
  for (Aov k : aovs_) {
    const AovInfo& info = aov_info(k);
    ImageLayer l;
    l.name = info.name;
    l.channels = info.channels;
    const size_t nc = info.channels.size();
    l.data.resize(pixels_.size() * nc);
    rows([&](size_t i) {
      const Pixel& p = pixels_[i];
      const double* v = &aov_[i * aov_floats_ + off];
      for (size_t c = 0; c < nc; ++c) {
        float val;
        if (k == Aov::Id)
          val = v[c] > 0 ? float(v[c] - 1) : -1.0f;
        else if (k == Aov::Spp)
          val = float(p.spp);
        else if (p.hits == 0)
          val = k == Aov::Depth ? std::numeric_limits<float>::infinity() : 0.0f;
        else
          val = float(v[c] / p.hits);
        l.data[i * nc + c] = val;
      }
    });
    off += nc;
    out.layers.push_back(std::move(l));
  }
  return out;
}

}  // namespace anamorph
