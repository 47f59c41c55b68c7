// Runs untrusted third-party parsing (assimp) in a process of its own, where a crash, an
// assertion, a hang or a runaway allocation becomes a LoadError instead of taking anamorph down.
//
// Why another process: assimp 5.2.5 aborts on an ai_assert, faults with SIGBUS and loops forever
// on files a few bytes long, and OSS-Fuzz keeps finding more; no validation of ours can cover
// every format it reads. The process is limited in address space and CPU time, dies with its
// parent, and hands its result back through a pipe as bytes.
//
// Why a new program (`anamorph-loader`, run_helper) rather than a bare fork (run_isolated): a
// forked child of a process with other threads inherits every lock those threads held at that
// instant, and assimp allocates. glibc's malloc takes its locks around fork, but a sanitizer's
// allocator (GCC 12's AddressSanitizer) does not: the editor forking while its preview thread
// rendered left children stuck on the allocator's lock until the time limit, 3 loads in 20 under
// load. A program started with posix_spawn begins with no locks and no threads; the fork remains
// for builds without the helper (a pip-installed module), where the process is single-threaded
// while it loads unless it runs the editor.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace anamorph {

struct IsolationLimits {
  double seconds = 60;                 // wall-clock time before the child is killed
  uint64_t memory_bytes = 4ull << 30;  // address space the child may add to the parent's
};

// The default limits for parsing a file of `file_bytes` bytes: 10 s plus 1 s per MB, 2 GiB plus
// 64 bytes per byte of input. ANAMORPH_LOADER_SECONDS and ANAMORPH_LOADER_MEMORY_MB override
// them (for very large models, and for tests).
IsolationLimits loader_limits(uint64_t file_bytes);

// False when ANAMORPH_LOADER_IN_PROCESS=1: loaders then run in this process (for debugging a
// loader under gdb, and to measure what the isolation costs).
bool loaders_isolated();

// The process-wide flag that a SIGINT/SIGTERM handler sets; run_isolated kills its child and
// throws when it is set. Null (the default) means no cancellation.
void set_load_cancel_flag(const std::atomic<bool>* flag);

// Calls work() in a forked child and returns the bytes it returns. Throws LoadError naming
// `what` when work throws (its message), the child dies (the signal), exceeds the limits, or the
// load is cancelled. work must not start threads or touch locks other threads may hold.
std::vector<unsigned char> run_isolated(const std::string& what,
                                        const std::function<std::vector<unsigned char>()>& work,
                                        const IsolationLimits& limits);

// The loader program: $ANAMORPH_LOADER_HELPER, else `anamorph-loader` beside this executable,
// else the one the build made; "" when there is none (or ANAMORPH_LOADER_HELPER=fork).
std::string loader_helper();

// Like run_isolated, but the work is done by `helper args...` started as a new program, which
// answers through serve_isolated. Same errors and limits. `folder_fd`, when not -1, is given to
// the program as descriptor kHelperFolderFd (a ConfinedFolder's, io/confined_folder.h).
inline constexpr int kHelperFolderFd = 4;
std::vector<unsigned char> run_helper(const std::string& what, const std::string& helper,
                                      const std::vector<std::string>& args,
                                      const IsolationLimits& limits, int folder_fd = -1);

// The helper's side of run_helper. parse_helper_args reads what run_helper passed (false when
// argv is not such a call); serve_isolated applies the limits, runs work, answers and exits.
struct HelperCall {
  int parent = 0;  // run_helper's process: the helper stops when it has gone
  IsolationLimits limits;
  std::vector<std::string> args;
};
bool parse_helper_args(int argc, const char* const* argv, HelperCall* call);
[[noreturn]] void serve_isolated(const HelperCall& call,
                                 const std::function<std::vector<unsigned char>()>& work);

}  // namespace anamorph
