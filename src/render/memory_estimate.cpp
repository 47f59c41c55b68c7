#include "render/memory_estimate.h"

#include <fmt/format.h>
#include <sys/resource.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "render/denoise_film.h"
#include "render/tile_buffer.h"
#include "scene/scene.h"

namespace anamorph {

namespace {

// Embree's BVH over triangles: an assumed figure (4-wide nodes and triangle leaves come to about
// 100 bytes a triangle), not measured here; an estimate, not a bound.
constexpr uint64_t kAccelBytesPerTriangle = 96;

// Strips waiting to be written besides the one being encoded: tiles finish nearly in order, so
// a few rows at most (two per thread, to be safe).
uint64_t strips_in_flight(int threads) { return uint64_t(2 * std::max(1, threads) + 1); }

uint64_t triangles(const Scene& scene) {
  uint64_t n = 0;
  for (const Instance& inst : scene.instances)
    if (inst.prototype < scene.prototypes.size())
      for (const TriangleMesh& m : scene.prototypes[inst.prototype].meshes) n += m.triangle_count();
  return n;
}

// A value from /proc/self/status or /proc/meminfo, in bytes ("MemAvailable:  123 kB").
uint64_t proc_kb(const char* file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key + ":", 0) == 0) {
      std::istringstream s(line.substr(key.size() + 1));
      uint64_t kb = 0;
      s >> kb;
      return kb * 1024;
    }
  return 0;
}

}  // namespace

uint64_t MemoryNeed::total() const {
  uint64_t t = 0;
  for (const auto& p : parts) t += p.second;
  return t;
}

std::string MemoryNeed::describe() const {
  std::string s;
  for (const auto& [what, bytes] : parts)
    if (bytes > 0) s += fmt::format("{}{} {}", s.empty() ? "" : ", ", what, format_bytes(bytes));
  return s;
}

MemoryNeed estimate_render_memory(const Scene& scene, const RenderShape& r) {
  MemoryNeed need;
  const uint64_t pixels = uint64_t(r.width) * uint64_t(r.height);
  const uint64_t per_pixel = sizeof(PixelSum) + 4 * r.aov_floats;
  const TileGrid grid(r.width, r.height, r.tile_size);
  if (r.whole_film || r.denoise) {
    need.parts.emplace_back(
        fmt::format("film ({} x {} pixels x {} B)", r.width, r.height, per_pixel),
        pixels * per_pixel);
    if (r.active_mask) need.parts.emplace_back("adaptive sampling's pixel mask", pixels);
  } else {
    const uint64_t tile = uint64_t(r.tile_size) * uint64_t(r.tile_size);
    need.parts.emplace_back("tiles in flight", uint64_t(std::max(1, r.threads)) * tile * per_pixel);
  }
  // The output's strips, one tile row each, in the layers and encodings the sinks take.
  const uint64_t strip_pixels = uint64_t(r.width) * uint64_t(r.tile_size);
  const uint64_t strip = strip_pixels * r.strip_bytes_per_pixel;
  need.parts.emplace_back("output strips", strip * strips_in_flight(r.threads));
  if (r.denoise)
    need.parts.emplace_back("the denoiser (other half's film, its planes and its peak)",
                            denoise_film_bytes(r.width, r.height, r.aov_floats, r.threads));
  if (r.output_image)
    need.parts.emplace_back("the whole output image", pixels * (16 + 4 * r.aov_floats + 4));
  need.parts.emplace_back("tile table", uint64_t(grid.count()) * (sizeof(void*) + 8));
  need.parts.emplace_back("acceleration structure (estimate)",
                          triangles(scene) * kAccelBytesPerTriangle);
  return need;
}

std::optional<std::string> memory_shortfall(const MemoryNeed& need, const std::string& what) {
  const uint64_t available = available_memory();
  if (available == 0 || need.total() <= available) return std::nullopt;
  return fmt::format("{} about {} ({}), but {} is available", what, format_bytes(need.total()),
                     need.describe(), format_bytes(available));
}

uint64_t available_memory() {
  uint64_t avail = proc_kb("/proc/meminfo", "MemAvailable");
  // An address-space limit counts what is mapped, not what is touched.
  struct rlimit lim {};
  if (getrlimit(RLIMIT_AS, &lim) == 0 && lim.rlim_cur != RLIM_INFINITY) {
    const uint64_t used = proc_kb("/proc/self/status", "VmSize");
    const uint64_t room = lim.rlim_cur > used ? lim.rlim_cur - used : 0;
    avail = avail ? std::min(avail, room) : room;
  }
  if (getrlimit(RLIMIT_DATA, &lim) == 0 && lim.rlim_cur != RLIM_INFINITY) {
    const uint64_t used = proc_kb("/proc/self/status", "VmData");
    const uint64_t room = lim.rlim_cur > used ? lim.rlim_cur - used : 0;
    avail = avail ? std::min(avail, room) : room;
  }
  return avail;
}

std::string format_bytes(uint64_t bytes) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
  double v = double(bytes);
  int u = 0;
  while (v >= 1024 && u < 4) v /= 1024, ++u;
  return u == 0 ? fmt::format("{} B", bytes) : fmt::format("{:.1f} {}", v, units[u]);
}

}  // namespace anamorph
