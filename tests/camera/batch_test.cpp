// Batched ray generation (the renderer's packets) gives exactly the rays of generate().
#include <gtest/gtest.h>

#include <cstring>

#include "camera/presets.h"
#include "math/rng.h"

namespace anamorph {

TEST(CameraBatch, SameBitsAsOneByOne) {
  const char* cases[][2] = {
      {"perspective", "fov = 70\nlook_from = [1, 2, 3]\nlook_at = [0, 0, 0]"},
      {"orthographic", "view_width = 3\nlook_from = [1, 2, 3]\nlook_at = [0, 0, 0]"},
      {"fisheye", "fov = 190"}};
  for (const auto& c : cases) {
    const VirtualCamera cam(make_preset(c[0], c[1], {640, 480}));
    Rng rng(5, 6);
    CameraSample s[37];
    for (auto& x : s)
      x.uv = {rng.uniform(), rng.uniform()}, x.lens = {rng.uniform(), rng.uniform()};
    CameraRay out[37];
    bool valid[37];
    cam.generate_batch(s, 37, out, valid);
    for (int i = 0; i < 37; ++i) {
      const auto r = cam.generate(s[i]);
      ASSERT_EQ(valid[i], bool(r)) << c[0] << " sample " << i;
      if (r) {
        EXPECT_EQ(0, std::memcmp(&out[i], &*r, sizeof(CameraRay))) << c[0] << " sample " << i;
      }
    }
  }
}

}  // namespace anamorph
