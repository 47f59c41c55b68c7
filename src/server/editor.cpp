#include "server/editor.h"

#include <fmt/format.h>

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "io/image_io.h"
#include "io/image_sink.h"
#include "scene/loaders.h"
#include "scene/scene_loader.h"
#include "scene/toml_reader.h"

namespace anamorph::server {

namespace fs = std::filesystem;

namespace {

Json toml_to_json(const toml::table& t) {
  std::ostringstream os;
  os << toml::json_formatter(t);
  return Json::parse(os.str());
}

EditError bad(std::string message, std::string key = {}) {
  return {400, std::move(message), std::move(key)};
}

// A request that is well formed but meets a document that cannot take it now (another tab has
// undone everything, or made an edit that cleared the redo list): 409, as a stale version is.
EditError conflict(std::string message) { return {409, std::move(message), {}}; }

// `p` is `folder` or inside it (both canonical, or as near as the file system allows).
bool inside(const fs::path& p, const fs::path& folder) {
  const fs::path rel = p.lexically_relative(folder);
  return !rel.empty() && *rel.begin() != "..";
}

// Every file a scene tree names (`include` and each `file` value), as written.
void files_named(const toml::node& n, std::string_view key, std::vector<std::string>* out) {
  if (const toml::table* t = n.as_table()) {
    for (const auto& [k, v] : *t) files_named(v, k.str(), out);
  } else if (const toml::array* a = n.as_array()) {
    for (const auto& e : *a) files_named(e, key, out);
  } else if (n.is_string() && (key == "file" || key == "include")) {
    out->push_back(*n.value<std::string>());
  }
}

// A new folder of this process's own (mkdtemp: created here, mode 0700; an existing one of the
// same name, made by someone else, is never taken over).
fs::path private_folder() {
  std::string name =
      (fs::temp_directory_path() / ("anamorph-serve-" + std::to_string(::getpid()) + "-XXXXXX"))
          .string();
  if (!::mkdtemp(name.data()))
    throw std::system_error(errno, std::generic_category(),
                            "cannot create a folder in " + fs::temp_directory_path().string());
  return name;
}

}  // namespace

struct Editor::Render {
  fs::path folder = private_folder();
  std::thread thread;
  mutable std::mutex mu;
  std::string state = "idle";  // idle, running, done, failed
  double fraction = 0, seconds = 0;
  std::string error;
  int64_t version = 0;
  std::vector<const SinkKind*> kinds;  // one file each per frame
  bool sequence = false;               // frames first..last as NAME_%04d (else one frame, NAME)
  int first = 0, last = 0, done_frames = 0;
  std::string file_name(const std::string& stem, std::optional<int> frame,
                        const std::string& ext) const;
  std::atomic<bool> cancel{false};
  ~Render() {
    cancel = true;  // (a server that stops does not wait for a long render)
    if (thread.joinable()) thread.join();
    std::error_code ec;
    fs::remove_all(folder, ec);
  }
};

namespace {

// The scene's folder with its symbolic links resolved, once: the folder the editor confines its
// files to, and the folder the scene's relative paths are read against.
fs::path scene_folder(const fs::path& scene_file) {
  std::error_code ec;
  const fs::path parent = fs::absolute(scene_file).parent_path();
  const fs::path folder = fs::canonical(parent, ec);
  return ec ? parent : folder;
}

}  // namespace

Editor::Editor(fs::path scene_file, FinalRenderer final_renderer)
    : folder_(scene_folder(scene_file)),
      doc_(folder_.path() / scene_file.filename()),
      final_renderer_(std::move(final_renderer)),
      render_(std::make_unique<Render>()) {
  std::vector<std::string> warnings;
  // The files this first load reads are the ones the user started the server with: later loads
  // read them as the command line would, and any other file only through the folder.
  const ScopedReadConfinement record({nullptr, nullptr, &trusted_});
  std::unique_ptr<Scene> s = load(doc_.table(), false, &warnings);
  warnings_ = warnings;
  preview_.show(doc_.version(), std::move(s), false);
}

Editor::~Editor() = default;

std::unique_ptr<Scene> Editor::load(const toml::table& t, bool view_only,
                                    std::vector<std::string>* warnings) {
  const std::string text = to_toml_text(t);
  std::unique_ptr<Scene> s;
  if (view_only && models_)
    s = std::make_unique<Scene>(load_view_from_string(text, doc_.file(), {}, frame_, *models_));
  else
    s = std::make_unique<Scene>(load_scene_from_string(text, doc_.file(), {}, frame_));
  if (!view_only || !models_) {
    models_ = std::make_unique<Scene>();
    models_->model_cameras = s->model_cameras;
  }
  *warnings = s->warnings;
  return s;
}

std::optional<std::string> Editor::check_files(const toml::table& t) const {
  std::vector<std::string> before, after;
  files_named(doc_.table(), "", &before);
  files_named(t, "", &after);
  for (const std::string& f : after) {
    if (std::find(before.begin(), before.end(), f) != before.end()) continue;
    // (as text when the name cannot be resolved, e.g. longer than the system allows: the load
    // then says why it cannot be read)
    const fs::path named = fs::path(f).is_absolute() ? fs::path(f) : folder() / f;
    std::error_code ec;
    fs::path p = fs::weakly_canonical(named, ec);
    if (ec) p = named.lexically_normal();
    if (!inside(p, folder()))
      return "'" + f + "' is outside the scene's folder (" + folder().string() +
             "): the editor reads files only there";
  }
  return std::nullopt;
}

// Loads `next`, and when it loads, lets `commit` make it the document and shows it.
EditOutcome Editor::show_new(const toml::table& next, const std::function<void()>& commit) {
  EditOutcome out;
  const bool view_only = models_ && differs_only_in_view(doc_.table(), next);
  std::unique_ptr<Scene> s;
  try {
    const ScopedReadConfinement confined(confinement());
    s = load(next, view_only, &out.warnings);
  } catch (const SceneError& e) {
    out.error = bad(e.message, e.key);
    return out;
  } catch (const ParamError& e) {
    out.error = bad(e.what(), e.key);
    return out;
  } catch (const std::exception& e) {  // a model or image that cannot be read, say
    out.error = bad(e.what());
    return out;
  }
  commit();
  warnings_ = out.warnings;
  out.version = doc_.version();
  preview_.show(doc_.version(), std::move(s), view_only);
  return out;
}

EditOutcome Editor::edit(std::span<const KeyEdit> edits, int64_t base_version) {
  std::lock_guard lock(mu_);
  if (base_version != doc_.version()) {
    EditOutcome out;
    out.error = EditError{409,
                          "the scene changed (version " + std::to_string(doc_.version()) +
                              ", the edit was made on " + std::to_string(base_version) +
                              "): reload it and edit again",
                          ""};
    out.version = doc_.version();
    return out;
  }
  toml::table next;
  try {
    next = doc_.edited(edits);
  } catch (const SceneError& e) {
    return {bad(e.message, e.key), doc_.version(), {}};
  }
  if (auto why = check_files(next)) return {bad(*why), doc_.version(), {}};
  return show_new(next, [&] { doc_.commit(std::move(next)); });
}

// (the document changes, and its version counts one, only when the state undone to loads)
EditOutcome Editor::undo() {
  std::lock_guard lock(mu_);
  if (!doc_.can_undo()) return {conflict("nothing to undo"), doc_.version(), {}};
  const toml::table then = *doc_.undo_target();
  return show_new(then, [&] { doc_.undo(); });
}

EditOutcome Editor::redo() {
  std::lock_guard lock(mu_);
  if (!doc_.can_redo()) return {conflict("nothing to redo"), doc_.version(), {}};
  const toml::table then = *doc_.redo_target();
  return show_new(then, [&] { doc_.redo(); });
}

EditOutcome Editor::set_frame(double frame) {
  std::lock_guard lock(mu_);
  const double before = frame_;
  frame_ = frame;
  // Only the view moves when every animated key is a view key; load() decides from the tree, so
  // the whole scene is loaded again, and the preview keeps its geometry when nothing else moved.
  EditOutcome out = show_new(doc_.table(), [&] { doc_.touch(); });
  if (out.error) frame_ = before;
  return out;
}

Json Editor::state() const {
  std::lock_guard lock(mu_);
  Json w = Json::array();
  for (const std::string& s : warnings_) w.push_back(s);
  return {{"version", doc_.version()},
          {"file", doc_.file().filename().string()},
          {"folder", folder().string()},
          {"text", doc_.text()},
          {"document", toml_to_json(doc_.table())},
          {"can_undo", doc_.can_undo()},
          {"can_redo", doc_.can_redo()},
          {"frame", frame_},
          {"warnings", w}};
}

// The longest name a save takes: the temporary it is written through (".NAME.tmp-PID-RANDOM",
// 32 bytes more) must fit the 255 bytes a file name may have.
constexpr size_t kMaxSaveName = 200;

Editor::SaveOutcome Editor::save(const std::string& name) {
  std::lock_guard lock(mu_);
  const std::string target = name.empty() ? doc_.file().filename().string() : name;
  if (!name.empty()) {
    // (a NUL would end the name the system sees: "model.obj\0.toml" writes model.obj)
    if (name.find_first_of(std::string("/\\\0", 3)) != std::string::npos || name == "." ||
        name == "..")
      return {"save takes a file name in the scene's folder, without a path: '" + name + "'"};
    if (fs::path(name).extension() != ".toml") return {"a scene file's name ends in .toml"};
    if (name.size() > kMaxSaveName)
      return {fmt::format("the name is too long ({} bytes; a saved scene's name has at most {})",
                          name.size(), kMaxSaveName)};
  }
  const SavedText saved = doc_.saved();
  if (!saved.reads_back)
    return {
        "the scene cannot be written as TOML that reads back the same (a key with control "
        "characters?): not saved"};
  if (auto why = folder_.write_atomic(target, saved.text)) {
    if (*why == "it is a symbolic link")
      return {"'" + target + "' is a symbolic link: the editor writes only plain files in the " +
              "scene's folder"};
    return {"cannot save '" + target + "': " + *why};
  }
  if (name.empty() || target == doc_.file().filename().string()) doc_.saved_as_file(saved.text);
  return {std::nullopt, saved.normalized};
}

std::string Editor::Render::file_name(const std::string& stem, std::optional<int> frame,
                                      const std::string& ext) const {
  if (!sequence) return stem + "." + ext;
  return fmt::format("{}_{:04d}.{}", stem, frame.value_or(first), ext);
}

namespace {

// The sink kinds the editor's final render (the beauty, no AOV layers) can write: not those
// that hold only some AOV (a .flo file, flow).
std::vector<const SinkKind*> editor_sink_kinds() {
  const std::vector<LayerSpec> beauty{{"", {"R", "G", "B", "A"}}};
  std::vector<const SinkKind*> kinds;
  for (const SinkKind* k : sink_kinds())
    if (!k->takes(beauty).empty()) kinds.push_back(k);
  return kinds;
}

// The sink kinds named, or the first one when none is (std::invalid_argument for an unknown name).
std::vector<const SinkKind*> sink_kinds_named(const std::vector<std::string>& names) {
  const std::vector<const SinkKind*> editor = editor_sink_kinds();
  std::string known;
  for (const SinkKind* k : editor) known += (known.empty() ? "" : ", ") + k->name;
  if (names.empty()) return {editor.front()};
  std::vector<const SinkKind*> kinds;
  for (const std::string& n : names) {
    const SinkKind* k = find_sink_kind_named(n);
    if (std::find(editor.begin(), editor.end(), k) == editor.end()) k = nullptr;
    if (!k) throw std::invalid_argument("no file format is named '" + n + "' (" + known + ")");
    if (std::find(kinds.begin(), kinds.end(), k) == kinds.end()) kinds.push_back(k);
  }
  return kinds;
}

}  // namespace

std::optional<std::string> Editor::start_render(const RenderRequest& req) {
  std::vector<const SinkKind*> kinds = sink_kinds_named(req.formats);
  if (req.frames && (req.frames->first > req.frames->second || req.frames->first < 0 ||
                     req.frames->second - req.frames->first > 100000))
    throw std::invalid_argument("'frames' go from a first to a last frame (0 <= first <= last)");
  Render& r = *render_;
  {
    std::lock_guard rl(r.mu);
    if (r.state == "running") return "a render is running";
  }
  if (r.thread.joinable()) r.thread.join();
  FinalRenderJob job;
  {
    std::lock_guard lock(mu_);
    job.text = doc_.text();
    job.scene_file = doc_.file();
    job.frame = frame_;
    std::lock_guard rl(r.mu);
    r.version = doc_.version();
  }
  const std::string stem = doc_.file().stem().string();
  {
    std::lock_guard rl(r.mu);
    for (const auto& e : fs::directory_iterator(r.folder)) fs::remove(e.path());
    r.state = "running";
    r.fraction = r.seconds = 0;
    r.error.clear();
    r.kinds = std::move(kinds);
    r.sequence = bool(req.frames);
    r.cancel = false;
    r.first = req.frames ? req.frames->first : int(job.frame);
    r.last = req.frames ? req.frames->second : r.first;
    r.done_frames = 0;
  }
  r.thread = std::thread(
      [this, job = std::move(job), stem]() mutable { render_frames(std::move(job), stem); });
  return std::nullopt;
}

// The render thread: every frame asked for into the render folder, the progress and the outcome
// in render_.
void Editor::render_frames(FinalRenderJob job, const std::string& stem) {
  Render& r = *render_;
  const auto start = std::chrono::steady_clock::now();
  const int count = r.last - r.first + 1;
  std::string error;
  // (the final render reads the scene's files again, under the same rule as an edit)
  const ScopedReadConfinement confined(confinement());
  try {
    job.cancel = &r.cancel;
    for (int f = r.first; f <= r.last && !r.cancel; ++f) {
      if (r.sequence) job.frame = f;
      job.files.clear();
      for (const SinkKind* k : r.kinds)
        job.files.push_back(r.folder / r.file_name(stem, f, k->extensions.front().substr(1)));
      const int done = f - r.first;
      job.progress = [&r, start, done, count](double fraction, double) {
        std::lock_guard rl(r.mu);
        r.fraction = (done + fraction) / count;
        r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      };
      final_renderer_(job);
      std::lock_guard rl(r.mu);
      r.done_frames = done + 1;
    }
  } catch (const std::exception& e) {
    error = e.what();
  }
  std::lock_guard rl(r.mu);
  r.state = r.cancel ? "cancelled" : error.empty() ? "done" : "failed";
  r.error = r.cancel ? "" : error;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (r.state == "done") r.fraction = 1;
}

bool Editor::cancel_render() {
  Render& r = *render_;
  std::lock_guard rl(r.mu);
  if (r.state != "running") return false;
  r.cancel = true;
  return true;
}

Json Editor::render_status() const {
  const Render& r = *render_;
  std::lock_guard rl(r.mu);
  const double eta =
      r.fraction > 0.01 && r.state == "running" ? r.seconds * (1 - r.fraction) / r.fraction : 0;
  Json j = {
      {"state", r.state},     {"fraction", r.fraction}, {"seconds", r.seconds},       {"eta", eta},
      {"version", r.version}, {"error", r.error},       {"folder", r.folder.string()}};
  // The formats of this render (each also as NAME: true), and every one the editor can write.
  j["formats"] = Json::array();
  j["available"] = Json::array();
  for (const SinkKind* k : editor_sink_kinds()) {
    const bool asked = std::find(r.kinds.begin(), r.kinds.end(), k) != r.kinds.end();
    j[k->name] = asked;
    if (asked) j["formats"].push_back(k->name);
    j["available"].push_back(
        {{"name", k->name}, {"extension", k->extensions.front().substr(1)}, {"label", k->label}});
  }
  if (r.sequence) j["frames"] = {r.first, r.last}, j["frames_done"] = r.done_frames;
  return j;
}

std::optional<fs::path> Editor::render_result(const std::string& ext,
                                              std::optional<int> frame) const {
  const Render& r = *render_;
  std::lock_guard rl(r.mu);
  const SinkKind* kind = find_sink_kind(fs::path("result." + ext));
  if (!kind || std::find(r.kinds.begin(), r.kinds.end(), kind) == r.kinds.end())
    return std::nullopt;
  const int f = frame.value_or(r.first);
  if (r.sequence ? (f < r.first || f >= r.first + r.done_frames) : r.state != "done")
    return std::nullopt;
  return r.folder / r.file_name(doc_.file().stem().string(), f, kind->extensions.front().substr(1));
}

}  // namespace anamorph::server
