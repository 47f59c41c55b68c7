// A frame's outputs written as its tiles finish. Each tile is resolved to the layers and
// encodings the sinks take (the plan: 8-bit sRGB for a PNG, floats for an EXR; io/image_sink.h),
// gathered into strips one tile row high, and each strip, once complete, is handed to every sink
// (prepared on the thread that completed it, appended in order from the top) and freed. Memory is
// the strips in flight, not the frame: a 16384^2 render holds a few strips of 16384 x 32 pixels.
// Nothing here knows a file format: the sinks do.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "io/image_sink.h"
#include "render/film.h"
#include "render/tile_buffer.h"

namespace anamorph {

struct FrameOutputSpec {
  int width = 0, height = 0, tile_size = 32;
  std::vector<Aov> aovs;
  // Each written by the sink kind its name chooses (io/image_sink.h: output_files() gives the
  // files an output name becomes).
  std::vector<std::filesystem::path> files;
  std::map<std::string, std::string> metadata;
};

// The layers of a render with these AOVs as sinks see them: the beauty RGBA (""), then each AOV.
std::vector<LayerSpec> render_layers(const std::vector<Aov>& aovs);
// What these files' sinks take of a render with these AOVs, each layer and encoding once, in the
// order first asked (the plan FrameOutput resolves tiles to), without opening the files.
std::vector<LayerRequest> output_plan(const std::vector<std::filesystem::path>& files,
                                      const std::vector<Aov>& aovs);
// "srgb8 float32 albedo:float32": a plan in a line (checkpoint identities).
std::string describe_plan(const std::vector<LayerRequest>& plan);

// One tile resolved to a plan: planes[i] holds plan[i] over the tile's rectangle.
struct ResolvedTile {
  size_t index = 0;
  std::vector<Plane> planes;
};
// Throws std::invalid_argument for a layer the tile does not sum or 8-bit colour of a layer
// other than the beauty.
ResolvedTile resolve(size_t index, const TileBuffer& tile, const std::vector<LayerRequest>& plan);
// The tile's beauty as 8-bit sRGB RGBA, the bytes resolve() gives for {"", Srgb8}, written
// straight into an image at `out` (the tile's top-left pixel; rows `stride` bytes apart): no
// planes allocated, nothing copied (`anamorph bench`'s frame).
void resolve_rgba8(const TileBuffer& tile, unsigned char* out, size_t stride);
// Whether `t` holds `plan` over `rect` (sizes of every plane), for tiles read back or received.
bool fits(const ResolvedTile& t, const std::vector<LayerRequest>& plan, const TileRect& rect,
          const std::vector<Aov>& aovs);

class FrameOutput {
 public:
  // A sink for each of the spec's files (by its kind), and `more` sinks besides (the editor's
  // preview).
  explicit FrameOutput(const FrameOutputSpec& spec,
                       std::vector<std::unique_ptr<ImageSink>> more = {});
  ~FrameOutput();
  const FrameOutputSpec& spec() const { return spec_; }
  const TileGrid& grid() const { return grid_; }
  // What every tile is resolved to: the sinks' requests, each once.
  const std::vector<LayerRequest>& plan() const { return plan_; }
  // A finished tile resolved to plan(), from any thread. Each tile once.
  void add(ResolvedTile tile);
  // Every tile `film` holds, resolved (in parallel).
  void add_tiles(const Film& film);
  size_t tiles_added() const;
  // Every tile added: the files appear under their names.
  void commit();
  // The image under the files' names with any tiles missing transparent (a time limit's image).
  void commit_incomplete();
  // The image so far (missing tiles transparent, AOVs "nothing") under each file's name with
  // `suffix` before the extension, e.g. "frame.partial.png".
  void commit_partial(const std::string& suffix);
  static std::filesystem::path with_suffix(const std::filesystem::path& p,
                                           const std::string& suffix);

 private:
  struct Row;  // a tile row's strips, one per sink
  std::unique_ptr<Row> new_row(int rows) const;
  void copy_into(Row& row, const ResolvedTile& t, const TileRect& r) const;
  std::unique_ptr<Row> empty_row(int row) const;
  void prepare(Row& row) const;
  void write_ready(int row, std::unique_ptr<Row> strips);
  void append(const Row& row);  // the next row from the top; write_mu_ held
  void drain_ready();           // write_mu_ held
  void flush_all_missing();

  FrameOutputSpec spec_;
  TileGrid grid_;
  std::vector<LayerSpec> layers_;
  std::vector<std::unique_ptr<ImageSink>> sinks_;
  std::vector<std::filesystem::path> sink_files_;  // per sink: its file, or empty
  std::vector<LayerRequest> plan_;
  std::vector<std::vector<size_t>> sink_plan_;  // per sink, per request: its index in plan_
  std::vector<size_t> plan_values_;             // per plan entry: values a pixel
  mutable std::mutex mu_;                       // rows_, added_
  std::map<int, std::unique_ptr<Row>> rows_;
  std::vector<uint8_t> added_;
  std::mutex write_mu_;  // the sinks, next_row_, ready_
  int next_row_ = 0;
  std::map<int, std::unique_ptr<Row>> ready_;
};

}  // namespace anamorph
