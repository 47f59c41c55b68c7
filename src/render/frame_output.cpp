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

void FrameOutput::add(ResolvedTile t) {
  const TileRect r = grid_.rect(t.index);
  const int row = r.y0 / grid_.size;
  const size_t W = size_t(spec_.width);
  std::unique_ptr<Strip> done;
  {
    const std::lock_guard<std::mutex> lock(mu_);
    if (t.index >= added_.size() || added_[t.index])
      throw std::logic_error("FrameOutput: tile added twice");
    added_[t.index] = 1;
    std::unique_ptr<Strip>& s = strips_[row];
    if (!s) {
      s = std::make_unique<Strip>();
      s->rows = r.height();
      const size_t n = W * size_t(s->rows);
      if (png_) s->rgba8.resize(n * 4);
      if (exr_) {
        s->rgba.resize(n * 4);
        for (Aov a : spec_.aovs) s->layers.emplace_back(n * aov_info(a).channels.size());
      }
    }
    // Row by row into the strip; AOV values split into their layers.
    const size_t tw = size_t(r.width());
    for (int y = 0; y < r.height(); ++y) {
      const size_t src = size_t(y) * tw, dst = size_t(y) * W + size_t(r.x0);
      if (png_) std::memcpy(&s->rgba8[dst * 4], &t.rgba8[src * 4], tw * 4);
      if (!exr_) continue;
      std::memcpy(&s->rgba[dst * 4], &t.rgba[src * 4], tw * 4 * sizeof(float));
      for (size_t x = 0; x < tw; ++x) {
        const float* v = &t.aov[(src + x) * aov_floats_];
        for (size_t l = 0; l < spec_.aovs.size(); ++l) {
          const size_t nc = aov_info(spec_.aovs[l]).channels.size();
          std::copy(v, v + nc, &s->layers[l][(dst + x) * nc]);
          v += nc;
        }
      }
    }
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
  for (auto it = ready_.find(next_row_); it != ready_.end(); it = ready_.find(next_row_)) {
    Strip& s = *it->second;
    if (png_) png_->append(s.band, s.rows);
    if (exr_) {
      std::vector<const float*> layers{s.rgba.data()};
      for (const auto& l : s.layers) layers.push_back(l.data());
      exr_->write_rows(layers, s.rows);
    }
    ready_.erase(it);
    ++next_row_;
  }
}

void FrameOutput::commit() {
  if (next_row_ != grid_.rows)
    throw std::logic_error("FrameOutput::commit: the frame is incomplete");
  if (png_) png_->commit();
  if (exr_) exr_->commit();
}

void FrameOutput::flush_all_missing() {
  std::vector<size_t> missing;
  {
    const std::lock_guard<std::mutex> lock(mu_);
    for (size_t i = 0; i < added_.size(); ++i)
      if (!added_[i]) missing.push_back(i);
  }
  for (size_t i : missing)
    add(resolve(i, TileBuffer(grid_.rect(i), spec_.aovs), bool(png_), bool(exr_)));
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
