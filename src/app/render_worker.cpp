// The MPI side of `anamorph render`: how frames are loaded (alike on the head and the workers, so
// every rank has the same scene) and a worker rank's loop.
#include "app/render_command.h"
#include "dist/worker.h"
#include "scene/scene_loader.h"
#include "scene/scene_pose.h"

namespace anamorph::app {

bool FrameScene::load_frame(const SceneOptions& o, const std::vector<std::string>& extra,
                            double frame, const std::vector<Aov>& aovs) {
  if (scene && animates_view_only(*scene)) {
    load_view_into(o, extra, frame, *scene);
    attach_next_frame(o, extra, aovs, *scene);
    return false;
  }
  if (scene && animates_view_and_pose(*scene)) {
    load_view_into(o, extra, frame, *scene);
    pose_scene(*scene, frame);
    attach_next_frame(o, extra, aovs, *scene);
    if (renderer) renderer->repose();
    return false;
  }
  renderer.reset();  // (it refers to the scene)
  scene = std::make_unique<Scene>(load(o, extra, frame));
  attach_next_frame(o, extra, aovs, *scene);
  return true;
}

std::unique_ptr<Renderer> make_renderer(const Scene& scene, const TileFarm* farm) {
  return farm ? std::make_unique<Renderer>(scene, Renderer::FarmOnly{})
              : std::make_unique<Renderer>(scene);
}

int serve_worker(const RenderSetup& s) {
  FrameScene current;
  return dist::serve_tiles(s.args.threads.value_or(0), s.aovs, [&](double frame) {
    if (current.load_frame(s.args.scene, s.extra, frame, s.aovs))
      current.renderer = std::make_unique<Renderer>(*current.scene);
    const RenderSettings& rs = current.scene->render;
    return dist::WorkerFrame{current.renderer.get(), rs.width, rs.height};
  });
}

}  // namespace anamorph::app
