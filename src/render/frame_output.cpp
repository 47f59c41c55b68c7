#include "render/frame_output.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace anamorph {

namespace fs = std::filesystem;

ResolvedTile resolve(size_t index, const TileBuffer& tile, bool png, bool exr) {
  ResolvedTile out;
  out.index = index;
  const TileRect& r = tile.rect();
  const size_t n = r.pixels(), nf = tile.aov_floats();
  if (png) out.rgba8.resize(n * 4);
  if (exr) out.rgba.resize(n * 4), out.aov.resize(n * nf);
  const size_t w = size_t(r.x1 - r.x0);
  std::vector<float> row(w * 4);
  size_t i = 0;
  for (int y = r.y0; y < r.y1; ++y, i += w) {
    for (int x = r.x0; x < r.x1; ++x) tile.beauty_rgba(x, y, &row[size_t(x - r.x0) * 4]);
    if (png) encode_rgba8(row.data(), w, &out.rgba8[i * 4]);
    if (!exr) continue;
    std::copy(row.begin(), row.end(), out.rgba.begin() + ptrdiff_t(i * 4));
    if (nf)
      for (int x = r.x0; x < r.x1; ++x)
        tile.aov_values(x, y, &out.aov[(i + size_t(x - r.x0)) * nf]);
  }
  return out;
}

struct FrameOutput::Strip {
  int rows = 0;
  int received = 0;
  std::vector<unsigned char> rgba8;
  std::vector<float> rgba;
  std::vector<std::vector<float>> layers;  // per AOV, interleaved
  PngStream::Band band;
};

FrameOutput::FrameOutput(const FrameOutputSpec& spec)
    : spec_(spec),
      grid_(spec.width, spec.height, spec.tile_size),
      aov_floats_(aov_floats(spec.aovs)),
      added_(grid_.count(), 0) {
  if (!spec.png.empty())
    png_ = std::make_unique<PngStream>(spec.png, spec.width, spec.height, spec.metadata);
  if (!spec.exr.empty()) {
    std::vector<LayerSpec> layers{{"", {"R", "G", "B", "A"}}};
    for (Aov a : spec.aovs) layers.push_back({aov_info(a).name, aov_info(a).channels});
    exr_ = std::make_unique<ExrStream>(spec.exr, spec.width, spec.height, layers, spec.metadata);
  }
}

FrameOutput::~FrameOutput() = default;

size_t FrameOutput::tiles_added() const {
  const std::lock_guard<std::mutex> lock(mu_);
  return size_t(std::count(added_.begin(), added_.end(), 1));
}

std::unique_ptr<FrameOutput::Strip> FrameOutput::new_strip(int rows) const {
  auto s = std::make_unique<Strip>();
  s->rows = rows;
  const size_t n = size_t(spec_.width) * size_t(rows);
  if (png_) s->rgba8.resize(n * 4);
  if (exr_) {
    s->rgba.resize(n * 4);
    for (Aov a : spec_.aovs) s->layers.emplace_back(n * aov_info(a).channels.size());
  }
  return s;
}

// Row by row into the strip; AOV values split into their layers.
void FrameOutput::copy_into(Strip& s, const ResolvedTile& t, const TileRect& r) const {
  const size_t W = size_t(spec_.width), tw = size_t(r.width());
  for (int y = 0; y < r.height(); ++y) {
    const size_t src = size_t(y) * tw, dst = size_t(y) * W + size_t(r.x0);
    if (png_) std::memcpy(&s.rgba8[dst * 4], &t.rgba8[src * 4], tw * 4);
    if (!exr_) continue;
    std::memcpy(&s.rgba[dst * 4], &t.rgba[src * 4], tw * 4 * sizeof(float));
    if (aov_floats_ == 0) continue;  // (t.aov is empty: no element to point at)
    for (size_t x = 0; x < tw; ++x) {
      const float* v = &t.aov[(src + x) * aov_floats_];
      for (size_t l = 0; l < spec_.aovs.size(); ++l) {
        const size_t nc = aov_info(spec_.aovs[l]).channels.size();
        std::copy(v, v + nc, &s.layers[l][(dst + x) * nc]);
        v += nc;
      }
    }
  }
}

void FrameOutput::add(ResolvedTile t) {
  const TileRect r = grid_.rect(t.index);
  const int row = r.y0 / grid_.size;
  std::unique_ptr<Strip> done;
  {
    const std::lock_guard<std::mutex> lock(mu_);
    if (t.index >= added_.size() || added_[t.index])
      throw std::logic_error("FrameOutput: tile added twice");
    added_[t.index] = 1;
    std::unique_ptr<Strip>& s = strips_[row];
    if (!s) s = new_strip(r.height());
    copy_into(*s, t, r);
    if (++s->received == grid_.cols) {
      done = std::move(s);
      strips_.erase(row);
    }
  }
  if (done) write_ready(row, std::move(done));
}

void FrameOutput::write_ready(int row, std::unique_ptr<Strip> strip) {
  // Encoding needs no lock: strips are deflated in parallel, written in order.
  if (png_) {
    strip->band = PngStream::encode(strip->rgba8.data(), spec_.width, strip->rows);
    strip->rgba8 = {};
  }
  const std::lock_guard<std::mutex> lock(write_mu_);
  ready_[row] = std::move(strip);
  drain_ready();
}

void FrameOutput::append(const Strip& s) {
  if (png_) png_->append(s.band, s.rows);
  if (exr_) {
    std::vector<const float*> layers{s.rgba.data()};
    for (const auto& l : s.layers) layers.push_back(l.data());
    exr_->write_rows(layers, s.rows);
  }
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
  if (png_) png_->commit();
  if (exr_) exr_->commit();
}

// Missing tiles are resolved empty (transparent, AOVs "nothing"), row by row from the top so
// nothing waits in ready_. A row none of whose tiles arrived is the same strip every time:
// built and encoded once per height and appended as often as needed, so an interrupted
// 65536^2 render writes its image so far without encoding billions of empty pixels.
void FrameOutput::flush_all_missing() {
  std::map<int, std::unique_ptr<Strip>> empty;  // by height
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
      for (size_t i : missing)
        add(resolve(i, TileBuffer(grid_.rect(i), spec_.aovs), bool(png_), bool(exr_)));
      continue;
    }
    std::unique_ptr<Strip>& e = empty[grid_.rect(missing[0]).height()];
    if (!e) e = empty_strip(row);
    const std::lock_guard<std::mutex> lock(write_mu_);
    if (next_row_ != row) throw std::logic_error("FrameOutput: rows out of order");
    append(*e);
    drain_ready();
  }
}

std::unique_ptr<FrameOutput::Strip> FrameOutput::empty_strip(int row) const {
  const size_t first = size_t(row) * size_t(grid_.cols);
  std::unique_ptr<Strip> s = new_strip(grid_.rect(first).height());
  for (size_t i = first; i < first + size_t(grid_.cols); ++i) {
    const TileRect r = grid_.rect(i);
    copy_into(*s, resolve(i, TileBuffer(r, spec_.aovs), bool(png_), bool(exr_)), r);
  }
  if (png_) s->band = PngStream::encode(s->rgba8.data(), spec_.width, s->rows);
  s->rgba8 = {};
  return s;
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
  if (png_) png_->commit_as(with_suffix(spec_.png, suffix));
  if (exr_) exr_->commit_as(with_suffix(spec_.exr, suffix));
}

}  // namespace anamorph
