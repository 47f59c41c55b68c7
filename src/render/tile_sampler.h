// Sample passes over one tile: camera samples built in 4x4 packets (the packet builder; the
// pixels per-pixel adaptive sampling leaves on are packed 16 to a packet instead), traced
// as one Embree packet, finished by the job and summed into the tile's buffer. Internal to the
// renderer.
#pragma once

#include <cstdint>
#include <vector>

#include "render/render_job.h"
#include "render/tile_buffer.h"

namespace anamorph {

// Rays, samples and dropped (non-finite) samples of one tile.
struct TileStats {
  uint64_t rays = 0, samples = 0, nans = 0;
  int nan_x = -1, nan_y = -1, nan_s = -1;
  void nan(int x, int y, int s) {
    if (nans++ == 0) nan_x = x, nan_y = y, nan_s = s;
  }
};

// Samples [begin, end) of every pixel of a tile that `active` (a frame-wide mask, or null for
// all pixels) leaves on. `footprint` is each sample's share of its pixel (RenderJob::finish).
struct SampleRange {
  uint32_t begin = 0, end = 1;
  double footprint = 1;
  const std::vector<uint8_t>* active = nullptr;
};

class TileSampler {
 public:
  explicit TileSampler(const RenderJob& job);
  // Adds the range's samples into `tile`; stops within one packet when the render is cancelled.
  void sample(const SampleRange& range, TileBuffer& tile, TileStats& st) const;

 private:
  static constexpr int kPacket = kCameraBatch;  // 4x4 pixels
  // One packet's lanes: pixel, camera sample, random numbers, rays and hits. Lives for a whole
  // tile: constructing the arrays per packet (zeroing about 6 KB) cost a third of the time of
  // primary-ray renders.
  struct Packet {
    int x[kPacket], y[kPacket];
    bool use[kPacket], valid[kPacket], found[kPacket];
    CameraSample cs[kPacket];
    Rng rng[kPacket];
    CameraRayBatch cam;
    Hit hits[kPacket];
    SampleResult res;
  };
  bool lane_on(const SampleRange& r, const TileRect& t, int x, int y) const;
  // Every sample at the same spot of its pixel, no random numbers: u per column, v per row.
  void build_fixed(const SampleRange& r, const TileRect& t, int x, int y, Packet& p) const;
  void build_random(const SampleRange& r, const TileRect& t, int x, int y, uint32_t s,
                    Packet& p) const;
  // Lane k's camera sample (and random numbers) for sample s of pixel (p.x[k], p.y[k]).
  void fill_lane(Packet& p, int k, uint32_t s) const;
  // The pixels `active` leaves on, packed 16 to a packet whatever their positions.
  void sample_listed(const SampleRange& r, TileBuffer& tile, TileStats& st) const;
  void trace(Packet& p, uint32_t s, double footprint, TileBuffer& tile, TileStats& st) const;

  const RenderJob& job_;
  bool lens_time_, needs_rng_, qmc_, gaussian_;
  Vec2 fixed_offset_;
};

}  // namespace anamorph
