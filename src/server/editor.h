// The editor's state behind the API: the document, the scene loaded from it (validated on every
// edit, with the scene reader's own messages), the live preview, picking through the camera,
// saving, and the final render.
#pragma once

#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "camera/coins.h"
#include "io/confined_folder.h"
#include "io/read_file.h"
#include "math/vec.h"
#include "params/param_schema.h"
#include "server/document.h"
#include "server/preview.h"
#include "solve/camera_solve.h"

namespace anamorph::server {

// Why an edit was refused: 400 (a bad key or value; `key` names it) or 409 (made against an older
// version than the document's).
struct EditError {
  int status = 400;
  std::string message;
  std::string key;
};

struct EditOutcome {
  std::optional<EditError> error;
  int64_t version = 0;
  std::vector<std::string> warnings;
};

// What the final render needs, given to the renderer the server was started with (the same code
// as `anamorph render`): the document's text and where to write.
struct FinalRenderJob {
  std::string text;
  std::filesystem::path scene_file;  // where relative paths resolve
  double frame = 0;
  std::vector<std::filesystem::path> files;  // each in the format its name says
  std::function<void(double fraction, double seconds)> progress;
  const std::atomic<bool>* cancel = nullptr;  // set: stop as soon as possible (throw)
};
using FinalRenderer = std::function<void(const FinalRenderJob&)>;  // throws on failure

struct PickResult {
  bool ray = false, hit = false;
  Vec3 position, normal;
  double distance = 0;
  uint32_t object = 0;
  Bounds3 box;  // the hit object's world bounding box (empty: unbounded, an infinite plane)
};

class Editor {
 public:
  // Loads the scene (throws SceneError / LoadError as `anamorph render` would).
  Editor(std::filesystem::path scene_file, FinalRenderer final_renderer);
  ~Editor();

  const std::filesystem::path& scene_file() const { return doc_.file(); }
  const std::filesystem::path& folder() const { return folder_.path(); }
  Preview& preview() { return preview_; }

  // The document's state: version, text, tree as JSON, undo/redo, frame, warnings.
  Json state() const;
  EditOutcome edit(std::span<const KeyEdit> edits, int64_t base_version);
  EditOutcome undo();
  EditOutcome redo();
  // The animation frame shown (the scene's [[animate]] keys evaluated there).
  EditOutcome set_frame(double frame);

  // The surface under image position (u, v) of the document version `version` (or newer).
  std::optional<PickResult> pick(Vec2 uv, int64_t version);
  // Every image position whose ray passes through `p`, with the camera shown.
  std::optional<std::vector<Vec2>> project(const Vec3& p, int64_t version);

  // The coins as the camera shown sees them: (uc, vc), radius, strength, ... per site.
  std::optional<std::vector<CoinSite>> coins(int64_t version);
  // How much the camera shown magnifies each of w x h image positions (pixel centers), row by
  // row: the linear scale sqrt(A_ref / A) of the ray footprint A = |dP/du x dP/dv| (P = org +
  // t dir, the beam where it meets the scene) against the same camera without its coins, or,
  // without coins, against the image's mean footprint. > 1 magnifies; NaN where there is no ray.
  std::optional<std::vector<float>> magnification(int w, int h, int64_t version);

  // The camera's rays at nu x nv image positions (cell centers, row by row) and the scene's
  // objects as world-space boxes (infinite planes left out): the 3D overview of the image
  // surface, its rays and the scene.
  struct RayOverview {
    int nu = 0, nv = 0;
    std::vector<Vec3> org, dir;
    std::vector<uint8_t> valid;
    std::vector<Bounds3> boxes;
  };
  std::optional<RayOverview> ray_overview(int nu, int nv, int64_t version);

  // The camera solved for goals (the editor's pin tool, docs/solve.md "In the editor"): the
  // document at `version` with `constraints` and `free` (TOML text of the arrays
  // [[camera.constraint]] and [[camera.free]], which replace the scene's own), solved from the
  // document's values with the library behind `anamorph solve`; with `apply`, the solved values
  // become the document's next version (the goals are not written). Only the view is loaded:
  // pins name points, not objects.
  struct SolveRequest {
    std::string constraints, free;
    int64_t version = 0;
    int max_iterations = 0;  // 0: the scene's [camera.solve]
    bool apply = false;
  };
  struct SolveOutcome {
    EditOutcome edit;  // its error: the goals or the document refused; else the applied version
    solve::SolveReport report;
    double seconds = 0;  // the solve's own time
  };
  SolveOutcome solve(const SolveRequest& req);

  // Writes the document to `name` (a file name in the scene's folder; "" = the scene file
  // itself), through the folder's descriptor (io/confined_folder.h). Errors (a path, a symbolic
  // link, not .toml, a name too long) are returned.
  struct SaveOutcome {
    std::optional<std::string> error;
    bool normalized = false;  // written whole (comments and layout not kept)
  };
  SaveOutcome save(const std::string& name);

  // The final render of the current document into a private folder, one frame (the one shown)
  // or, with `frames`, a sequence (what `anamorph render --frames A:B` writes); status as JSON.
  struct RenderRequest {
    // Output sink kinds by name (io/image_sink.h), one file each; none: the first kind.
    std::vector<std::string> formats;
    std::optional<std::pair<int, int>> frames;
  };
  // Why not when one is running; std::invalid_argument for a request that names no format, an
  // unknown one or bad frames.
  std::optional<std::string> start_render(const RenderRequest& req);
  Json render_status() const;
  // Stops the final render at its next packet (its state becomes "cancelled"); false when none
  // is running.
  bool cancel_render();
  // A finished file by its extension without the dot ("png"), of frame `frame` of a sequence
  // (default its first).
  std::optional<std::filesystem::path> render_result(const std::string& ext,
                                                     std::optional<int> frame = {}) const;

 private:
  struct Render;
  void render_frames(FinalRenderJob job, const std::string& stem);
  std::unique_ptr<Scene> load(const toml::table& t, bool view_only,
                              std::vector<std::string>* warnings);
  EditOutcome show_new(const toml::table& next, const std::function<void()>& commit);
  std::optional<std::string> check_files(const toml::table& t) const;
  // The rule for what loads after the first may read (io/read_file.h).
  ReadConfinement confinement() const { return {&folder_, &trusted_, nullptr}; }

  ConfinedFolder folder_;          // opened once, when the server starts
  std::set<std::string> trusted_;  // the files the scene read then
  mutable std::mutex mu_;          // doc_, frame_, model_cameras_, the render's start
  Document doc_;
  double frame_ = 0;
  std::unique_ptr<Scene> models_;  // the model cameras of the geometry shown (load_view needs them)
  std::vector<std::string> warnings_;
  Preview preview_;
  FinalRenderer final_renderer_;
  std::unique_ptr<Render> render_;
};

}  // namespace anamorph::server
