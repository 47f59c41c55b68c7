#include "scene/isolated.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>

#include "math/sanitizers.h"
#include "scene/loaders.h"

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(undefined_behavior_sanitizer)
#define ANAMORPH_SANITIZER_DEATH_CALLBACK 1
#endif
#endif
#if defined(ANAMORPH_ASAN)
#define ANAMORPH_SANITIZER_DEATH_CALLBACK 1
#endif
#ifdef ANAMORPH_SANITIZER_DEATH_CALLBACK
#include <sanitizer/common_interface_defs.h>
#endif

namespace anamorph {

namespace {

std::atomic<const std::atomic<bool>*> g_cancel{nullptr};

// The child's verdict, the first byte it writes.
enum Status : unsigned char { kDone = 0, kThrew = 1, kOutOfMemory = 2 };

uint64_t env_number(const char* name, uint64_t fallback) {
  const char* v = std::getenv(name);
  if (!v || !*v) return fallback;
  char* end = nullptr;
  const unsigned long long x = std::strtoull(v, &end, 10);
  return end && *end == 0 && x > 0 ? x : fallback;
}

// The address space in use now (bytes): the child's limit is this plus its allowance, because a
// fork starts with all of the parent's mappings (and a sanitizer's shadow reservations).
uint64_t address_space_now() {
  std::ifstream statm("/proc/self/statm");
  uint64_t pages = 0;
  statm >> pages;
  return pages * uint64_t(sysconf(_SC_PAGESIZE));
}

bool write_all(int fd, const void* data, size_t n) {
  const auto* p = static_cast<const unsigned char*>(data);
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    p += w, n -= size_t(w);
  }
  return true;
}

[[noreturn]] void child_main(int fd, pid_t parent,
                             const std::function<std::vector<unsigned char>()>& work,
                             const IsolationLimits& limits) {
  prctl(PR_SET_PDEATHSIG, SIGKILL);  // never outlive the parent
  if (getppid() != parent) _exit(1);
  // Default actions: the parent's handlers (and a sanitizer's, which would turn a fault into an
  // abort after a report) must not run here; the parent names the signal itself.
  // (SIGABRT too: a fuzzer's handler would report assimp's ai_assert as its own crash.)
  for (const int sig : {SIGINT, SIGTERM, SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT})
    signal(sig, SIG_DFL);
#ifdef ANAMORPH_SANITIZER_DEATH_CALLBACK
  // Likewise a sanitizer's death callback (libFuzzer's writes a crash-* file): an allocation
  // past the child's memory limit makes ASan abort the child, which the parent reports.
  __sanitizer_set_death_callback(nullptr);
#endif
  const rlim_t cpu = rlim_t(std::ceil(limits.seconds)) + 1;  // the parent's clock acts first
  const rlimit cpu_limit{cpu, cpu + 1};
  setrlimit(RLIMIT_CPU, &cpu_limit);
  const rlim_t as = address_space_now() + limits.memory_bytes;
  const rlimit as_limit{as, as};
  setrlimit(RLIMIT_AS, &as_limit);
  Status status = kDone;
  std::vector<unsigned char> result;
  try {
    result = work();
  } catch (const std::bad_alloc&) {
    status = kOutOfMemory;
  } catch (const std::exception& e) {
    status = kThrew;
    const std::string m = e.what();
    result.assign(m.begin(), m.end());
  }
  const uint64_t n = result.size();
  const bool ok = write_all(fd, &status, 1) && write_all(fd, &n, sizeof n) &&
                  write_all(fd, result.data(), result.size());
  _exit(ok ? 0 : 1);  // no destructors, atexit handlers or leak checks of the parent's state
}

std::string signal_name(int sig) {
  const char* abbrev = sigabbrev_np(sig);
  return fmt::format("signal {}{}{}", sig, abbrev ? " SIG" : "", abbrev ? abbrev : "");
}

// The child's output until it closes the pipe, watching the clock and the cancel flag; *stop
// says why it stopped early ("" when the pipe closed).
std::vector<unsigned char> collect(int fd, const std::string& what, const IsolationLimits& limits,
                                   std::string* stop) {
  std::vector<unsigned char> got;
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(limits.seconds);
  unsigned char buf[1 << 16];
  for (;;) {
    const std::atomic<bool>* cancel = g_cancel.load();
    if (cancel && cancel->load()) {
      *stop = "interrupted";
      return got;
    }
    if (std::chrono::steady_clock::now() > deadline) {
      *stop = fmt::format(
          "{} did not finish within {:g} s and was stopped (set ANAMORPH_LOADER_SECONDS to "
          "allow more for a very large model)",
          what, limits.seconds);
      return got;
    }
    pollfd p{fd, POLLIN, 0};
    const int r = poll(&p, 1, 50);
    if (r < 0 && errno != EINTR) {
      *stop = fmt::format("cannot wait for {}: {}", what, std::strerror(errno));
      return got;
    }
    if (r <= 0) continue;
    const ssize_t n = read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return got;  // closed: the child finished or died
    got.insert(got.end(), buf, buf + n);
  }
}

// The result in a finished child's output (status byte, length, bytes), or its error.
std::vector<unsigned char> answer(std::vector<unsigned char> got, const std::string& what,
                                  const IsolationLimits& limits, int status) {
  uint64_t n = 0;
  if (got.size() < 1 + sizeof n)
    throw LoadError(fmt::format("{} stopped without an answer (exit status {})", what,
                                WIFEXITED(status) ? WEXITSTATUS(status) : -1));
  std::memcpy(&n, got.data() + 1, sizeof n);
  if (got.size() != 1 + sizeof n + n)
    throw LoadError(fmt::format("the answer of {} was cut short", what));
  const auto verdict = Status(got[0]);
  got.erase(got.begin(), got.begin() + 1 + sizeof n);
  switch (verdict) {
    case kDone:
      return got;
    case kOutOfMemory:
      throw LoadError(fmt::format(
          "{} ran out of memory (limit {} MB; set ANAMORPH_LOADER_MEMORY_MB to allow more)", what,
          limits.memory_bytes >> 20));
    case kThrew:
    default:
      throw LoadError(std::string(got.begin(), got.end()));
  }
}

}  // namespace

IsolationLimits loader_limits(uint64_t file_bytes) {
  IsolationLimits l;
  l.seconds = double(env_number("ANAMORPH_LOADER_SECONDS", 10 + (file_bytes >> 20)));
  l.memory_bytes = env_number("ANAMORPH_LOADER_MEMORY_MB", ((2ull << 30) + 64 * file_bytes) >> 20)
                   << 20;
  return l;
}

bool loaders_isolated() {
  const char* v = std::getenv("ANAMORPH_LOADER_IN_PROCESS");
  return !(v && std::string(v) == "1");
}

void set_load_cancel_flag(const std::atomic<bool>* flag) { g_cancel = flag; }

namespace {

// The helper writes its answer to this descriptor (its stdout is /dev/null: a parser that
// prints must not corrupt the answer).
constexpr int kHelperAnswerFd = 3;

// Waits for child `pid`'s answer on `fd` (closing it) and returns it, or throws its error.
std::vector<unsigned char> finish(pid_t pid, int fd, const std::string& what,
                                  const IsolationLimits& limits) {
  std::string stop;
  std::vector<unsigned char> got = collect(fd, what, limits, &stop);
  close(fd);
  if (!stop.empty()) kill(pid, SIGKILL);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!stop.empty()) throw LoadError(stop);
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    if (sig == SIGXCPU || sig == SIGKILL)
      throw LoadError(
          fmt::format("{} ran out of CPU time ({:g} s) and was stopped", what, limits.seconds));
    throw LoadError(
        fmt::format("{} crashed on it ({}): the file is damaged or in a form {} cannot read", what,
                    signal_name(sig), what));
  }
  return answer(std::move(got), what, limits, status);
}

bool executable(const std::string& path) { return access(path.c_str(), X_OK) == 0; }

// posix_spawn's settings for the helper: all signals unblocked and at their defaults, stdin and
// stdout on /dev/null, stderr shared (a sanitizer's report shows), the pipe on kHelperAnswerFd.
struct SpawnSetup {
  posix_spawn_file_actions_t actions;
  posix_spawnattr_t attr;
  SpawnSetup(int answer_fd, int folder_fd) {
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, answer_fd, kHelperAnswerFd);
    if (folder_fd >= 0) posix_spawn_file_actions_adddup2(&actions, folder_fd, kHelperFolderFd);
    posix_spawnattr_init(&attr);
    sigset_t none, all;
    sigemptyset(&none);
    sigfillset(&all);
    posix_spawnattr_setsigmask(&attr, &none);
    posix_spawnattr_setsigdefault(&attr, &all);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  }
  ~SpawnSetup() {
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attr);
  }
  SpawnSetup(const SpawnSetup&) = delete;
  SpawnSetup& operator=(const SpawnSetup&) = delete;
};

}  // namespace

std::vector<unsigned char> run_isolated(const std::string& what,
                                        const std::function<std::vector<unsigned char>()>& work,
                                        const IsolationLimits& limits) {
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0)
    throw LoadError(fmt::format("cannot create a pipe for {}: {}", what, std::strerror(errno)));
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]), close(fds[1]);
    throw LoadError(fmt::format("cannot start a process for {}: {}", what, std::strerror(errno)));
  }
  if (pid == 0) {
    close(fds[0]);
    child_main(fds[1], parent, work, limits);
  }
  close(fds[1]);
  return finish(pid, fds[0], what, limits);
}

std::string loader_helper() {
  if (const char* v = std::getenv("ANAMORPH_LOADER_HELPER"); v && *v)
    return std::string(v) == "fork" ? "" : v;
  // Beside the program, then beside the shared object holding this code (the Python module).
  std::vector<std::filesystem::path> places;
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) places.push_back(self.parent_path());
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&loader_helper), &info) && info.dli_fname)
    places.push_back(std::filesystem::absolute(info.dli_fname, ec).parent_path());
  for (const std::filesystem::path& dir : places)
    if (executable((dir / "anamorph-loader").string())) return (dir / "anamorph-loader").string();
#ifdef ANAMORPH_LOADER_HELPER_BUILT
  if (executable(ANAMORPH_LOADER_HELPER_BUILT)) return ANAMORPH_LOADER_HELPER_BUILT;
#endif
  return "";
}

std::vector<unsigned char> run_helper(const std::string& what, const std::string& helper,
                                      const std::vector<std::string>& args,
                                      const IsolationLimits& limits, int folder_fd) {
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0)
    throw LoadError(fmt::format("cannot create a pipe for {}: {}", what, std::strerror(errno)));
  // Above the descriptors the helper receives, so dup2 always copies (and clears CLOEXEC).
  const int answer_fd = fcntl(fds[1], F_DUPFD_CLOEXEC, kHelperFolderFd + 1);
  close(fds[1]);
  if (answer_fd < 0) {
    close(fds[0]);
    throw LoadError(fmt::format("cannot create a pipe for {}: {}", what, std::strerror(errno)));
  }
  std::vector<std::string> words = {helper, std::to_string(getpid()),
                                    fmt::format("{:.17g}", limits.seconds),
                                    std::to_string(limits.memory_bytes)};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  int err = 0;
  {
    // (the folder's descriptor likewise, if it sits where the answer goes)
    const int folder = folder_fd >= 0 ? fcntl(folder_fd, F_DUPFD_CLOEXEC, kHelperFolderFd + 1) : -1;
    const SpawnSetup setup(answer_fd, folder);
    err = posix_spawn(&pid, helper.c_str(), &setup.actions, &setup.attr, argv.data(), environ);
    if (folder >= 0) close(folder);
  }
  close(answer_fd);
  if (err != 0) {
    close(fds[0]);
    throw LoadError(fmt::format("cannot start {} ({}): {}", what, helper, std::strerror(err)));
  }
  return finish(pid, fds[0], what, limits);
}

bool parse_helper_args(int argc, const char* const* argv, HelperCall* call) {
  if (argc < 4) return false;
  char* end = nullptr;
  call->parent = int(std::strtol(argv[1], &end, 10));
  if (*end || call->parent <= 0) return false;
  call->limits.seconds = std::strtod(argv[2], &end);
  if (*end || !(call->limits.seconds > 0)) return false;
  call->limits.memory_bytes = std::strtoull(argv[3], &end, 10);
  if (*end || call->limits.memory_bytes == 0) return false;
  call->args.assign(argv + 4, argv + argc);
  return true;
}

void serve_isolated(const HelperCall& call,
                    const std::function<std::vector<unsigned char>()>& work) {
  child_main(kHelperAnswerFd, pid_t(call.parent), work, call.limits);
}

}  // namespace anamorph
