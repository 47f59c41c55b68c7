// Loops over index ranges on every core of the current task arena: oneTBB normally, plain
// std::threads under ThreadSanitizer. Debian's oneTBB is not built with TSan, so the
// happens-before of its joins is invisible to it and every hand-off after a TBB loop (a film
// read after the tiles wrote it) would be reported as a race; with std::threads, atomics and
// join, TSan sees every synchronization and reports only real races.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "math/sanitizers.h"

namespace anamorph {

// The most threads a caller may ask for (0 means all cores): the one check behind the CLI's
// --threads, the Python module's threads= and every arena built from them. TBB starts as many
// workers as asked; 200,000 of them exhausted the process (the Python interpreter faulted).
inline constexpr int kMaxThreads = 1024;

// Why `n` is not a thread count, or "" when it is.
inline std::string thread_count_error(long long n) {
  if (n >= 0 && n <= kMaxThreads) return "";
  return "threads = " + std::to_string(n) + " is out of range: 0 (all cores) to " +
         std::to_string(kMaxThreads);
}

// The concurrency of an arena of `n` threads (0: all cores); throws std::invalid_argument with
// thread_count_error's text for any other count.
inline int arena_concurrency(long long n) {
  if (const std::string e = thread_count_error(n); !e.empty()) throw std::invalid_argument(e);
  return n > 0 ? int(n) : tbb::task_arena::automatic;
}

#if defined(ANAMORPH_TSAN)
inline constexpr bool kParallelWithStdThreads = true;
#else
inline constexpr bool kParallelWithStdThreads = false;
#endif

// f(lo, hi) over [begin, end) in chunks of at most `grain` indices, each chunk once, on as many
// threads as the current arena allows. Chunks may run in any order and on any thread.
template <class F>
void parallel_chunks(size_t begin, size_t end, size_t grain, F&& f) {
  if (begin >= end) return;
  grain = std::max<size_t>(grain, 1);
  if constexpr (!kParallelWithStdThreads) {
    tbb::parallel_for(
        tbb::blocked_range<size_t>(begin, end, grain),
        [&](const tbb::blocked_range<size_t>& r) { f(r.begin(), r.end()); },
        tbb::simple_partitioner());
  } else {
    std::atomic<size_t> next{begin};
    std::exception_ptr error;
    std::mutex error_mutex;
    const auto work = [&] {
      try {
        for (size_t lo; (lo = next.fetch_add(grain)) < end;) f(lo, std::min(lo + grain, end));
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
      }
    };
    const size_t chunks = (end - begin + grain - 1) / grain;
    const size_t n = std::min<size_t>(size_t(tbb::this_task_arena::max_concurrency()), chunks);
    std::vector<std::thread> threads;
    for (size_t t = 1; t < n; ++t) threads.emplace_back(work);
    work();
    for (std::thread& t : threads) t.join();
    if (error) std::rethrow_exception(error);
  }
}

// f(i) for every i in [begin, end), handed out in increasing order from one counter to as many
// threads as the arena allows: work finishes roughly in order, which a streamed image needs (a
// recursive split would start one thread in the middle of the frame and hold half of it back).
template <class F>
void parallel_in_order(size_t begin, size_t end, F&& f) {
  if (begin >= end) return;
  if constexpr (!kParallelWithStdThreads) {
    std::atomic<size_t> next{begin};
    const int n = std::min<int>(tbb::this_task_arena::max_concurrency(), int(end - begin));
    tbb::parallel_for(0, n, [&](int) {
      for (size_t i; (i = next.fetch_add(1)) < end;) f(i);
    });
  } else {
    parallel_chunks(begin, end, 1, [&](size_t lo, size_t) { f(lo); });
  }
}

// f(i) for every i in [begin, end).
template <class F>
void parallel_for_each(int begin, int end, F&& f) {
  if (end <= begin) return;
  if constexpr (!kParallelWithStdThreads) {
    tbb::parallel_for(begin, end, f);
  } else {
    parallel_chunks(size_t(begin), size_t(end), 1, [&](size_t lo, size_t hi) {
      for (size_t i = lo; i < hi; ++i) f(int(i));
    });
  }
}

}  // namespace anamorph
