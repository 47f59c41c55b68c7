#include "io/read_log.h"

#include <sys/stat.h>

#include <algorithm>

namespace anamorph {

namespace {
thread_local ReadLog* t_log = nullptr;
thread_local const std::string* t_role = nullptr;
}  // namespace

void ReadLog::add(FileRead read) {
  const bool known = std::any_of(files_.begin(), files_.end(), [&](const FileRead& f) {
    return (f.inode != 0 && f.device == read.device && f.inode == read.inode) ||
           f.path == read.path;
  });
  if (!known) files_.push_back(std::move(read));
}

ReadLogScope::ReadLogScope(ReadLog* log) : previous_(t_log) { t_log = log; }
ReadLogScope::~ReadLogScope() { t_log = previous_; }

ReadRole::ReadRole(std::string role) : previous_(t_role), role_(std::move(role)) {
  t_role = &role_;
}
ReadRole::~ReadRole() { t_role = previous_; }

void note_read(const std::filesystem::path& path, int fd) {
  if (!t_log) return;
  FileRead r{path, t_role ? *t_role : "a file", 0, 0};
  struct stat st {};
  if ((fd >= 0 ? ::fstat(fd, &st) : ::stat(path.c_str(), &st)) == 0) {
    r.device = st.st_dev;
    r.inode = st.st_ino;
  }
  t_log->add(std::move(r));
}

}  // namespace anamorph
