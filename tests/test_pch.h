// The headers most test files read, precompiled once per test executable (tests/CMakeLists.txt):
// GoogleTest, fmt, nlohmann::json and the standard library were most of a test file's compile
// time. Only third-party and standard headers belong here: each test file still includes what it
// uses, so it compiles the same without this header.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
