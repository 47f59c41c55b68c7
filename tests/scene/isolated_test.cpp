// run_isolated: the child's result comes back byte for byte, and every way a third-party parser
// can fail (throw, abort, fault, hang, allocate without bound, be interrupted) becomes a
// LoadError that says which, while the calling process carries on.
#include <gtest/gtest.h>
#include <signal.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <thread>

#include "scene/isolated.h"
#include "scene/loaders.h"

namespace anamorph {
namespace {

std::string error_of(const std::function<std::vector<unsigned char>()>& work,
                     IsolationLimits limits = {}) {
  try {
    run_isolated("parser", work, limits);
  } catch (const LoadError& e) {
    return e.what();
  }
  return "(no error)";
}

#define EXPECT_CONTAINS(hay, needle) \
  EXPECT_NE(std::string(hay).find(needle), std::string::npos) << "message was: " << (hay)

TEST(Isolated, ResultComesBackByteForByte) {
  std::vector<unsigned char> big(10u << 20);
  for (size_t i = 0; i < big.size(); ++i)
    big[i] = static_cast<unsigned char>(i * 2654435761u >> 13);
  EXPECT_EQ(run_isolated("parser", [&] { return big; }, {}), big);
  EXPECT_TRUE(run_isolated("parser", [] { return std::vector<unsigned char>{}; }, {}).empty());
}

TEST(Isolated, ExceptionMessagePassesThrough) {
  EXPECT_EQ(error_of([]() -> std::vector<unsigned char> { throw LoadError("bad face 7"); }),
            "bad face 7");
}

TEST(Isolated, AbortAndFaultsBecomeErrorsNamingTheSignal) {
  EXPECT_CONTAINS(error_of([]() -> std::vector<unsigned char> { abort(); }),
                  "parser crashed on it (signal 6 SIGABRT)");
  EXPECT_CONTAINS(error_of([]() -> std::vector<unsigned char> {
                    raise(SIGBUS);
                    return {};
                  }),
                  "(signal 7 SIGBUS)");
  EXPECT_CONTAINS(error_of([]() -> std::vector<unsigned char> {
                    raise(SIGSEGV);
                    return {};
                  }),
                  "(signal 11 SIGSEGV)");
}

TEST(Isolated, HangIsStoppedAtTheTimeLimit) {
  IsolationLimits l;
  l.seconds = 0.5;
  const auto t0 = std::chrono::steady_clock::now();
  const std::string e = error_of(
      []() -> std::vector<unsigned char> {
        std::atomic<unsigned> spin{0};
        for (;;) spin.fetch_add(1, std::memory_order_relaxed);
      },
      l);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_CONTAINS(e, "parser did not finish within 0.5 s and was stopped");
  EXPECT_LT(s, 30) << "the child must be killed, not waited for";
}

TEST(Isolated, RunawayAllocationHitsTheMemoryLimit) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer's allocator reports, not throws, past the limit";
#else
  IsolationLimits l;
  l.memory_bytes = 256u << 20;
  const std::string e = error_of(
      []() {
        std::vector<std::vector<unsigned char> > hog;
        for (;;) hog.emplace_back(64u << 20, 1);  // touched, so never optimized away
        return hog.back();
      },
      l);
  EXPECT_CONTAINS(e, "parser ran out of memory (limit 256 MB");
#endif
}

TEST(Isolated, CancelFlagStopsTheChild) {
  std::atomic<bool> cancel{false};
  set_load_cancel_flag(&cancel);
  std::thread t([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    cancel = true;
  });
  const std::string e = error_of([]() -> std::vector<unsigned char> {
    for (;;) pause();
  });
  t.join();
  set_load_cancel_flag(nullptr);
  EXPECT_EQ(e, "interrupted");
}

TEST(Isolated, DefaultLimitsGrowWithTheFile) {
  const IsolationLimits small = loader_limits(1000), large = loader_limits(1ull << 30);
  EXPECT_GE(small.seconds, 10);
  EXPECT_GT(large.seconds, small.seconds);
  EXPECT_GT(large.memory_bytes, small.memory_bytes);
}

}  // namespace
}  // namespace anamorph
