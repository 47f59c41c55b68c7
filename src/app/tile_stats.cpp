#include "app/tile_stats.h"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <thread>

#include "app/common.h"
#include "io/image_io.h"
#include "render/tile_buffer.h"
#include "scene/scene_schema.h"

namespace anamorph::app {

void write_tile_stats(const std::filesystem::path& file, const Scene& scene, double frame,
                      int threads, const RenderStats& st, std::vector<TileTiming> tiles) {
  const RenderSettings& rs = scene.render;
  const TileGrid grid(rs.width, rs.height, rs.tile_size);
  std::sort(tiles.begin(), tiles.end(), [](const TileTiming& a, const TileTiming& b) {
    return a.pass != b.pass ? a.pass < b.pass : a.index < b.index;
  });
  nlohmann::json j;
  j["anamorph"] = ANAMORPH_VERSION;
  j["command"] = command_line();
  j["scene"] = scene.path;
  j["frame"] = frame;
  j["width"] = rs.width;
  j["height"] = rs.height;
  j["tile_size"] = grid.size;
  j["tiles_total"] = grid.count();
  j["threads"] = threads > 0 ? threads : int(std::thread::hardware_concurrency());
  j["integrator"] = std::string(rs.shown());
  j["seconds"] = st.seconds;
  j["samples"] = st.samples;
  j["rays"] = st.rays;
  j["cancelled"] = st.cancelled;
  j["time_limited"] = st.time_limited;
  nlohmann::json list = nlohmann::json::array();
  for (const TileTiming& t : tiles) {
    const TileRect r = grid.rect(t.index);
    list.push_back({{"index", t.index},
                    {"x", r.x0},
                    {"y", r.y0},
                    {"w", r.x1 - r.x0},
                    {"h", r.y1 - r.y0},
                    {"pass", t.pass},
                    {"start", t.start},
                    {"seconds", t.seconds},
                    {"samples", t.samples},
                    {"rays", t.rays},
                    {"rank", t.rank},
                    {"pass_samples", t.pass_samples}});
  }
  j["tiles"] = std::move(list);
  const std::string text = j.dump(1) + "\n";
  write_file_atomic(file, text.data(), text.size());
}

}  // namespace anamorph::app
