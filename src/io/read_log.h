// Which files a load reads, so that the command line can refuse an output that would overwrite
// one of them (docs/robustness.md, "Second probe"). A ReadLog collects the files read on its
// thread while a ReadLogScope is alive; ReadRole names what the files read inside it are ("a
// texture", "a ray table"). read_whole_file records every file it opens; readers that open files
// some other way (a loader child, a third-party parser) call note_read.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace anamorph {

struct FileRead {
  std::filesystem::path path;  // as given to the reader
  std::string role;            // "the scene file", "a texture", ...
  dev_t device = 0;            // the file's identity when it was read (0, 0: could not stat)
  ino_t inode = 0;
};

class ReadLog {
 public:
  // Adds `path` unless the same file (by device and inode, or by path) is there already.
  void add(FileRead read);
  const std::vector<FileRead>& files() const { return files_; }

 private:
  std::vector<FileRead> files_;
};

// While alive, files read on this thread go to `log` (scopes nest: the innermost one wins).
class ReadLogScope {
 public:
  explicit ReadLogScope(ReadLog* log);
  ~ReadLogScope();
  ReadLogScope(const ReadLogScope&) = delete;
  ReadLogScope& operator=(const ReadLogScope&) = delete;

 private:
  ReadLog* previous_;
};

// While alive, files read on this thread are recorded with this role (the innermost one wins;
// "a file" outside any).
class ReadRole {
 public:
  explicit ReadRole(std::string role);
  ~ReadRole();
  ReadRole(const ReadRole&) = delete;
  ReadRole& operator=(const ReadRole&) = delete;

 private:
  const std::string* previous_;
  std::string role_;
};

// Records `path` in the active log (none: nothing happens); `fd` >= 0 identifies the file open
// (no race with a rename), otherwise the path is stat'ed.
void note_read(const std::filesystem::path& path, int fd = -1);

}  // namespace anamorph
