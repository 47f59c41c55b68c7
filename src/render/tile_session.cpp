#include "render/tile_session.h"

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <chrono>
#include <limits>

#include "accel/accel.h"
#include "camera/ray_field.h"
#include "render/adaptive.h"
#include "render/lights.h"

namespace anamorph {

namespace {

// One tile of the paper's adaptive supersampling, into `tile`. AOVs come from one sample at each
// pixel's center (averaging lattice points' ids or normals across an edge means nothing).
void render_lattice_tile(const AdaptiveGrid& grid, const RenderJob& job, AdaptiveWorkspace& ws,
                         TileBuffer& tile, TileStats& st) {
  const AdaptiveGrid::EvalBatch eval = [&](const Vec2* uv, const uint64_t* keys,
                                           const double* footprints, const bool* use,
                                           SampleResult* out, uint64_t& rays, CameraRayBatch* cam) {
    job.lattice_samples(uv, keys, footprints, use, out, rays, cam);
  };
  const bool aovs = !tile.aovs().empty();
  const TileRect& r = tile.rect();
  grid.render_tile(
      r.x0, r.y0, r.x1, r.y1, ws, eval,
      [&](int x, int y, const PixelResult& p) {
        AovSample a;
        if (aovs) {
          Rng rng(mix64(uint64_t(y) * 0x9E3779B97F4A7C15ULL + uint64_t(x)), job.rs.seed);
          a = job.sample_at({(x + 0.5) / job.W, (y + 0.5) / job.H}, rng, st.rays).aov;
        }
        if (p.nans) st.nan(x, y, 0);
        tile.set(x, y, p.L, p.alpha, p.samples, a);
      },
      st.rays, st.samples);
}

// The per-pixel layers (ray_origin, ray_direction) of the tile: the pixel-centre camera ray of
// every pixel, hit or not, NaN where the camera has none. Written after each of the tile's
// sweeps (the same values each time), so whole tiles, passes and resumed sums all hold them.
void set_ray_layers(const Camera& cam, int W, int H, TileBuffer& tile) {
  const std::vector<Aov>& aovs = tile.aovs();
  if (std::none_of(aovs.begin(), aovs.end(), aov_is_per_pixel)) return;
  const TileRect& r = tile.rect();
  const size_t n = r.pixels();
  std::vector<double> org(3 * n), dir(3 * n);
  std::vector<uint8_t> valid(n);
  generate_pixel_rays(cam, W, H, r.x0, r.y0, r.x1, r.y1,
                      {org.data(), dir.data(), nullptr, nullptr, nullptr, nullptr, valid.data()});
  for (size_t layer = 0; layer < aovs.size(); ++layer) {
    if (!aov_is_per_pixel(aovs[layer])) continue;
    const double* v = aovs[layer] == Aov::RayOrigin ? org.data() : dir.data();
    for (size_t k = 0; k < n; ++k) {
      float f[3];
      for (size_t c = 0; c < 3; ++c)
        f[c] = valid[k] ? float(v[3 * k + c]) : std::numeric_limits<float>::quiet_NaN();
      tile.set_values(r.x0 + int(k % size_t(r.width())), r.y0 + int(k / size_t(r.width())), layer,
                      f);
    }
  }
}

}  // namespace

struct TileSession::Workspaces {
  tbb::enumerable_thread_specific<AdaptiveWorkspace> local;
};

TileSession::TileSession(const World& w, std::vector<Aov> aovs, int width, int height,
                         const std::atomic<bool>* cancel)
    : rs_(w.settings ? *w.settings : w.scene.render),
      aovs_(std::move(aovs)),
      ctx_{w.scene, w.accel, w.lights, rs_.max_depth, rs_.bailout, cancel},
      job_(w.scene, w.accel, ctx_, rs_, width, height, aovs_),
      sampler_(job_),
      spaces_(std::make_unique<Workspaces>()) {
  // The paper's adaptive supersampling: corners shared between pixels, squares split where they
  // differ, stretched pixels split from the start.
  if (rs_.adaptive() && rs_.antialias == Antialias::Lattice)
    lattice_ =
        std::make_unique<AdaptiveGrid>(*w.scene.camera, width, height, rs_, w.accel.bounds());
}

TileSession::~TileSession() = default;

FarmResult TileSession::render(const FarmTile& t, std::unique_ptr<TileBuffer>& buffer) const {
  FarmResult r;
  r.index = t.index;
  const auto t0 = std::chrono::steady_clock::now();
  if (!t.whole) {
    samples(t.range, *t.sums, r.stats);
    set_ray_layers(*job_.scene.camera, job_.W, job_.H, *t.sums);
  } else {
    if (buffer)
      buffer->reset(t.rect);
    else
      buffer = std::make_unique<TileBuffer>(t.rect, aovs_);
    whole(*buffer, r.stats);
    set_ray_layers(*job_.scene.camera, job_.W, job_.H, *buffer);
    if (t.plan)
      r.resolved = resolve(t.index, *buffer, *t.plan);
    else
      r.tile = std::move(buffer);
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

void TileSession::whole(TileBuffer& tile, TileStats& st) const {
  if (lattice_)
    render_lattice_tile(*lattice_, job_, spaces_->local.local(), tile, st);
  else
    sampler_.sample({0, uint32_t(rs_.spp), job_.uniform_scale, nullptr}, tile, st);
}

uint64_t TileSession::whole_work_per_pixel(const RenderSettings& rs) {
  return rs.adaptive() && rs.antialias == Antialias::Lattice ? 1 : uint64_t(rs.spp);
}

}  // namespace anamorph
