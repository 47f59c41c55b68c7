// Helpers shared by tests: where fixtures live, and skipping when ../shared is absent.
#pragma once

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "math/sanitizers.h"

namespace anamorph::test {

inline std::filesystem::path data_dir() { return ANAMORPH_TEST_DATA; }
inline std::filesystem::path source_dir() { return ANAMORPH_SOURCE_DIR; }
inline std::filesystem::path binary() { return ANAMORPH_BINARY; }
inline std::filesystem::path shared_scenes() { return ANAMORPH_SHARED_SCENES; }
// A file's bytes as text ("" when it cannot be read).
inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
inline bool have_shared() { return std::filesystem::exists(shared_scenes() / "MANIFEST.md"); }

// Whether this build runs under AddressSanitizer or ThreadSanitizer: 5-20x slower, so end-to-end
// renders there use smaller images (the same code paths; the suite's time is bounded).
#if defined(ANAMORPH_ASAN) || defined(ANAMORPH_TSAN)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif
// An image side for an end-to-end render: `n`, or half of it under the sanitizers.
inline std::string side(int n) { return std::to_string(kSanitized ? n / 2 : n); }
// Samples a pixel for an end-to-end render: `n`, or a quarter of it under the sanitizers.
inline int spp(int n) { return kSanitized ? std::max(1, n / 4) : n; }

}  // namespace anamorph::test

// Expects `hay` (a message or a command's output) to contain `needle`, printing `hay` when not.
#define EXPECT_CONTAINS(hay, needle) \
  EXPECT_NE(std::string(hay).find(needle), std::string::npos) << "output was:\n" << (hay)

// Skips the current test with a clear message when ../shared/scenes is not beside the repo.
#define ANAMORPH_REQUIRE_SHARED()                                                           \
  do {                                                                                      \
    if (!::anamorph::test::have_shared())                                                   \
      GTEST_SKIP() << "../shared/scenes not found at " << ::anamorph::test::shared_scenes() \
                   << ": skipping test that needs third-party models";                      \
  } while (0)
