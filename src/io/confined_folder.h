// A folder opened once, by descriptor, and the files beneath it reached only through that
// descriptor: no path is resolved twice, no symbolic link is followed (neither the file nor any
// folder on the way), and nothing above the folder can be named. The editor's reads and saves go
// through one (docs/editor.md, "Security"): a symbolic link swapped in between a check and a write
// cannot redirect either, because there is no check by path to race with.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace anamorph {

class ConfinedFolder {
 public:
  // Opens `folder` (made absolute and lexically normal). Throws std::system_error naming it.
  explicit ConfinedFolder(const std::filesystem::path& folder);
  // Takes an open descriptor of the directory `folder` (the loader program gets one from the
  // process that starts it); it is closed with this object.
  ConfinedFolder(int fd, std::filesystem::path folder);
  ~ConfinedFolder();
  ConfinedFolder(const ConfinedFolder&) = delete;
  ConfinedFolder& operator=(const ConfinedFolder&) = delete;

  const std::filesystem::path& path() const { return path_; }
  int fd() const { return fd_; }

  // `file` (absolute, or relative to the working directory) relative to the folder when it lies
  // beneath it as text, "." and ".." applied without reading the file system; none otherwise.
  std::optional<std::filesystem::path> relative(const std::filesystem::path& file) const;

  // open(2) of `relative` beneath the folder with `flags` (O_CREAT is not allowed): a descriptor,
  // or -errno. ELOOP: a component is a symbolic link; EXDEV: the path leaves the folder. Uses
  // openat2(RESOLVE_BENEATH | RESOLVE_NO_SYMLINKS) where the kernel has it (Linux 5.6), else a
  // walk one component at a time with O_NOFOLLOW.
  int open_beneath(const std::filesystem::path& relative, int flags) const;

  // Writes `bytes` as the file `name` (one component, no '/') in the folder, atomically: a new
  // temporary created in the folder with O_EXCL | O_NOFOLLOW, fsync, renameat(2) over `name`,
  // fsync of the folder. A symbolic link at `name` is refused (and were one swapped in after that
  // check, renameat replaces the link itself: nothing outside the folder is ever written). The
  // reason when it fails (the temporary is removed), or none.
  std::optional<std::string> write_atomic(const std::string& name, std::string_view bytes) const;

 private:
  int fd_ = -1;
  std::filesystem::path path_;
};

// The walk open_beneath uses without openat2: each folder on the way opened with
// O_DIRECTORY | O_NOFOLLOW relative to the last, the file with O_NOFOLLOW. "..", "." and empty
// components are refused (EXDEV), as an absolute path is. Exposed for its test.
int open_beneath_by_walk(int dirfd, const std::filesystem::path& relative, int flags);

}  // namespace anamorph
