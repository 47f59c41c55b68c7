// Rendering a scene given as TOML text into a film, for tests.
#pragma once

#include <string>
#include <vector>

#include "render/renderer.h"
#include "scene/scene_loader.h"

namespace anamorph::test {

struct Rendered {
  Scene scene;
  std::unique_ptr<Film> film;
  RenderStats stats;
};

inline Rendered render_text(const std::string& toml, const std::vector<std::string>& overrides = {},
                            int threads = 0, std::vector<Aov> aovs = {}) {
  Rendered r{load_scene_from_string(toml, "test.toml", overrides), nullptr, {}};
  const Renderer renderer(r.scene);
  r.film = std::make_unique<Film>(r.scene.render.width, r.scene.render.height, aovs);
  RenderOptions opt;
  opt.threads = threads;
  opt.aovs = aovs;
  r.stats = renderer.render(*r.film, opt);
  return r;
}

}  // namespace anamorph::test
