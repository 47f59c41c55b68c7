// Runs untrusted third-party parsing (assimp) in a child process, where a crash, an assertion,
// a hang or a runaway allocation becomes a LoadError instead of taking anamorph down.
//
// Why a child process: assimp 5.2.5 aborts on an ai_assert, faults with SIGBUS and loops forever
// on files a few bytes long, and OSS-Fuzz keeps finding more; no validation of ours can cover
// every format it reads. A forked child shares the parent's pages copy-on-write (no exec, no
// second binary), is limited in address space and CPU time, dies with its parent, and hands its
// result back through a pipe as bytes.
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

}  // namespace anamorph
