// A render stopped by render.time_limit, run again and again until it completes (checkpoint and
// MPI tests): every run exits 0 and writes the image so far, a stopped run keeps its checkpoint,
// and the runs end.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>

#include "app/cli_util.h"

namespace anamorph::test {

struct BudgetRuns {
  int runs = 1;     // runs made, the first included
  int limited = 0;  // runs a time limit stopped
};

// `r`: the first run's result; `again()` runs the resumed command; `on_limited(r, run)` checks
// a stopped run's output. Returns with a fatal failure when a run fails.
inline void resume_until_complete(
    CliResult r, const std::filesystem::path& out, const std::filesystem::path& ck,
    const std::function<CliResult()>& again, BudgetRuns* counts,
    const std::function<void(const CliResult&, int)>& on_limited = {}) {
  for (;; ++counts->runs) {
    ASSERT_EQ(r.code, 0) << r.out;
    ASSERT_TRUE(std::filesystem::exists(out))
        << "run " << counts->runs << " wrote no image: " << r.out;
    if (r.out.find("time limit of") == std::string::npos) return;
    ++counts->limited;
    ASSERT_TRUE(std::filesystem::exists(ck)) << r.out;
    if (on_limited) on_limited(r, counts->runs);
    ASSERT_LT(counts->runs, 200) << "the render does not get further";
    r = again();
  }
}

}  // namespace anamorph::test
