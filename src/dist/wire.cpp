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

}  // namespace

std::vector<char> encode_work(const FarmTile& t) {
  WireWriter w;
  const TileRect& rect = t.rect;
  w.put(uint64_t(t.index));
  put_rect(w, rect);
  w.put(uint8_t(t.whole));
  if (!t.whole) {
    w.put(t.range.begin);
    w.put(t.range.end);
    w.put(t.range.footprint);
    const auto& s = t.sums->sums();
    const auto& a = t.sums->aov_sums();
    w.put_array(s.data(), s.size());
    w.put_array(a.data(), a.size());
    std::vector<uint8_t> active;
    if (t.range.active) {
      active.reserve(rect.pixels());
      for (int y = rect.y0; y < rect.y1; ++y) {
        const auto row = t.range.active->begin() + ptrdiff_t(y) * t.image_width;
        active.insert(active.end(), row + rect.x0, row + rect.x1);
      }
    }
    w.put_array(active.data(), active.size());
  }
  return std::move(w.bytes());
}

WorkMessage decode_work(const char* data, size_t size) {
  WireReader r(data, size);
  WorkMessage m;
  m.index = r.get<uint64_t>();
  m.rect = get_rect(r);
  m.whole = r.get<uint8_t>() != 0;
  if (!m.whole) {
    m.begin = r.get<uint32_t>();
    m.end = r.get<uint32_t>();
    m.footprint = r.get<double>();
    r.get_array(m.sums);
    r.get_array(m.aov);
    r.get_array(m.active);
    if (m.sums.size() != m.rect.pixels() ||
        (!m.active.empty() && m.active.size() != m.rect.pixels()))
      throw std::runtime_error("a tile's sums do not fit its rectangle");
  }
  if (!r.done()) throw std::runtime_error("a work message with bytes left over");
  return m;
}

std::vector<char> encode_result(size_t index, const TileBuffer& tile, const TileStats& st,
                                double seconds) {
  WireWriter w;
  w.put(uint64_t(index));
  put_rect(w, tile.rect());
  w.put(st.rays);
  w.put(st.samples);
  w.put(st.nans);
  for (int v : {st.nan_x, st.nan_y, st.nan_s}) w.put(int32_t(v));
  w.put(seconds);
  w.put_array(tile.sums().data(), tile.sums().size());
  w.put_array(tile.aov_sums().data(), tile.aov_sums().size());
  return std::move(w.bytes());
}

FarmResult decode_result(const char* data, size_t size, const std::vector<Aov>& aovs) {
  WireReader r(data, size);
  FarmResult out;
  out.index = r.get<uint64_t>();
  const TileRect rect = get_rect(r);
  out.stats.rays = r.get<uint64_t>();
  out.stats.samples = r.get<uint64_t>();
  out.stats.nans = r.get<uint64_t>();
  out.stats.nan_x = r.get<int32_t>();
  out.stats.nan_y = r.get<int32_t>();
  out.stats.nan_s = r.get<int32_t>();
  out.seconds = r.get<double>();
  out.tile = std::make_unique<TileBuffer>(rect, aovs);
  r.get_array(out.tile->sums());
  r.get_array(out.tile->aov_sums());
  if (out.tile->sums().size() != rect.pixels() ||
      out.tile->aov_sums().size() != rect.pixels() * out.tile->aov_floats())
    throw std::runtime_error("a tile's sums do not fit its rectangle");
  if (!r.done()) throw std::runtime_error("a result message with bytes left over");
  return out;
}

}  // namespace anamorph::dist
