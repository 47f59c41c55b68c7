// The scene being edited: the scene file's own TOML tree (its includes stay includes), changed
// by dotted-key edits, with undo and redo, and a version that counts every change so that two
// tabs editing one scene find out when they disagree.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "server/document_save.h"

namespace anamorph::server {

// One change: `value` is TOML text (a bare word is a string); none removes the key.
struct KeyEdit {
  std::string key;
  std::optional<std::string> value;
};

class Document {
 public:
  // Reads the file (throws SceneError: not found, or not TOML).
  explicit Document(std::filesystem::path file);
  const std::filesystem::path& file() const { return file_; }
  const toml::table& table() const { return table_; }
  int64_t version() const { return version_; }
  // The document as the scene file it would save: the file's own text with the edits spliced
  // in (comments and layout kept), or rewritten whole when they do not fit (document_save.h).
  SavedText saved() const;
  std::string text() const;
  // The file now holds `text` (saved): later saves splice into it.
  void saved_as_file(std::string text) { original_text_ = std::move(text); }
  // The tree after `edits`, in order (throws SceneError naming a key that cannot be set).
  toml::table edited(std::span<const KeyEdit> edits) const;
  // `next` becomes the document (a new version; what it replaced can be undone).
  void commit(toml::table next);
  // A new version of the same tree (the animation frame shown changed).
  void touch() { ++version_; }
  bool can_undo() const { return !undo_.empty(); }
  bool can_redo() const { return !redo_.empty(); }
  // The tree undo() / redo() would make the document (null when there is none), unchanged.
  const toml::table* undo_target() const { return undo_.empty() ? nullptr : &undo_.back(); }
  const toml::table* redo_target() const { return redo_.empty() ? nullptr : &redo_.back(); }
  bool undo();
  bool redo();

 private:
  std::filesystem::path file_;
  std::string original_text_;  // the file as read (or last saved)
  toml::table table_;
  int64_t version_ = 1;
  std::vector<toml::table> undo_, redo_;
};

// `text` (TOML) with every float written in the fewest digits that read back as the same double.
std::string tidy_floats(const std::string& text);

// Whether `a` and `b` differ only in [camera], [image] and [render]: the editor then keeps the
// loaded geometry and acceleration structure and rebuilds the view alone.
bool differs_only_in_view(const toml::table& a, const toml::table& b);

}  // namespace anamorph::server
