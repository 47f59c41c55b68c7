// Comparing a render's output files bit for bit (checkpoint/resume and MPI tests: the same
// render reached another way must give the same bits in every layer).
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "io/image_io.h"

namespace anamorph::test {

// Every channel of two EXRs equal, bit for bit; names the first difference.
inline void expect_same_exr(const std::filesystem::path& a, const std::filesystem::path& b) {
  int wa = 0, ha = 0, wb = 0, hb = 0;
  const auto ca = read_exr_channels(a, &wa, &ha), cb = read_exr_channels(b, &wb, &hb);
  ASSERT_EQ(wa, wb);
  ASSERT_EQ(ha, hb);
  ASSERT_EQ(ca.size(), cb.size());
  for (const auto& [name, values] : ca) {
    ASSERT_TRUE(cb.count(name)) << name;
    const auto& other = cb.at(name);
    for (size_t i = 0; i < values.size(); ++i)
      if (std::memcmp(&values[i], &other[i], sizeof(float)) != 0) {
        ADD_FAILURE() << "channel " << name << " differs at pixel " << i % size_t(wa) << ","
                      << i / size_t(wa) << ": " << values[i] << " vs " << other[i];
        return;
      }
  }
}

// The pixels of two PNGs (decoded RGBA) equal.
inline void expect_same_png(const std::filesystem::path& a, const std::filesystem::path& b) {
  const Image ia = read_image(a, false), ib = read_image(b, false);
  ASSERT_EQ(ia.width, ib.width);
  ASSERT_EQ(ia.height, ib.height);
  for (size_t i = 0; i < ia.pixels.size(); ++i)
    if (ia.pixels[i] != ib.pixels[i]) {
      ADD_FAILURE() << "PNG value " << i << " differs: " << ia.pixels[i] << " vs " << ib.pixels[i];
      return;
    }
}

// Every layer of the render `out` equals the reference `ref`: the EXR, or the PNG and, with AOVs,
// the EXR beside it.
inline void expect_same_outputs(const std::filesystem::path& ref, const std::filesystem::path& out,
                                const std::string& ext, bool aovs) {
  if (ext == ".exr") {
    expect_same_exr(ref, out);
    return;
  }
  expect_same_png(ref, out);
  if (aovs)
    expect_same_exr(std::filesystem::path(ref).replace_extension(".exr"),
                    std::filesystem::path(out).replace_extension(".exr"));
}

}  // namespace anamorph::test
