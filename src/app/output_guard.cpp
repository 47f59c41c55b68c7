#include "app/output_guard.h"

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>

#include "io/image_io.h"

namespace anamorph::app {

namespace fs = std::filesystem;

namespace {

FILE* g_messages = nullptr;  // null: stdout

bool same_as_fd(const struct stat& st, int fd) {
  struct stat s {};
  return ::fstat(fd, &s) == 0 && s.st_dev == st.st_dev && s.st_ino == st.st_ino;
}

// The path a write to `file` lands on: symbolic links followed (also a dangling last one, which
// the write would create), then made absolute and normal.
fs::path resolved(const fs::path& file) {
  fs::path p = file;
  std::error_code ec;
  for (int hops = 0; hops < 40 && fs::is_symlink(fs::symlink_status(p, ec)); ++hops) {
    const fs::path target = fs::read_symlink(p, ec);
    if (ec) break;
    p = target.is_absolute() ? target : p.parent_path() / target;
  }
  const fs::path w = fs::weakly_canonical(p, ec);
  return ec ? fs::absolute(p, ec).lexically_normal() : w;
}

std::string mode_text(mode_t m) { return fmt::format("{:04o}", m & 07777); }

}  // namespace

bool written_directly(const fs::path& file) { return AtomicFile::writes_directly(file); }

bool is_standard_output(const fs::path& file) {
  struct stat st {};
  return ::stat(file.c_str(), &st) == 0 && same_as_fd(st, STDOUT_FILENO);
}

FILE* messages() { return g_messages ? g_messages : stdout; }
void messages_to_stderr() { g_messages = stderr; }

OutputGuard::Entry OutputGuard::entry(const fs::path& file, std::string what) {
  Entry e{file, std::move(what), resolved(file), 0, 0};
  struct stat st {};
  if (::stat(file.c_str(), &st) == 0 && S_ISREG(st.st_mode)) {
    e.device = st.st_dev;
    e.inode = st.st_ino;
  }
  return e;
}

void OutputGuard::add_input(const fs::path& file, const std::string& role) {
  inputs_.push_back(entry(file, role));
}

void OutputGuard::add_inputs(const std::vector<FileRead>& files) {
  for (const FileRead& f : files) {
    Entry e = entry(f.path, f.role);
    if (f.inode != 0) {  // the file that was read, even if another has its name by now
      e.device = f.device;
      e.inode = f.inode;
    }
    inputs_.push_back(std::move(e));
  }
}

void OutputGuard::add_output(const fs::path& file, const std::string& what) {
  if (written_directly(file)) return;
  const Entry out = entry(file, what);
  const auto same = [&](const Entry& e) {
    return (out.inode != 0 && e.inode == out.inode && e.device == out.device) || e.key == out.key;
  };
  for (const Entry& in : inputs_)
    if (same(in))
      throw OutputClash(fmt::format(
          "{} is {} this run reads{}; nothing was written (choose another output name)", what,
          in.what, in.path == file ? "" : fmt::format(" ({})", in.path.string())));
  for (const Entry& o : outputs_)
    if (same(o))
      throw OutputClash(fmt::format(
          "{} is also {}: two outputs of one run cannot share a file; nothing was written", what,
          o.what));
  struct stat st {};
  if (::stat(file.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) throw OutputClash(fmt::format("{} is a directory", what));
    // (root may write any file: the mode is what the owner asked for.)
    if ((st.st_mode & 0222) == 0 || ::access(file.c_str(), W_OK) != 0)
      throw OutputClash(fmt::format(
          "{} is read-only (mode {}): anamorph does not replace a read-only file; make it "
          "writable or choose another name",
          what, mode_text(st.st_mode)));
  }
  outputs_.push_back(out);
}

void check_outputs(const std::vector<FileRead>& inputs,
                   const std::vector<std::pair<fs::path, std::string>>& outputs) {
  OutputGuard guard;
  guard.add_inputs(inputs);
  for (const auto& [file, what] : outputs) guard.add_output(file, what);
}

std::vector<FileRead> scene_file_input(const fs::path& scene) {
  return {{scene, "the scene file"}};
}

}  // namespace anamorph::app
