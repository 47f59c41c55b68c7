// A frame's output files written as its tiles finish: tiles are resolved to the files' formats
// (8-bit sRGB for PNG, float layers for EXR), gathered into strips one tile row high, and each
// strip, once complete, is encoded and appended to the files in order and freed. Memory is the
// strips in flight, not the frame: a 16384^2 render holds a few strips of 16384 x 32 pixels.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "io/image_stream.h"
#include "render/tile_buffer.h"

namespace anamorph {

struct FrameOutputSpec {
  int width = 0, height = 0, tile_size = 32;
  std::vector<Aov> aovs;
  std::filesystem::path png;  // beauty as 8-bit sRGB RGBA, or empty
  std::filesystem::path exr;  // beauty and AOV layers as float, or empty
  std::map<std::string, std::string> metadata;
};

// One tile in the output's formats.
struct ResolvedTile {
  size_t index = 0;
  std::vector<unsigned char> rgba8;  // with a PNG: 4 per pixel
  std::vector<float> rgba;           // with an EXR: 4 per pixel
  std::vector<float> aov;            // with an EXR: aov_floats() per pixel, in aovs order
};
ResolvedTile resolve(size_t index, const TileBuffer& tile, bool png, bool exr);

class FrameOutput {
 public:
  explicit FrameOutput(const FrameOutputSpec& spec);
  ~FrameOutput();
  const FrameOutputSpec& spec() const { return spec_; }
  const TileGrid& grid() const { return grid_; }
  // A finished tile, from any thread. Each tile once.
  void add(ResolvedTile tile);
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
  struct Strip;
  std::unique_ptr<Strip> new_strip(int rows) const;
  void copy_into(Strip& s, const ResolvedTile& t, const TileRect& r) const;
  std::unique_ptr<Strip> empty_strip(int row) const;
  void write_ready(int row, std::unique_ptr<Strip> strip);
  void append(const Strip& s);  // the next strip from the top; write_mu_ held
  void drain_ready();           // write_mu_ held
  void flush_all_missing();

  FrameOutputSpec spec_;
  TileGrid grid_;
  size_t aov_floats_;
  std::unique_ptr<PngStream> png_;
  std::unique_ptr<ExrStream> exr_;
  mutable std::mutex mu_;  // strips_, added_
  std::map<int, std::unique_ptr<Strip>> strips_;
  std::vector<uint8_t> added_;
  std::mutex write_mu_;  // the files, next_row_, ready_
  int next_row_ = 0;
  std::map<int, std::unique_ptr<Strip>> ready_;
};

}  // namespace anamorph
