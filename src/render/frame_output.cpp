#include "render/frame_output.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "math/parallel.h"

namespace anamorph {

namespace fs = std::filesystem;

namespace {

// The index of `name` among `layers`, or throws std::invalid_argument.
size_t layer_index(const std::vector<LayerSpec>& layers, const std::string& name) {
  for (size_t i = 0; i < layers.size(); ++i)
    if (layers[i].name == name) return i;
  throw std::invalid_argument(fmt::format("no layer '{}' in this render", name));
}

void check_request(const std::vector<LayerSpec>& layers, const LayerRequest& r) {
  if (layer_index(layers, r.layer) != 0 && r.encoding == Encoding::Srgb8)
    throw std::invalid_argument(
        fmt::format("8-bit sRGB is for the beauty's colour, not the layer '{}'", r.layer));
}

void add_once(std::vector<LayerRequest>& plan, const LayerRequest& r) {
  if (std::find(plan.begin(), plan.end(), r) == plan.end()) plan.push_back(r);
}

// The beauty's requests of a tile row: straight RGBA floats of the row, then each encoding.
void resolve_beauty_row(const TileBuffer& tile, int y, std::vector<float>& row,
                        const std::vector<LayerRequest>& plan, size_t first, ResolvedTile& out) {
  const TileRect& r = tile.rect();
  const size_t w = size_t(r.width());
  for (int x = r.x0; x < r.x1; ++x) tile.beauty_rgba(x, y, &row[size_t(x - r.x0) * 4]);
  for (size_t i = 0; i < plan.size(); ++i) {
    if (!plan[i].layer.empty()) continue;
    if (plan[i].encoding == Encoding::Srgb8)
      encode_rgba8(row.data(), w, &out.planes[i].u8[first * 4]);
    else
      std::copy(row.begin(), row.end(), out.planes[i].f32.begin() + ptrdiff_t(first * 4));
  }
}

}  // namespace

std::vector<LayerSpec> render_layers(const std::vector<Aov>& aovs) {
  std::vector<LayerSpec> layers{{"", {"R", "G", "B", "A"}}};
  for (Aov a : aovs) layers.push_back({aov_info(a).name, aov_info(a).channels});
  return layers;
}

std::vector<LayerRequest> output_plan(const std::vector<fs::path>& files,
                                      const std::vector<Aov>& aovs) {
  const std::vector<LayerSpec> layers = render_layers(aovs);
  std::vector<LayerRequest> plan;
  for (const fs::path& f : files)
    for (const LayerRequest& r : sink_kind(f).takes(layers)) add_once(plan, r);
  return plan;
}

std::string describe_plan(const std::vector<LayerRequest>& plan) {
  std::string s;
  for (const LayerRequest& r : plan)
    s += fmt::format("{}{}{}{}", s.empty() ? "" : " ", r.layer, r.layer.empty() ? "" : ":",
                     encoding_name(r.encoding));
  return s;
}

ResolvedTile resolve(size_t index, const TileBuffer& tile, const std::vector<LayerRequest>& plan) {
  const std::vector<LayerSpec> layers = render_layers(tile.aovs());
  ResolvedTile out;
  out.index = index;
  const TileRect& r = tile.rect();
  const size_t n = r.pixels(), w = size_t(r.width());
  bool beauty = false;
  for (const LayerRequest& q : plan) {
    check_request(layers, q);
    const size_t values = n * values_per_pixel(layers[layer_index(layers, q.layer)], q.encoding);
    Plane& p = out.planes.emplace_back();
    if (q.encoding == Encoding::Srgb8)
      p.u8.resize(values);
    else
      p.f32.resize(values);
    beauty = beauty || q.layer.empty();
  }
  std::vector<float> row(w * 4);
  for (int y = r.y0; y < r.y1; ++y) {
    const size_t first = size_t(y - r.y0) * w;
    if (beauty) resolve_beauty_row(tile, y, row, plan, first, out);
    for (size_t i = 0; i < plan.size(); ++i) {
      if (plan[i].layer.empty()) continue;
      const size_t layer = layer_index(layers, plan[i].layer) - 1,
                   nc = layers[layer + 1].channels.size();
      for (int x = r.x0; x < r.x1; ++x)
        tile.aov_layer_values(x, y, layer, &out.planes[i].f32[(first + size_t(x - r.x0)) * nc]);
    }
  }
  return out;
}

void resolve_rgba8(const TileBuffer& tile, unsigned char* out, size_t stride) {
  constexpr int kChunk = 64;  // pixels resolved to floats, then encoded, while in L1
  float px[kChunk * 4];
  const TileRect& r = tile.rect();
  for (int y = r.y0; y < r.y1; ++y, out += stride)
    for (int x = r.x0; x < r.x1; x += kChunk) {
      const int n = std::min(kChunk, r.x1 - x);
      for (int i = 0; i < n; ++i) tile.beauty_rgba(x + i, y, &px[i * 4]);
      encode_rgba8(px, size_t(n), out + size_t(x - r.x0) * 4);
    }
}

bool fits(const ResolvedTile& t, const std::vector<LayerRequest>& plan, const TileRect& rect,
          const std::vector<Aov>& aovs) {
  const std::vector<LayerSpec> layers = render_layers(aovs);
  if (t.planes.size() != plan.size()) return false;
  for (size_t i = 0; i < plan.size(); ++i) {
    const LayerSpec* layer = nullptr;
    for (const LayerSpec& l : layers)
      if (l.name == plan[i].layer) layer = &l;
    if (!layer) return false;
    const size_t values = rect.pixels() * values_per_pixel(*layer, plan[i].encoding);
    const bool srgb8 = plan[i].encoding == Encoding::Srgb8;
    if (t.planes[i].u8.size() != (srgb8 ? values : 0) ||
        t.planes[i].f32.size() != (srgb8 ? 0 : values))
      return false;
  }
  return true;
}

// One tile row of the image for every sink: sinks[s] holds sink s's planes.
struct FrameOutput::Row {
  int received = 0;
  std::vector<Strip> sinks;
};

FrameOutput::FrameOutput(const FrameOutputSpec& spec, std::vector<std::unique_ptr<ImageSink>> more)
    : spec_(spec),
      grid_(spec.width, spec.height, spec.tile_size),
      layers_(render_layers(spec.aovs)),
      added_(grid_.count(), 0) {
  for (const fs::path& f : spec.files) {
    sinks_.push_back(make_file_sink({f, spec.width, spec.height, layers_, spec.metadata}));
    sink_files_.push_back(f);
  }
  for (auto& s : more) sinks_.push_back(std::move(s)), sink_files_.emplace_back();
  for (const auto& s : sinks_) {
    std::vector<size_t>& map = sink_plan_.emplace_back();
    for (const LayerRequest& r : s->requests()) {
      check_request(layers_, r);
      add_once(plan_, r);
      map.push_back(size_t(std::find(plan_.begin(), plan_.end(), r) - plan_.begin()));
    }
  }
  for (const LayerRequest& r : plan_)
    plan_values_.push_back(values_per_pixel(layers_[layer_index(layers_, r.layer)], r.encoding));
}

FrameOutput::~FrameOutput() = default;

size_t FrameOutput::tiles_added() const {
  const std::lock_guard<std::mutex> lock(mu_);
  return size_t(std::count(added_.begin(), added_.end(), 1));
}

std::unique_ptr<FrameOutput::Row> FrameOutput::new_row(int rows) const {
  auto row = std::make_unique<Row>();
  const size_t n = size_t(spec_.width) * size_t(rows);
  for (const std::vector<size_t>& map : sink_plan_) {
    Strip& s = row->sinks.emplace_back();
    s.rows = rows;
    for (size_t p : map) {
      Plane& plane = s.planes.emplace_back();
      if (plan_[p].encoding == Encoding::Srgb8)
        plane.u8.resize(n * plan_values_[p]);
      else
        plane.f32.resize(n * plan_values_[p]);
    }
  }
  return row;
}

// Row by row of the tile into each sink's planes.
void FrameOutput::copy_into(Row& row, const ResolvedTile& t, const TileRect& r) const {
  const size_t W = size_t(spec_.width), tw = size_t(r.width());
  for (size_t s = 0; s < sinks_.size(); ++s)
    for (size_t k = 0; k < sink_plan_[s].size(); ++k) {
      const size_t p = sink_plan_[s][k], nv = plan_values_[p];
      const Plane& from = t.planes[p];
      Plane& to = row.sinks[s].planes[k];
      for (int y = 0; y < r.height(); ++y) {
        const size_t src = size_t(y) * tw * nv, dst = (size_t(y) * W + size_t(r.x0)) * nv;
        if (plan_[p].encoding == Encoding::Srgb8)
          std::memcpy(&to.u8[dst], &from.u8[src], tw * nv);
        else
          std::memcpy(&to.f32[dst], &from.f32[src], tw * nv * sizeof(float));
      }
    }
}

void FrameOutput::add(ResolvedTile t) {
  const TileRect r = grid_.rect(t.index);
  const int index = r.y0 / grid_.size;
  if (!fits(t, plan_, r, spec_.aovs))
    throw std::logic_error("FrameOutput: a tile resolved to another plan");
  std::unique_ptr<Row> done;
  {
    const std::lock_guard<std::mutex> lock(mu_);
    if (t.index >= added_.size() || added_[t.index])
      throw std::logic_error("FrameOutput: tile added twice");
    added_[t.index] = 1;
    std::unique_ptr<Row>& row = rows_[index];
    if (!row) row = new_row(r.height());
    copy_into(*row, t, r);
    if (++row->received == grid_.cols) {
      done = std::move(row);
      rows_.erase(index);
    }
  }
  if (done) write_ready(index, std::move(done));
}

void FrameOutput::add_tiles(const Film& film) {
  parallel_for_each(0, int(grid_.count()), [&](int i) {
    if (const TileBuffer* t = film.tile_if_any(size_t(i))) add(resolve(size_t(i), *t, plan_));
  });
}

void FrameOutput::prepare(Row& row) const {
  for (size_t s = 0; s < sinks_.size(); ++s) sinks_[s]->prepare(row.sinks[s]);
}

void FrameOutput::write_ready(int index, std::unique_ptr<Row> row) {
  prepare(*row);  // without a lock: strips are encoded in parallel, written in order
  const std::lock_guard<std::mutex> lock(write_mu_);
  ready_[index] = std::move(row);
  drain_ready();
}

void FrameOutput::append(const Row& row) {
  for (size_t s = 0; s < sinks_.size(); ++s) sinks_[s]->append(row.sinks[s]);
  ++next_row_;
}

void FrameOutput::drain_ready() {
  for (auto it = ready_.find(next_row_); it != ready_.end(); it = ready_.find(next_row_)) {
    append(*it->second);
    ready_.erase(it);
  }
}

void FrameOutput::commit() {
  if (next_row_ != grid_.rows)
    throw std::logic_error("FrameOutput::commit: the frame is incomplete");
  for (auto& s : sinks_) s->commit();
}

// Missing tiles are resolved empty (transparent, AOVs "nothing"), row by row from the top so
// nothing waits in ready_. A row none of whose tiles arrived is the same strip every time:
// built and prepared once per height and appended as often as needed, so an interrupted
// 65536^2 render writes its image so far without encoding billions of empty pixels.
void FrameOutput::flush_all_missing() {
  std::map<int, std::unique_ptr<Row>> empty;  // by height
  for (int row = 0; row < grid_.rows; ++row) {
    std::vector<size_t> missing;
    bool whole_row = false;
    {
      const std::lock_guard<std::mutex> lock(mu_);
      for (int c = 0; c < grid_.cols; ++c) {
        const size_t i = size_t(row) * size_t(grid_.cols) + size_t(c);
        if (!added_[i]) missing.push_back(i);
      }
      whole_row = missing.size() == size_t(grid_.cols);
      if (whole_row)
        for (size_t i : missing) added_[i] = 1;
    }
    if (!whole_row) {
      for (size_t i : missing) add(resolve(i, TileBuffer(grid_.rect(i), spec_.aovs), plan_));
      continue;
    }
    std::unique_ptr<Row>& e = empty[grid_.rect(missing[0]).height()];
    if (!e) e = empty_row(row);
    const std::lock_guard<std::mutex> lock(write_mu_);
    if (next_row_ != row) throw std::logic_error("FrameOutput: rows out of order");
    append(*e);
    drain_ready();
  }
}

std::unique_ptr<FrameOutput::Row> FrameOutput::empty_row(int row) const {
  const size_t first = size_t(row) * size_t(grid_.cols);
  std::unique_ptr<Row> r = new_row(grid_.rect(first).height());
  for (size_t i = first; i < first + size_t(grid_.cols); ++i) {
    const TileRect t = grid_.rect(i);
    copy_into(*r, resolve(i, TileBuffer(t, spec_.aovs), plan_), t);
  }
  prepare(*r);
  return r;
}

fs::path FrameOutput::with_suffix(const fs::path& p, const std::string& suffix) {
  fs::path out = p;
  out.replace_filename(p.stem().string() + suffix + p.extension().string());
  return out;
}

void FrameOutput::commit_incomplete() {
  flush_all_missing();
  commit();
}

void FrameOutput::commit_partial(const std::string& suffix) {
  flush_all_missing();
  for (size_t s = 0; s < sinks_.size(); ++s)
    if (sink_files_[s].empty())
      sinks_[s]->commit();
    else
      sinks_[s]->commit_as(with_suffix(sink_files_[s], suffix));
}

}  // namespace anamorph
