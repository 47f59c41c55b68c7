// Small pieces shared by the loaders: opening files with a clear error, collecting warnings once,
// and textures read from image files.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "io/read_file.h"
#include "material/texture.h"

namespace anamorph {

// Throws LoadError "cannot open <path>: <reason>" (from the OS, e.g. "No such file or directory",
// or io/read_file.h's: "is a FIFO, not a regular file") unless `file` is a readable regular file
// no larger than `kind` allows; returns its size.
uint64_t require_readable(const std::filesystem::path& file, const InputKind& kind);
// The whole file; same errors as require_readable.
std::vector<unsigned char> read_file_bytes(const std::filesystem::path& file,
                                           const InputKind& kind);
// A scene file's text (kSceneInput).
std::string read_text_file(const std::filesystem::path& file);
// Up to `max` bytes of `file` from `offset` (from the end when `from_end`); same errors.
std::string read_file_part(const std::filesystem::path& file, const InputKind& kind,
                           uint64_t offset, size_t max, bool from_end = false);
// ".GLB" -> ".glb".
std::string lowercase_extension(const std::filesystem::path& file);

// Warnings in first-seen order, each distinct message once.
class WarningList {
 public:
  void add(std::string w) {
    if (seen_.insert(w).second) list_.push_back(std::move(w));
  }
  std::vector<std::string> take() { return std::move(list_); }

 private:
  std::set<std::string> seen_;
  std::vector<std::string> list_;
};

// Image files used as textures, each decoded once per (path, colour space). A texture that
// cannot be read gives null and the reason in *error (the caller warns and falls back to the
// material's colour: models often reference textures that did not travel with them).
class ImageFileCache {
 public:
  std::shared_ptr<const MipMap> get(const std::filesystem::path& file, bool srgb,
                                    std::string* error);

 private:
  std::map<std::pair<std::string, bool>, std::pair<std::shared_ptr<const MipMap>, std::string>>
      cache_;  // image or the reason it could not be read
};

}  // namespace anamorph
