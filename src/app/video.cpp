#include "app/video.h"

#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "app/common.h"
#include "app/output_guard.h"
#include "io/temporary_files.h"

namespace anamorph::app {

namespace fs = std::filesystem;

namespace {

bool on_path(const std::string& exe) {
  const char* path = std::getenv("PATH");
  if (!path) return false;
  std::string p = path;
  for (size_t s = 0, e; s <= p.size(); s = e + 1) {
    e = p.find(':', s);
    if (e == std::string::npos) e = p.size();
    const fs::path cand = fs::path(p.substr(s, e - s)) / exe;
    if (!p.substr(s, e - s).empty() && access(cand.c_str(), X_OK) == 0) return true;
  }
  return false;
}

}  // namespace

bool video_tool_found() {
  if (on_path("ffmpeg")) return true;
  fmt::print(stderr,
             "error: --video needs ffmpeg, which is not on the PATH (install it, e.g. `apt-get "
             "install ffmpeg`, "
             "or drop --video; the frames alone need nothing else)\n");
  return false;
}

int assemble_video(const std::string& pattern, int first, int count, int fps,
                   const std::string& video, bool quiet) {
  const bool direct = written_directly(video);
  const fs::path target = video;
  const fs::path tmp =
      direct ? target
             : target.parent_path() / fmt::format(".{}.tmp-{}{}", target.stem().string(), getpid(),
                                                  target.extension().string());
  std::error_code ec;
  if (!direct && target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  const int slot = direct ? -1 : register_temporary(tmp);
  const std::string rate = std::to_string(fps), start = std::to_string(first);
  const pid_t pid = fork();
  if (pid == 0) {
    execlp("ffmpeg", "ffmpeg", "-y", "-loglevel", "error", "-framerate", rate.c_str(),
           "-start_number", start.c_str(), "-i", pattern.c_str(), "-c:v", "libx264", "-pix_fmt",
           "yuv420p", tmp.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  set_child_to_stop(pid);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  set_child_to_stop(0);
  const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (ok && !direct) fs::rename(tmp, target, ec);
  if (!direct && (!ok || ec)) fs::remove(tmp);
  unregister_temporary(slot);
  if (!ok) {
    fmt::print(stderr, "error: ffmpeg failed to assemble {} (exit status {})\n", video,
               WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    return kFailure;
  }
  if (ec) {
    fmt::print(stderr, "error: cannot write {}: {}\n", video, ec.message());
    return kFailure;
  }
  if (!quiet) fmt::print(messages(), "video: {} ({} frames at {} fps)\n", video, count, fps);
  return kOk;
}

}  // namespace anamorph::app
