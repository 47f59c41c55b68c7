// run_isolated: the child's result comes back byte for byte, and every way a third-party parser
// can fail (throw, abort, fault, hang, allocate without bound, be interrupted) becomes a
// LoadError that says which, while the calling process carries on.
#include <gtest/gtest.h>
#include <signal.h>
#include <algorithm>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <thread>

#include "loader_fixture.h"
#include "scene/assimp_child.h"
#include "scene/isolated.h"
#include "scene/loaders.h"
#include "test_util.h"

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
#if defined(ANAMORPH_ASAN)
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

// A tetrahedron: four vertices, four faces.
constexpr const char* kTetrahedron =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

std::string helper_error(const std::string& helper, const std::vector<std::string>& args) {
  try {
    run_helper("assimp", helper, args, {});
  } catch (const LoadError& e) {
    return e.what();
  }
  return "(no error)";
}

// An answer with the time of day assimp's binary dump writes after "ASSIMP.binary-dump." blanked
// (asctime's 24 characters): two answers a second apart differ there and nowhere else.
std::vector<unsigned char> untimed(std::vector<unsigned char> v) {
  const std::string head = "ASSIMP.binary-dump.";
  if (v.size() >= head.size() + 24 && std::equal(head.begin(), head.end(), v.begin()))
    std::fill(v.begin() + std::ptrdiff_t(head.size()), v.begin() + std::ptrdiff_t(head.size() + 24),
              '_');
  return v;
}

TEST(LoaderHelper, IsFoundInTheBuildAndAnswersAsTheReaderInThisProcessDoes) {
  const std::string helper = loader_helper();
  ASSERT_FALSE(helper.empty()) << "the build makes anamorph-loader; it was not found";
  test::ScratchDir dir;
  const auto obj = dir.write("tetra.obj", kTetrahedron);
  const std::vector<unsigned char> here = assimp_answer(obj);
  EXPECT_EQ(untimed(run_helper("assimp", helper, {"assimp", obj.string()}, {})), untimed(here));
  EXPECT_EQ(load_model(obj).triangle_count(), 4u);
}

TEST(LoaderHelper, ErrorsAreTheReadersAndAMissingProgramIsNamed) {
  test::ScratchDir dir;
  const auto missing = dir.path() / "absent.obj";
  std::string in_process;
  try {
    assimp_answer(missing);
  } catch (const LoadError& e) {
    in_process = e.what();
  }
  EXPECT_FALSE(in_process.empty());
  EXPECT_EQ(helper_error(loader_helper(), {"assimp", missing.string()}), in_process);
  EXPECT_CONTAINS(helper_error("/nonexistent/anamorph-loader", {"assimp", missing.string()}),
                  "cannot start assimp (/nonexistent/anamorph-loader): No such file");
  // A call that is not run_helper's: the program refuses, and the caller hears it stopped.
  EXPECT_CONTAINS(helper_error(loader_helper(), {"gltf", missing.string()}),
                  "assimp stopped without an answer (exit status 2)");
}

TEST(LoaderHelper, ArgumentsRoundTripAndMalformedOnesAreRefused) {
  const char* good[] = {"anamorph-loader", "42", "2.5", "1048576", "assimp", "a b.obj"};
  HelperCall call;
  ASSERT_TRUE(parse_helper_args(6, good, &call));
  EXPECT_EQ(call.parent, 42);
  EXPECT_EQ(call.limits.seconds, 2.5);
  EXPECT_EQ(call.limits.memory_bytes, 1048576u);
  EXPECT_EQ(call.args, (std::vector<std::string>{"assimp", "a b.obj"}));
  const char* bad[][4] = {{"x", "0", "1", "1"},   {"x", "7q", "1", "1"}, {"x", "7", "-1", "1"},
                          {"x", "7", "nan", "1"}, {"x", "7", "1", "0"},  {"x", "7", "1", "1k"}};
  for (const auto& b : bad) EXPECT_FALSE(parse_helper_args(4, b, &call)) << b[1] << " " << b[2];
  EXPECT_FALSE(parse_helper_args(3, good, &call));
}

// The failure this program exists for: loading while other threads allocate. A forked child
// inherits whatever allocator lock another thread held at that instant (AddressSanitizer's
// allocator does not take its locks around fork) and waits for it until the time limit; CI saw
// this in the editor, whose preview thread renders while an edit loads a model.
TEST(LoaderHelper, LoadsWhileOtherThreadsAllocate) {
  test::ScratchDir dir;
  const auto obj = dir.write("tetra.obj", kTetrahedron);
  setenv("ANAMORPH_LOADER_SECONDS", "5", 1);
  std::atomic<bool> stop{false};
  std::vector<std::thread> churn;
  for (int t = 0; t < 3; ++t)
    churn.emplace_back([&] {
      while (!stop.load(std::memory_order_relaxed)) {
        std::vector<std::unique_ptr<std::vector<char> > > v;
        for (int i = 0; i < 64; ++i) v.push_back(std::make_unique<std::vector<char> >(4096 + i));
      }
    });
  int loaded = 0;
  std::string error;
  for (int i = 0; i < 40 && error.empty(); ++i) {
    try {
      loaded += load_model(obj).triangle_count() == 4;
    } catch (const LoadError& e) {
      error = e.what();
    }
  }
  stop = true;
  for (std::thread& t : churn) t.join();
  unsetenv("ANAMORPH_LOADER_SECONDS");
  EXPECT_EQ(error, "");
  EXPECT_EQ(loaded, 40) << "loads that gave the tetrahedron";
}

}  // namespace
}  // namespace anamorph
