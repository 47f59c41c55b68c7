// --threads of the commands that render: the library's one thread-count check (math/parallel.h),
// which the Python module's threads= goes through too, as a CLI11 validator.
#pragma once

#include <CLI/CLI.hpp>

#include <cerrno>
#include <cstdlib>
#include <string>

#include "math/parallel.h"

namespace anamorph::app {

inline CLI::Validator thread_count_check() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        char* end = nullptr;
        errno = 0;
        const long long n = std::strtoll(text.c_str(), &end, 10);
        if (end == text.c_str() || *end != '\0' || errno == ERANGE)
          return "expected a whole number of threads, got '" + text + "'";
        return thread_count_error(n);
      },
      "0 (all cores) to " + std::to_string(kMaxThreads), "THREADS");
}

}  // namespace anamorph::app
