#include "render/tile_buffer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace anamorph {

// Over 60 lines on purpose: a table, one row per layer (its name, channels and definition), read
// as the one source of the layers' names and documentation.
const std::vector<AovInfo>& aov_table() {
  static const std::vector<AovInfo> t = {
      {Aov::Albedo, "albedo", {"R", "G", "B"}, "base colour of the first surface hit"},
      {Aov::Normal,
       "normal",
       {"X", "Y", "Z"},
       "world-space shading normal of the first hit, facing the camera ray"},
      {Aov::Depth,
       "depth",
       {"Z"},
       "ray distance: Euclidean distance from the camera ray's origin to the first hit, scene "
       "units (the same as distance); inf where nothing is hit"},
      {Aov::Position, "position", {"X", "Y", "Z"}, "world-space position of the first hit"},
      {Aov::Id, "id", {"id"}, "object id of the first hit (first sample's), -1 for none"},
      {Aov::Uv, "uv", {"U", "V"}, "surface parameters of the first hit"},
      {Aov::Spp, "spp", {"N"}, "camera samples the pixel took"},
      {Aov::Distance,
       "distance",
       {"D"},
       "ray distance: Euclidean distance from the camera ray's origin (per ray, not the camera "
       "centre) to the first hit, scene units; inf where nothing is hit"},
      {Aov::DepthZ,
       "depth_z",
       {"Z"},
       "distance of the first hit in front of the camera rig's origin along its view axis: -z "
       "of camera space (the rig at shutter open), scene units; the pinhole z-depth, and the "
       "same plane-parallel depth under any camera (negative behind the rig's plane); inf where "
       "nothing is hit"},
      {Aov::CameraPosition,
       "position_camera",
       {"X", "Y", "Z"},
       "first hit in camera space (the rig at shutter open): x right, y up, looking along -z, "
       "scene units (OpenCV's camera frame is (x, -y, -z))"},
      {Aov::FlowForward,
       "flow_forward",
       {"X", "Y", "valid"},
       "forward optical flow in pixels (x right, y down): where the first hit's point, moved "
       "with its object (a deforming mesh's: with its triangle's vertices) to frame + 1, is seen "
       "by frame + 1's camera (inverse map), minus where "
       "it is seen now; mean over the pixel's samples that have one (NaN where none has); "
       "a sample has none when the point leaves the image or is hidden at frame + 1 (traced from "
       "that frame's camera ray to it); valid: their fraction of the hits"},
      {Aov::FlowBackward,
       "flow_backward",
       {"X", "Y", "valid"},
       "backward optical flow in pixels (x right, y down): flow_forward's definition toward "
       "frame - 1"},
      {Aov::Motion,
       "motion",
       {"X", "Y", "Z", "W"},
       "motion vectors in Blender Cycles' Vector pass convention, pixels with y up: (X, Y) = "
       "position at frame - 1 minus position now, (Z, W) = position now minus position at "
       "frame + 1; the first hit's point moved with its object (or its deforming mesh's "
       "vertices) and seen by that frame's "
       "camera, hidden or not; mean over the pixel's hits, a hit without an image there "
       "counting 0; 0 where nothing is hit"},
      {Aov::RayOrigin,
       "ray_origin",
       {"X", "Y", "Z"},
       "world-space origin of the camera ray through the pixel centre ((x + 1/2) / W, "
       "(y + 1/2) / H) with the lens centre and the shutter-open time (what `anamorph rays` "
       "writes), scene units; set for every pixel, hit or not; NaN where the camera has no ray "
       "(outside a fisheye's circle)"},
      {Aov::RayDirection,
       "ray_direction",
       {"X", "Y", "Z"},
       "world-space unit direction of ray_origin's ray (the pixel-centre camera ray); NaN where "
       "the camera has no ray"},
  };
  return t;
}

bool aovs_need_frame(const std::vector<Aov>& aovs, int step) {
  const Aov flow = step > 0 ? Aov::FlowForward : Aov::FlowBackward;
  return std::find(aovs.begin(), aovs.end(), flow) != aovs.end() ||
         std::find(aovs.begin(), aovs.end(), Aov::Motion) != aovs.end();
}

const AovInfo& aov_info(Aov a) {
  for (const auto& i : aov_table())
    if (i.aov == a) return i;
  throw std::logic_error("unknown AOV");
}

size_t aov_floats(const std::vector<Aov>& aovs) {
  size_t n = 0;
  for (Aov a : aovs) n += aov_info(a).channels.size();
  return n;
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

TileGrid::TileGrid(int w, int h, int tile_size)
    : width(w),
      height(h),
      size(std::max(1, tile_size)),
      cols((w + size - 1) / size),
      rows((h + size - 1) / size) {}

TileRect TileGrid::rect(size_t index) const {
  const int tx = int(index % size_t(cols)), ty = int(index / size_t(cols));
  return {tx * size, ty * size, std::min(width, (tx + 1) * size),
          std::min(height, (ty + 1) * size)};
}

TileBuffer::TileBuffer(const TileRect& rect, const std::vector<Aov>& aovs)
    : rect_(rect),
      aovs_(aovs),
      aov_floats_(anamorph::aov_floats(aovs)),
      px_(rect.pixels()),
      aov_(rect.pixels() * aov_floats_) {
  size_t offset = 0;
  for (Aov a : aovs_) {
    aov_offsets_.push_back(offset);
    offset += aov_info(a).channels.size();
  }
}

void TileBuffer::reset(const TileRect& rect) {
  rect_ = rect;
  px_.assign(rect.pixels(), PixelSum{});
  aov_.assign(rect.pixels() * aov_floats_, 0.0f);
}

void TileBuffer::set(int x, int y, const Color& L, double alpha, uint32_t spp, const AovSample& a) {
  PixelSum& p = at(x, y);
  p = PixelSum{};
  p.rgb[0] = float(L.x);
  p.rgb[1] = float(L.y);
  p.rgb[2] = float(L.z);
  p.alpha = float(alpha);
  p.n = 1;
  p.spp = spp;
  if (aov_floats_ == 0) return;
  std::fill_n(aov_.begin() + ptrdiff_t(index(x, y) * aov_floats_), aov_floats_, 0.0f);
  if (a.hit) add_aovs(x, y, a);
}

void TileBuffer::set_values(int x, int y, size_t layer, const float* values) {
  const size_t n = aov_info(aovs_[layer]).channels.size();
  std::copy_n(values, n, aov_.begin() + ptrdiff_t(index(x, y) * aov_floats_ + aov_offsets_[layer]));
}

// Over 60 lines on purpose: a switch over the closed set of layers, each case the few values its
// layer sums (cutting it would only scatter the cases).
void TileBuffer::add_aovs(int x, int y, const AovSample& a) {
  PixelSum& p = at(x, y);
  p.hits++;
  float* v = &aov_[index(x, y) * aov_floats_];
  const auto add = [&v](std::initializer_list<double> values) {
    for (const double d : values) *v++ += float(d);
  };
  for (Aov k : aovs_) {
    switch (k) {
      case Aov::Albedo:
        add({a.albedo.x, a.albedo.y, a.albedo.z});
        break;
      case Aov::Normal:
        add({a.normal.x, a.normal.y, a.normal.z});
        break;
      case Aov::Position:
        add({a.position.x, a.position.y, a.position.z});
        break;
      case Aov::Depth:
        add({a.depth});
        break;
      case Aov::Id:
        // An average of ids means nothing: keep the first hit's, stored +1 so 0 means "none".
        if (*v == 0) *v = float(a.id + 1);
        ++v;
        break;
      case Aov::Uv:
        add({a.uv.x, a.uv.y});
        break;
      case Aov::Spp:
        ++v;  // read from the pixel's sample count when resolved
        break;
      case Aov::Distance:
        add({a.depth});
        break;
      case Aov::DepthZ:
        add({a.depth_z});
        break;
      case Aov::CameraPosition:
        add({a.position_camera.x, a.position_camera.y, a.position_camera.z});
        break;
      case Aov::FlowForward:
      case Aov::FlowBackward: {
        // Summed over the samples whose point has an image at the other frame, and counted.
        const int d = k == Aov::FlowForward ? 0 : 1;
        if (a.flow_valid[d])
          add({a.flow[d].x, a.flow[d].y, 1.0});
        else
          v += 3;
        break;
      }
      case Aov::RayOrigin:
      case Aov::RayDirection:
        v += 3;  // per pixel, set_values
        break;
      case Aov::Motion: {
        // Cycles: y up, (previous - now, now - next).
        const Vec2 back = a.moved[1] ? a.flow[1] : Vec2{}, fwd = a.moved[0] ? a.flow[0] : Vec2{};
        add({back.x, -back.y, -fwd.x, fwd.y});
        break;
      }
    }
  }
}

namespace {

// Flow: the mean over the samples that have one (NaN where none has), and the fraction of the
// pixel's hits that have one.
void resolve_flow(const PixelSum& p, const float* v, float* out) {
  const float valid = v[2];
  out[0] = valid > 0 ? v[0] / valid : std::numeric_limits<float>::quiet_NaN();
  out[1] = valid > 0 ? v[1] / valid : std::numeric_limits<float>::quiet_NaN();
  out[2] = p.hits > 0 ? valid / float(p.hits) : 0.0f;
}

// One AOV's resolved channels from its sums `v` (a pixel's share of aov_sums()).
void resolve_aov(Aov k, size_t channels, const PixelSum& p, const float* v, float* out) {
  if (k == Aov::FlowForward || k == Aov::FlowBackward) return resolve_flow(p, v, out);
  if (aov_is_per_pixel(k)) {
    std::copy_n(v, channels, out);
    return;
  }
  const bool distance = k == Aov::Depth || k == Aov::Distance || k == Aov::DepthZ;
  for (size_t c = 0; c < channels; ++c, ++v, ++out) {
    if (k == Aov::Id)
      *out = *v > 0 ? *v - 1 : -1.0f;
    else if (k == Aov::Spp)
      *out = float(p.spp);
    else if (p.hits == 0)
      *out = distance ? std::numeric_limits<float>::infinity() : 0.0f;
    else
      *out = *v / float(p.hits);
  }
}

}  // namespace

void TileBuffer::aov_values(int x, int y, float* out) const {
  const PixelSum& p = at(x, y);
  const float* v = aov_at(x, y);
  for (Aov k : aovs_) {
    const size_t nc = aov_info(k).channels.size();
    resolve_aov(k, nc, p, v, out);
    v += nc;
    out += nc;
  }
}

void TileBuffer::aov_layer_values(int x, int y, size_t layer, float* out) const {
  const Aov k = aovs_[layer];
  resolve_aov(k, aov_info(k).channels.size(), at(x, y), aov_at(x, y) + aov_offsets_[layer], out);
}

double TileBuffer::standard_error(int x, int y) const {
  const PixelSum& p = at(x, y);
  if (p.n < 2) return kInf;
  const double n = p.n;
  const double mean = luminance({p.rgb[0], p.rgb[1], p.rgb[2]}) / n;
  const double var = std::max(0.0, (double(p.lum2) - n * mean * mean) / (n - 1));
  return std::sqrt(var / n);
}

}  // namespace anamorph
