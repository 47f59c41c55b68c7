#include "dist/wire.h"

namespace anamorph::dist {

namespace {

void put_rect(WireWriter& w, const TileRect& r) {
  for (int v : {r.x0, r.y0, r.x1, r.y1}) w.put(int32_t(v));
}

TileRect get_rect(WireReader& r) {
  TileRect t;
  t.x0 = r.get<int32_t>();
  t.y0 = r.get<int32_t>();
  t.x1 = r.get<int32_t>();
  t.y1 = r.get<int32_t>();
  if (t.x1 < t.x0 || t.y1 < t.y0 || t.x0 < 0 || t.y0 < 0)
    throw std::runtime_error("a tile with a bad rectangle");
  return t;
}

// The sums of the pixels `mask` leaves on (all when empty), in order, onto the wire.
void put_sums(WireWriter& w, const TileBuffer& tile, const std::vector<uint8_t>& mask) {
  const size_t nf = tile.aov_floats();
  if (mask.empty()) {
    w.put_array(tile.sums().data(), tile.sums().size());
    w.put_array(tile.aov_sums().data(), tile.aov_sums().size());
    return;
  }
  std::vector<PixelSum> sums;
  std::vector<float> aov;
  for (size_t i = 0; i < mask.size(); ++i)
    if (mask[i]) {
      sums.push_back(tile.sums()[i]);
      aov.insert(aov.end(), tile.aov_sums().begin() + ptrdiff_t(i * nf),
                 tile.aov_sums().begin() + ptrdiff_t((i + 1) * nf));
    }
  w.put_array(sums.data(), sums.size());
  w.put_array(aov.data(), aov.size());
}

// Sums in the order put_sums wrote them, back into the pixels `mask` leaves on.
void scatter(const std::vector<PixelSum>& sums, const std::vector<float>& aov,
             const std::vector<uint8_t>& mask, TileBuffer& tile) {
  const size_t nf = tile.aov_floats();
  if (!mask.empty() && mask.size() != tile.sums().size())
    throw std::runtime_error("a tile's mask does not fit its rectangle");
  const size_t on =
      mask.empty()
          ? tile.sums().size()
          : size_t(std::count_if(mask.begin(), mask.end(), [](uint8_t m) { return m != 0; }));
  if (sums.size() != on || aov.size() != on * nf)
    throw std::runtime_error("a tile's sums do not fit its pixels");
  for (size_t i = 0, k = 0; i < tile.sums().size(); ++i) {
    if (!mask.empty() && !mask[i]) continue;
    tile.sums()[i] = sums[k];
    std::copy_n(aov.begin() + ptrdiff_t(k * nf), nf, tile.aov_sums().begin() + ptrdiff_t(i * nf));
    ++k;
  }
}

}  // namespace

std::vector<uint8_t> mask_slice(const std::vector<uint8_t>* active, int image_width,
                                const TileRect& rect) {
  std::vector<uint8_t> slice;
  if (!active) return slice;
  slice.reserve(rect.pixels());
  for (int y = rect.y0; y < rect.y1; ++y) {
    const auto row = active->begin() + ptrdiff_t(y) * image_width;
    slice.insert(slice.end(), row + rect.x0, row + rect.x1);
  }
  return slice;
}

namespace {

// The layers and encodings a whole tile is resolved to: their count, then each one's encoding
// and layer name.
constexpr uint32_t kMaxPlan = 256;
constexpr size_t kMaxLayerName = 255;

void put_plan(WireWriter& w, const std::vector<LayerRequest>& plan) {
  w.put(uint32_t(plan.size()));
  for (const LayerRequest& r : plan) {
    w.put(uint8_t(r.encoding));
    w.put_array(r.layer.data(), r.layer.size());
  }
}

std::vector<LayerRequest> get_plan(WireReader& r) {
  const auto n = r.get<uint32_t>();
  if (n > kMaxPlan) throw std::runtime_error("a tile resolved to too many layers");
  std::vector<LayerRequest> plan(n);
  for (LayerRequest& q : plan) {
    const auto e = r.get<uint8_t>();
    if (e > uint8_t(Encoding::Float32)) throw std::runtime_error("a layer in an unknown encoding");
    q.encoding = Encoding(e);
    std::vector<char> name;
    r.get_array(name);
    if (name.size() > kMaxLayerName) throw std::runtime_error("a layer name too long");
    q.layer.assign(name.begin(), name.end());
  }
  return plan;
}

}  // namespace

std::vector<char> encode_work(const FarmTile& t, const std::vector<uint8_t>& mask) {
  WireWriter w;
  w.put(uint64_t(t.index));
  put_rect(w, t.rect);
  w.put(uint8_t(t.whole));
  if (t.whole) {
    w.put(uint8_t(t.plan != nullptr));
    if (t.plan) put_plan(w, *t.plan);
  } else {
    w.put(t.range.begin);
    w.put(t.range.end);
    w.put(t.range.footprint);
    w.put_array(mask.data(), mask.size());
    // Before the first pass every sum is zero: nothing to send.
    w.put(uint8_t(t.range.begin > 0));
    if (t.range.begin > 0) put_sums(w, *t.sums, mask);
  }
  return std::move(w.bytes());
}

WorkMessage decode_work(const char* data, size_t size) {
  WireReader r(data, size);
  WorkMessage m;
  m.index = r.get<uint64_t>();
  m.rect = get_rect(r);
  m.whole = r.get<uint8_t>() != 0;
  if (m.whole) {
    m.resolve = r.get<uint8_t>() != 0;
    if (m.resolve) m.plan = get_plan(r);
  } else {
    m.begin = r.get<uint32_t>();
    m.end = r.get<uint32_t>();
    m.footprint = r.get<double>();
    r.get_array(m.active);
    if (!m.active.empty() && m.active.size() != m.rect.pixels())
      throw std::runtime_error("a tile's mask does not fit its rectangle");
    if (r.get<uint8_t>()) {
      r.get_array(m.sums);
      r.get_array(m.aov);
    }
  }
  if (!r.done()) throw std::runtime_error("a work message with bytes left over");
  return m;
}

void unpack_work(WorkMessage& m, TileBuffer& tile) {
  if (m.begin > 0) scatter(m.sums, m.aov, m.active, tile);
}

namespace {

enum Kind : uint8_t { kPassSums = 0, kWholeSums = 1, kResolved = 2 };

void put_header(WireWriter& w, size_t index, const TileRect& rect, Kind kind, const TileStats& st,
                double seconds) {
  w.put(uint64_t(index));
  put_rect(w, rect);
  w.put(uint8_t(kind));
  w.put(st.rays);
  w.put(st.samples);
  w.put(st.nans);
  for (int v : {st.nan_x, st.nan_y, st.nan_s}) w.put(int32_t(v));
  w.put(seconds);
}

template <class T>
std::vector<T> get_sized(WireReader& r, size_t expected) {
  std::vector<T> v;
  r.get_array(v);
  if (v.size() != expected)
    throw std::runtime_error("a resolved tile's layers do not fit its pixels");
  return v;
}

// A resolved tile's planes, each as many values as its layer (among the head's) and encoding
// take over `rect`.
ResolvedTile get_resolved(WireReader& r, size_t index, const TileRect& rect,
                          const std::vector<LayerRequest>& plan, const std::vector<Aov>& aovs) {
  const std::vector<LayerSpec> layers = render_layers(aovs);
  ResolvedTile t;
  t.index = index;
  for (const LayerRequest& q : plan) {
    const auto layer = std::find_if(layers.begin(), layers.end(),
                                    [&](const LayerSpec& l) { return l.name == q.layer; });
    if (layer == layers.end()) throw std::runtime_error("a resolved tile of another layer");
    const size_t n = rect.pixels() * values_per_pixel(*layer, q.encoding);
    Plane& p = t.planes.emplace_back();
    if (q.encoding == Encoding::Srgb8)
      p.u8 = get_sized<unsigned char>(r, n);
    else
      p.f32 = get_sized<float>(r, n);
  }
  return t;
}

}  // namespace

std::vector<char> encode_result(size_t index, const TileBuffer& tile, bool whole,
                                const std::vector<uint8_t>& mask, const TileStats& st,
                                double seconds) {
  WireWriter w;
  put_header(w, index, tile.rect(), whole ? kWholeSums : kPassSums, st, seconds);
  put_sums(w, tile, whole ? std::vector<uint8_t>() : mask);
  return std::move(w.bytes());
}

std::vector<char> encode_resolved(const ResolvedTile& tile, const TileRect& rect,
                                  const TileStats& st, double seconds) {
  WireWriter w;
  put_header(w, tile.index, rect, kResolved, st, seconds);
  for (const Plane& p : tile.planes)  // (the one vector of its encoding: a count and the values)
    if (p.f32.empty())
      w.put_array(p.u8.data(), p.u8.size());
    else
      w.put_array(p.f32.data(), p.f32.size());
  return std::move(w.bytes());
}

size_t result_index(const char* data, size_t size) {
  WireReader r(data, size);
  return r.get<uint64_t>();
}

FarmResult decode_result(const char* data, size_t size, const std::vector<Aov>& aovs,
                         const FarmTile& sent, const std::vector<uint8_t>& mask) {
  WireReader r(data, size);
  FarmResult out;
  out.index = r.get<uint64_t>();
  const TileRect rect = get_rect(r);
  const auto kind = Kind(r.get<uint8_t>());
  out.stats.rays = r.get<uint64_t>();
  out.stats.samples = r.get<uint64_t>();
  out.stats.nans = r.get<uint64_t>();
  out.stats.nan_x = r.get<int32_t>();
  out.stats.nan_y = r.get<int32_t>();
  out.stats.nan_s = r.get<int32_t>();
  out.seconds = r.get<double>();
  const TileRect& t = sent.rect;
  if (out.index != sent.index || t.x0 != rect.x0 || t.y0 != rect.y0 || t.x1 != rect.x1 ||
      t.y1 != rect.y1)
    throw std::runtime_error("a result for another tile");
  const Kind expected = !sent.whole ? kPassSums : sent.plan ? kResolved : kWholeSums;
  if (kind != expected) throw std::runtime_error("a result of another kind of tile");
  if (kind == kResolved) {
    out.resolved = get_resolved(r, out.index, rect, *sent.plan, aovs);
  } else {
    std::vector<PixelSum> sums;
    std::vector<float> aov;
    r.get_array(sums);
    r.get_array(aov);
    if (kind == kWholeSums) {
      out.tile = std::make_unique<TileBuffer>(rect, aovs);
      scatter(sums, aov, {}, *out.tile);
    } else {
      scatter(sums, aov, mask, *sent.sums);
    }
  }
  if (!r.done()) throw std::runtime_error("a result message with bytes left over");
  return out;
}

}  // namespace anamorph::dist
