// The instruction-set override (ANAMORPH_ISA, math/simd.h): every set this CPU has gives the same
// camera rays bit for bit, the benchmark names the set it ran, and a set that is unknown or more
// than the CPU has is a clear error (exit 2), never a silent fallback.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "cli_util.h"
#include "math/simd.h"
#include "test_util.h"

namespace anamorph {

namespace fs = std::filesystem;

namespace {

test::CliResult run_with(const std::string& isa, const std::string& args) {
  return test::run_shell("ANAMORPH_ISA=" + isa + " " + test::binary().string() + " " + args);
}

// The sets this CPU can run, lowest first.
std::vector<simd::Isa> usable() {
  std::vector<simd::Isa> sets;
  for (simd::Isa s : {simd::Isa::Baseline, simd::Isa::Avx2, simd::Isa::Avx512})
    if (int(s) <= int(simd::cpu_best())) sets.push_back(s);
  return sets;
}

}  // namespace

TEST(Isa, NamesRoundTrip) {
  for (simd::Isa s : {simd::Isa::Baseline, simd::Isa::Avx2, simd::Isa::Avx512})
    EXPECT_EQ(simd::parse(simd::name(s)), s) << simd::name(s);
  EXPECT_EQ(simd::parse("sse2"), simd::Isa::Baseline);
  EXPECT_FALSE(simd::parse("avx3"));
  EXPECT_FALSE(simd::parse("AVX2"));
}

// The rays of an affine field with coins, a spline surface with normal directions and a fisheye
// (the three kernel families of VirtualCamera and the functions' own kernels), written with 17
// significant digits: the same text from every instruction set.
TEST(Isa, EverySetGivesTheSameRays) {
  const fs::path d = fs::temp_directory_path() / ("anamorph_isa_" + std::to_string(getpid()));
  fs::create_directories(d);
  const fs::path ex = test::source_dir() / "examples";
  const std::vector<std::string> scenes{(ex / "paper/09.toml").string(),
                                        (ex / "paper/14.toml").string(),
                                        (ex / "apps/fisheye_180.toml").string()};
  for (size_t k = 0; k < scenes.size(); ++k) {
    std::string first;
    for (simd::Isa s : usable()) {
      const fs::path out = d / (std::to_string(k) + "_" + simd::name(s) + ".csv");
      const auto r = run_with(simd::name(s),
                              "rays " + scenes[k] + " --width 37 --height 23 -o " + out.string());
      ASSERT_EQ(r.code, 0) << r.out;
      const std::string text = test::read_text(out);
      ASSERT_GT(text.size(), 1000u) << out;
      if (first.empty())
        first = text;
      else
        EXPECT_TRUE(text == first) << scenes[k] << ": the rays of " << simd::name(s)
                                   << " differ from the baseline's (" << out << ")";
    }
  }
  fs::remove_all(d);
}

TEST(Isa, BenchNamesTheSetItRan) {
  const std::string scene = (test::source_dir() / "examples/paper/09.toml").string();
  for (simd::Isa s : usable()) {
    const auto r = run_with(simd::name(s),
                            "bench " + scene + " --width 16 --height 12 --warm-up 0 --measure 1");
    ASSERT_EQ(r.code, 0) << r.out;
    const std::string want = std::string("BENCHMARK_ISA ") + simd::name(s) +
                             " (Embree: isa=" + (s == simd::Isa::Baseline ? "sse2" : simd::name(s));
    EXPECT_NE(r.out.find(want), std::string::npos) << "want " << want << " in:\n" << r.out;
  }
}

TEST(Isa, UnknownOrMissingSetIsAnError) {
  const std::string scene = (test::source_dir() / "examples/paper/09.toml").string();
  const auto bad = run_with("avx3", "info " + scene);
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_NE(bad.out.find("ANAMORPH_ISA=avx3 is not an instruction set (valid: avx512, avx2, "
                         "baseline)"),
            std::string::npos)
      << bad.out;
  if (simd::cpu_best() == simd::Isa::Avx512) return;  // (nothing to refuse on this CPU)
  const auto more = run_with("avx512", "info " + scene);
  EXPECT_EQ(more.code, 2) << more.out;
  EXPECT_NE(more.out.find("this CPU has no avx512"), std::string::npos) << more.out;
}

}  // namespace anamorph
