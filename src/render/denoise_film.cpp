#include "render/denoise_film.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "math/parallel.h"
#include "render/rim_coverage.h"

namespace anamorph {

namespace {

// The features: albedo (3), normal (3), depth (1) and the fraction of the covered samples that
// hit a surface (1: a pixel on a silhouette against the sky mixes the two in that proportion, so
// its colour is affine in it).
// The positions a rim pixel's coverage is computed from: 32 x 32 (render/rim_coverage.h).
constexpr int kRimGrid = 32;
constexpr int kAlbedo = 0, kNormal = 3, kDepth = 6, kHit = 7, kFeatureChannels = 8;
// The feature pass's samples: kFeatureSppFactor times the colour's, at most kFeatureSppMost (and
// never fewer than the colour's); its films hold the albedo, normal and depth layers.
constexpr int kFeatureSppFactor = 8, kFeatureSppMost = 256, kFeatureLayerFloats = 7;
// The least factor the colour is demodulated by (demodulation_of).
constexpr float kLeastDemodulation = 0.02f;

struct Layers {
  size_t albedo = 0, normal = 0, depth = 0;
};

Layers find_layers(const std::vector<Aov>& aovs) {
  const auto at = [&](Aov a) {
    const auto it = std::find(aovs.begin(), aovs.end(), a);
    if (it == aovs.end())
      throw std::invalid_argument(std::string("denoise: the film has no ") + aov_info(a).name +
                                  " layer (with_denoise_aovs gives the layers it needs)");
    return size_t(it - aovs.begin());
  };
  return {at(Aov::Albedo), at(Aov::Normal), at(Aov::Depth)};
}

// One half's planes: straight colour (3 a pixel) and features (kFeatureChannels a pixel), and
// the sums of coverage and samples per pixel (for the merged coverage).
struct Half {
  explicit Half(size_t pixels)
      : color(pixels * 3), features(pixels * kFeatureChannels), alpha(pixels), n(pixels) {}
  std::vector<float> color, features, alpha, n;
  std::vector<uint8_t> has_color, has_hits;
};

// Pixel (x, y) of a half's colour tile and feature tile (null: no samples) into its planes at
// index i.
void gather_pixel(const TileBuffer* t, const TileBuffer* ft, const Layers& l, int x, int y,
                  size_t i, Half& h) {
  float* c = &h.color[i * 3];
  float* f = &h.features[i * kFeatureChannels];
  const PixelSum* p = t ? &t->at(x, y) : nullptr;
  const PixelSum* q = ft ? &ft->at(x, y) : nullptr;
  h.alpha[i] = p ? p->alpha : 0;
  h.n[i] = p ? float(p->n) : 0;
  h.has_color[i] = p && p->alpha > 0;
  h.has_hits[i] = q && q->hits > 0 && q->alpha > 0;
  if (h.has_color[i])
    for (int k = 0; k < 3; ++k) c[k] = p->rgb[k] / p->alpha;
  if (!h.has_hits[i]) return;  // features 0 (filled from the other half where it has them)
  ft->aov_layer_values(x, y, l.albedo, f + kAlbedo);
  ft->aov_layer_values(x, y, l.normal, f + kNormal);
  ft->aov_layer_values(x, y, l.depth, f + kDepth);
  f[kHit] = float(q->hits) / q->alpha;
}

// Both halves' planes over the frame: colour from `a` and `b`, features from `fa` and `fb`.
void gather(const Film& a, const Film& b, const Film& fa, const Film& fb, Half& ha, Half& hb) {
  const Layers la = find_layers(fa.aovs()), lb = find_layers(fb.aovs());
  const size_t pixels = size_t(a.width()) * size_t(a.height());
  for (Half* h : {&ha, &hb}) h->has_color.assign(pixels, 0), h->has_hits.assign(pixels, 0);
  const TileGrid& g = a.grid();
  for (size_t ti = 0; ti < g.count(); ++ti) {
    const TileRect r = g.rect(ti);
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x) {
        const size_t i = size_t(y) * size_t(a.width()) + size_t(x);
        gather_pixel(a.tile_if_any(ti), fa.tile_if_any(ti), la, x, y, i, ha);
        gather_pixel(b.tile_if_any(ti), fb.tile_if_any(ti), lb, x, y, i, hb);
      }
  }
}

// Where one half has no covered sample (or no hit) at a pixel the other has, it takes the other's
// colour (features): both halves then estimate the pixel alike. Returns the merged coverage.
std::vector<float> complete_halves(Half& a, Half& b) {
  std::vector<float> coverage(a.alpha.size());
  const auto color = [](const Half& from, Half& to, size_t i) {
    std::copy_n(&from.color[i * 3], 3, &to.color[i * 3]);
  };
  const auto features = [](const Half& from, Half& to, size_t i) {
    std::copy_n(&from.features[i * kFeatureChannels], kFeatureChannels,
                &to.features[i * kFeatureChannels]);
  };
  for (size_t i = 0; i < coverage.size(); ++i) {
    const float n = a.n[i] + b.n[i];
    coverage[i] = n > 0 ? std::min(1.0f, (a.alpha[i] + b.alpha[i]) / n) : 0.0f;
    if (coverage[i] <= 0) continue;
    if (!a.has_color[i]) color(b, a, i);
    if (!b.has_color[i]) color(a, b, i);
    if (!a.has_hits[i] && b.has_hits[i]) features(b, a, i);
    if (!b.has_hits[i] && a.has_hits[i]) features(a, b, i);
  }
  return coverage;
}

// Half a's sums added into `film`'s (half b's), tile by tile.
void merge(Film& a, Film& film) {
  for (size_t ti = 0; ti < film.grid().count(); ++ti) {
    std::unique_ptr<TileBuffer> ta = a.take(ti);
    if (!ta) continue;
    if (!film.tile_if_any(ti)) {
      film.put(ti, std::move(ta));
      continue;
    }
    TileBuffer& tb = film.tile(ti);
    for (size_t i = 0; i < tb.sums().size(); ++i) {
      PixelSum& p = tb.sums()[i];
      const PixelSum& q = ta->sums()[i];
      for (int k = 0; k < 3; ++k) p.rgb[k] += q.rgb[k];
      p.alpha += q.alpha;
      p.lum2 += q.lum2;
      p.n += q.n;
      p.hits += q.hits;
      p.spp += q.spp;
    }
    for (size_t i = 0; i < tb.aov_sums().size(); ++i) tb.aov_sums()[i] += ta->aov_sums()[i];
  }
}

// Pixels beside the no-ray boundary (one with coverage below 1 within one pixel of one with
// coverage above 0) that have a ray take their coverage from the camera. A pixel none of whose
// samples had a ray keeps 0: it has no colour to show.
void exact_rim_coverage(const Scene& scene, int w, int h, std::vector<float>& coverage) {
  if (!rim_coverage_applies(*scene.camera, scene.render)) return;
  std::vector<uint8_t> rim(coverage.size(), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      if (coverage[i] <= 0) continue;
      bool partial = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int u = x + dx, v = y + dy;
          if (u >= 0 && v >= 0 && u < w && v < h)
            partial |= coverage[size_t(v) * size_t(w) + size_t(u)] < 1;
        }
      rim[i] = partial;
    }
  const std::vector<float> exact = rim_coverage(*scene.camera, scene.render, w, h, rim, kRimGrid);
  // A pixel that had a ray where none of the grid's positions has one covers less than a cell.
  const float least = 0.5f / float(kRimGrid * kRimGrid);
  for (size_t i = 0; i < coverage.size(); ++i)
    if (rim[i]) coverage[i] = std::max(exact[i], least);
}

// What the colour is demodulated by (denoise.h), per pixel and channel: the albedo of the hits
// mixed with 1 for the misses by the hit fraction (the features' mean over both halves: many
// samples), at least kLeastDemodulation (a black texture's colour is not divided by 0).
std::vector<float> demodulation_of(const Half& a, const Half& b,
                                   const std::vector<float>& coverage) {
  std::vector<float> d(coverage.size() * 3, 1.0f);
  for (size_t i = 0; i < coverage.size(); ++i) {
    if (coverage[i] <= 0) continue;
    const float* fa = &a.features[i * kFeatureChannels];
    const float* fb = &b.features[i * kFeatureChannels];
    const float hit = 0.5f * (fa[kHit] + fb[kHit]);
    for (int c = 0; c < 3; ++c) {
      const float albedo = 0.5f * (fa[kAlbedo + c] + fb[kAlbedo + c]);
      d[i * 3 + size_t(c)] = std::max(hit * albedo + (1 - hit), kLeastDemodulation);
    }
  }
  return d;
}

// The denoised straight colour written as the film's beauty: rgb sums = colour x coverage sum,
// and the coverage sum = coverage x samples (the camera's coverage at a rim).
void write_beauty(Film& film, const std::vector<float>& rgb, const std::vector<float>& coverage) {
  const TileGrid& g = film.grid();
  for (size_t ti = 0; ti < g.count(); ++ti) {
    if (!film.tile_if_any(ti)) continue;
    TileBuffer& t = film.tile(ti);
    const TileRect r = g.rect(ti);
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x) {
        const size_t i = size_t(y) * size_t(film.width()) + size_t(x);
        PixelSum& p = t.at(x, y);
        if (coverage[i] <= 0 || p.alpha <= 0) continue;
        if (coverage[i] != std::min(1.0f, p.alpha / float(p.n))) p.alpha = coverage[i] * float(p.n);
        for (int k = 0; k < 3; ++k) p.rgb[k] = rgb[i * 3 + size_t(k)] * p.alpha;
      }
  }
}

}  // namespace

std::vector<Aov> with_denoise_aovs(std::vector<Aov> aovs) {
  for (Aov a : {Aov::Albedo, Aov::Normal, Aov::Depth})
    if (std::find(aovs.begin(), aovs.end(), a) == aovs.end()) aovs.push_back(a);
  return aovs;
}

std::optional<std::string> denoise_unsupported(const RenderSettings& rs) {
  if (rs.adaptive())
    return "it needs uniform sampling (render.antialias = \"uniform\", or --spp N): its two half "
           "buffers split every pixel's samples in two equal halves";
  if (rs.spp < 2) return "it needs at least 2 samples per pixel (two half buffers)";
  if (rs.time_limit > 0)
    return "it cannot be combined with render.time_limit (the second half might be cut short)";
  return std::nullopt;
}

uint32_t denoise_feature_spp(int spp) {
  return uint32_t(std::max(spp, std::min(kFeatureSppFactor * spp, kFeatureSppMost)));
}

uint64_t denoise_film_bytes(int width, int height, size_t film_aov_floats, int threads) {
  const uint64_t pixels = uint64_t(width) * uint64_t(height);
  // The other half's film, and the feature pass's two films (albedo, normal, depth layers).
  const uint64_t half = sizeof(PixelSum) + 4 * film_aov_floats +
                        2 * (sizeof(PixelSum) + 4 * uint64_t(kFeatureLayerFloats));
  // Inputs: two halves of colour and features, their coverage sums and counts, the merged
  // coverage, the demodulation, the output colour; flags.
  const uint64_t planes = 4 * (2 * (3 + kFeatureChannels + 2) + 1 + 3 + 3) + 4;
  return pixels * (half + planes) + denoise_bytes(width, height, kFeatureChannels, {}, threads);
}

DenoiseStats denoise_halves(Film& a, Film& film, const DenoiseOptions& options, const Scene* scene,
                            const Film* features_a, const Film* features_b) {
  const size_t pixels = size_t(film.width()) * size_t(film.height());
  Half ha(pixels), hb(pixels);
  gather(a, film, features_a ? *features_a : a, features_b ? *features_b : film, ha, hb);
  std::vector<float> coverage = complete_halves(ha, hb);
  if (scene) exact_rim_coverage(*scene, film.width(), film.height(), coverage);
  DenoiseInput in;
  in.width = film.width();
  in.height = film.height();
  in.color_a = ha.color.data();
  in.color_b = hb.color.data();
  in.coverage = coverage.data();
  in.features = {{ha.features.data(), hb.features.data(), kFeatureChannels}};
  std::vector<float> out(pixels * 3);
  const std::vector<float> demodulation = demodulation_of(ha, hb, coverage);
  in.demodulation = demodulation.data();
  const DenoiseStats st = denoise(in, options, out.data());
  merge(a, film);
  if (!st.cancelled) write_beauty(film, out, coverage);
  return st;
}

namespace {

// Renders `rs` (the albedo view, no light paths) into two films of the denoiser's layers, split
// in halves as the colour is. False when cancelled.
bool render_feature_halves(const Renderer& renderer, const RenderSettings& rs, RenderOptions opt,
                           Film& fa, Film& fb) {
  opt.settings = &rs;
  opt.aovs = fa.aovs();
  opt.on_progress = nullptr;  // (the colour's progress is the render's)
  opt.on_tile_pass = nullptr;
  opt.on_pass_start = nullptr;
  opt.tile_times = nullptr;
  opt.split_at = uint32_t(rs.spp) / 2;
  opt.on_pass = [&](const Film&, int pass) {
    if (pass == 0)
      for (size_t i = 0; i < fb.grid().count(); ++i) fa.put(i, fb.take(i));
  };
  const RenderStats st = renderer.render(fb, opt);
  return !st.cancelled && !st.time_limited;
}

}  // namespace

DenoisedRender render_denoised(const Renderer& renderer, const RenderSettings& rs, Film& film,
                               RenderOptions opt, const DenoiseOptions& options) {
  if (const auto why = denoise_unsupported(rs)) throw std::invalid_argument("denoise: " + *why);
  find_layers(film.aovs());
  Film a(film.width(), film.height(), film.aovs(), film.grid().size);
  opt.aovs = film.aovs();
  opt.progressive = false;
  opt.split_at = uint32_t(rs.spp) / 2;
  opt.finest_footprint = true;
  bool halved = false;
  opt.on_pass = [&](const Film&, int pass) {
    if (pass != 0) return;
    for (size_t i = 0; i < film.grid().count(); ++i) a.put(i, film.take(i));
    halved = true;
  };
  DenoisedRender r;
  r.stats = renderer.render(film, opt);
  if (!halved || r.stats.cancelled || r.stats.time_limited) {
    merge(a, film);
    return r;
  }
  const auto t0 = std::chrono::steady_clock::now();
  RenderSettings frs = rs;
  frs.view = View::Albedo;
  frs.spp = int(denoise_feature_spp(rs.spp));
  const std::vector<Aov> layers = with_denoise_aovs({});
  Film fa(film.width(), film.height(), layers, film.grid().size);
  Film fb(film.width(), film.height(), layers, film.grid().size);
  if (!render_feature_halves(renderer, frs, opt, fa, fb)) {
    merge(a, film);
    return r;
  }
  tbb::task_arena arena(arena_concurrency(opt.threads));
  DenoiseOptions o = options;
  if (!o.cancel) o.cancel = opt.cancel;
  arena.execute([&] { r.denoise = denoise_halves(a, film, o, &renderer.scene(), &fa, &fb); });
  r.denoise_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.denoised = !r.denoise.cancelled;
  return r;
}

}  // namespace anamorph
