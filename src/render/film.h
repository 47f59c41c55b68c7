// The film: per-pixel sums of samples for the beauty pass and any AOVs. Every pixel is written by
// exactly one thread (its tile's), in sample order, so sums are bit-identical for any thread count.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "io/image_io.h"
#include "math/vec.h"

namespace anamorph {

enum class Aov { Albedo, Normal, Depth, Position, Id, Uv, Spp };

struct AovInfo {
  Aov aov;
  const char* name;
  std::vector<std::string> channels;
};
const std::vector<AovInfo>& aov_table();
// Parses "albedo,normal,depth"; throws std::invalid_argument naming a bad entry.
std::vector<Aov> parse_aovs(const std::string& list);
const AovInfo& aov_info(Aov a);

// What one camera sample contributes to the AOVs (valid only when `hit`).
struct AovSample {
  bool hit = false;
  Color albedo;
  Vec3 normal, position;
  double depth = 0;
  double id = -1;
  Vec2 uv;
};

class Film {
 public:
  Film(int width, int height, std::vector<Aov> aovs);
  int width() const { return w_; }
  int height() const { return h_; }
  const std::vector<Aov>& aovs() const { return aovs_; }

  // One camera sample: radiance, coverage (0 for "no ray") and AOV values. The first sample of a
  // render (first_sample) replaces whatever the pixel held.
  // Inline: one call per camera sample, and most renders have no AOV layers.
  void add(int x, int y, const Color& L, double alpha, const AovSample& a, bool first_sample) {
    Pixel& p = px(x, y);
    const double l = luminance(L);
    if (first_sample) {
      // The first sample of a render overwrites the pixel, as a viewer overwrites its frame
      // buffer: the film need not be cleared between renders, and the old values are not read.
      p = Pixel{{L.x, L.y, L.z}, alpha, l * l, 1, 0, 1};
    } else {
      p.rgb[0] += L.x;
      p.rgb[1] += L.y;
      p.rgb[2] += L.z;
      p.alpha += alpha;
      p.lum2 += l * l;
      p.n++;
      p.spp++;
    }
    if (aov_floats_ > 0) {
      if (first_sample) clear_aovs(x, y);
      add_aovs(x, y, a, first_sample);
    }
  }
  // The pixel back to no samples (a first sample that was dropped).
  void reset(int x, int y);
  // Back to no samples (keeps the memory).
  void clear();
  // A pixel finished elsewhere (adaptive subdivision): its value and how many samples it took.
  void set(int x, int y, const Color& L, double alpha, uint32_t spp, const AovSample& a);
  // Camera samples that went into a pixel (the `spp` AOV).
  uint32_t samples(int x, int y) const { return px(x, y).spp; }
  // Standard error of the pixel's mean luminance (per-pixel adaptive sampling).
  double standard_error(int x, int y) const;

  // Averages: beauty as RGBA (straight alpha), AOV layers as their channels.
  OutputImage output() const;
  // The beauty layer of output() as a PNG stores it (8-bit sRGB, straight alpha), without the
  // float layer in between (33 MB at 1080p, a visible part of a quick render).
  std::vector<unsigned char> output_rgba8() const;
  Color pixel(int x, int y) const;  // averaged beauty RGB (premultiplied by coverage)
  double alpha(int x, int y) const;

 private:
  // Trivial, so the allocator below can leave new pixels for clear() to zero in parallel (the
  // first touch of a 1080p film is ~30,000 page faults); Pixel{} is all zeros.
  struct Pixel {
    double rgb[3];
    double alpha;
    double lum2;    // sum of squared luminance (variance estimate)
    uint32_t n;     // terms in the sums
    uint32_t hits;  // samples that hit a surface (AOV averages)
    uint32_t spp;   // camera samples taken (equals n for uniform sampling)
  };
  template <class T>
  struct UninitializedAllocator : std::allocator<T> {
    UninitializedAllocator() = default;
    template <class U>
    UninitializedAllocator(const UninitializedAllocator<U>&) {}
    template <class U>
    void construct(U*) noexcept {}  // default construction: left to clear()
    template <class U, class... A>
    void construct(U* p, A&&... a) {
      ::new (static_cast<void*>(p)) U(std::forward<A>(a)...);
    }
  };
  // A pixel's averaged beauty as straight RGBA.
  static void beauty_rgba(const Pixel& p, float* out);
  void add_aovs(int x, int y, const AovSample& a, bool first_sample);
  void clear_aovs(int x, int y);
  Pixel& px(int x, int y) { return pixels_[size_t(y) * w_ + x]; }
  const Pixel& px(int x, int y) const { return pixels_[size_t(y) * w_ + x]; }
  int w_, h_;
  std::vector<Aov> aovs_;
  std::vector<Pixel, UninitializedAllocator<Pixel>> pixels_;
  size_t aov_floats_ = 0;    // per pixel
  std::vector<double> aov_;  // per pixel sums, aov_floats_ each
};

}  // namespace anamorph
