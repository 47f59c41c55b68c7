// The editor's live camera solve (the pin tool): the document with the page's goals, solved by
// src/solve (the library behind `anamorph solve`), the solution applied as an edit.
#include <chrono>

#include "scene/scene_loader.h"
#include "scene/toml_reader.h"
#include "server/editor.h"

namespace anamorph::server {

namespace {

EditError refused(std::string message, std::string key = {}) {
  return {400, std::move(message), std::move(key)};
}

}  // namespace

Editor::SolveOutcome Editor::solve(const SolveRequest& req) {
  std::lock_guard lock(mu_);
  SolveOutcome out;
  out.edit.version = doc_.version();
  if (req.version != doc_.version()) {
    out.edit.error = EditError{409,
                               "the scene changed (version " + std::to_string(doc_.version()) +
                                   ", the solve was asked of " + std::to_string(req.version) + ")",
                               ""};
    return out;
  }
  const auto t0 = std::chrono::steady_clock::now();
  try {
    const KeyEdit goals[] = {{"camera.constraint", req.constraints}, {"camera.free", req.free}};
    const toml::table with_goals = doc_.edited(goals);
    solve::SolveInput in;
    in.text = to_toml_text(with_goals);
    in.file = doc_.file();
    in.frame = frame_;
    in.explain = false;
    in.max_iterations = req.max_iterations;
    const ScopedReadConfinement confined(confinement());
    const Scene view = load_view_from_string(in.text, in.file, {}, frame_, *models_);
    in.loaded = &view;
    in.models = models_.get();
    out.report = solve::solve_camera(in);
  } catch (const SceneError& e) {
    out.edit.error = refused(e.message, e.key);
  } catch (const ParamError& e) {
    out.edit.error = refused(e.what(), e.key);
  } catch (const std::exception& e) {
    out.edit.error = refused(e.what());
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (out.edit.error || !req.apply) return out;
  std::vector<KeyEdit> edits;
  for (const auto& [key, text] : out.report.texts) edits.push_back({key, text});
  toml::table next;
  try {
    next = doc_.edited(edits);
  } catch (const SceneError& e) {
    out.edit.error = refused(e.message, e.key);
    return out;
  }
  out.edit = show_new(next, [&] { doc_.commit(std::move(next)); });
  return out;
}

}  // namespace anamorph::server
