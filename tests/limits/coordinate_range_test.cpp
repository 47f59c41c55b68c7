// Coordinates of any size never reach Embree beyond what it takes (it asserted, aborting the
// process, once a ray passed 1.8e18): random scenes with huge, tiny and ordinary positions,
// radii, transforms (composed with a model's own node transforms), camera positions and ray-table
// samples either load and render, every camera ray starting within the world, or are refused
// with an error at the file, line, column and key that put them there; through the scene reader
// and the renderer, and through the editor's edits (whose server must go on). Python:
// python/tests/test_limits.py.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "accel/accel.h"
#include "math/input_limits.h"
#include "render/film.h"
#include "render/renderer.h"
#include "scene/scene_loader.h"
#include "scene/toml_reader.h"
#include "server/server_fixture.h"

namespace anamorph::test {
namespace {

// A number of any magnitude: mostly ordinary (0.01 to 100), one in ten zero, huge (to 1e308),
// tiny (to 1e-308) or around the world's bound, either sign. (A scene draws some 30 numbers: one
// in three scenes has none out of range and renders.)
double wild(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  const double sign = u(rng) < 0.5 ? -1 : 1;
  switch (u(rng) < 0.9 ? 4 : std::uniform_int_distribution<int>(0, 3)(rng)) {
    case 0:
      return 0;
    case 1:
      return sign * std::pow(10.0, 11 + u(rng) * 297);  // huge: 1e11 to 1e308
    case 2:
      return sign * std::pow(10.0, -308 + u(rng) * 298);  // tiny: 1e-308 to 1e-10
    case 3:
      return sign * (kMaxCoordinate * (0.5 + u(rng)));  // around the bound
    default:
      return sign * std::pow(10.0, -2 + u(rng) * 4);  // ordinary: 0.01 to 100
  }
}
double positive(std::mt19937_64& rng) {
  const double x = std::abs(wild(rng));
  return x > 0 ? x : 1;
}

std::string num(double x) { return fmt::format("{:.17g}", x); }
std::string vec(std::mt19937_64& rng) {
  return fmt::format("[{}, {}, {}]", num(wild(rng)), num(wild(rng)), num(wild(rng)));
}
std::string transform(std::mt19937_64& rng) {
  return fmt::format("{{ scale = {}, translate = {} }}", num(positive(rng)), vec(rng));
}

// The model the scenes place: a quad used by two nodes (an instanced prototype), one of them
// scaled by `node_scale` in the file itself.
std::string model_with_node_scale(double node_scale) {
  std::string text = read_text(data_dir() / "models/shared_mesh.gltf");
  const std::string from = "\"matrix\": [\n    2,\n    0,\n    0,\n    0,\n    0,\n    2,";
  const size_t at = text.find(from);
  if (at == std::string::npos) return text;
  return text.replace(
      at, from.size(),
      fmt::format("\"matrix\": [\n    {0},\n    0,\n    0,\n    0,\n    0,\n    {0},",
                  num(node_scale)));
}

// A random scene: one camera (a preset, maybe with a coin, or a ray table), each kind of analytic
// shape, the model, a point light, every position, size and transform drawn by `wild`.
std::string random_scene(std::mt19937_64& rng, const std::string& model) {
  std::string s =
      "[image]\nwidth = 6\nheight = 4\n[render]\nintegrator = \"whitted\"\n"
      "max_depth = 3\n";
  if (rng() % 4 == 0) {
    const auto grid = [&](bool zeros) {
      std::string g = "[";
      for (int j = 0; j < 2; ++j) {
        g += j ? ", [" : "[";
        for (int i = 0; i < 2; ++i) g += (i ? ", " : "") + (zeros ? "[0, 0, 0]" : vec(rng));
        g += "]";
      }
      return g + "]";
    };
    s += "[camera.org]\ntype = \"table\"\nsamples = " + grid(false) +
         "\n[camera.dir]\ntype = \"table\"\nsamples = " + grid(rng() % 3 == 0) + "\n";
  } else {
    static const char* const kPresets[] = {"perspective", "fisheye", "orthographic"};
    s += fmt::format("[camera]\npreset = \"{}\"\nlook_from = {}\nlook_at = {}\n",
                     kPresets[rng() % 3], vec(rng), vec(rng));
    if (rng() % 3 == 0) s += "transform = " + transform(rng) + "\n";
    // (Coins deform the ray field after org and dir: their rays are checked as well.)
    if (rng() % 3 == 0) s += "[[camera.coin]]\nposition = " + vec(rng) + "\n";
  }
  s += "[[material]]\nname = \"m\"\nreflectivity = 0.5\n";
  const auto object = [&](const std::string& keys) {
    s += "[[object]]\nmaterial = \"m\"\n" + keys;
    if (rng() % 3 == 0) s += "transform = " + transform(rng) + "\n";
  };
  object(
      fmt::format("type = \"sphere\"\ncenter = {}\nradius = {}\n", vec(rng), num(positive(rng))));
  object(fmt::format("type = \"plane\"\npoint = {}\nnormal = {}\n", vec(rng), vec(rng)));
  object(fmt::format(
      "type = \"box\"\ncenter = {}\nsize = {}\n", vec(rng),
      fmt::format("[{}, {}, {}]", num(positive(rng)), num(positive(rng)), num(positive(rng)))));
  object(fmt::format("type = \"cylinder\"\nbase = {}\ntop = {}\nradius = {}\n", vec(rng), vec(rng),
                     num(positive(rng))));
  object(fmt::format("type = \"disk\"\ncenter = {}\nnormal = {}\nradius = {}\n", vec(rng), vec(rng),
                     num(positive(rng))));
  object(fmt::format("type = \"mesh\"\nfile = \"{}\"\n", model));
  s += fmt::format("[[light]]\ntype = \"point\"\nposition = {}\n", vec(rng));
  return s;
}

// A scene is refused at a place in its text and a key, never by anything else.
void expect_located(const SceneError& e, const std::string& scene) {
  EXPECT_GT(e.loc.line, 0) << e.what() << "\n" << scene;
  EXPECT_FALSE(e.key.empty()) << e.what() << "\n" << scene;
}

TEST(CoordinateRange, RandomScenesLoadAndRenderOrAreRefusedAtTheirKey) {
  TempFolder dir;
  std::mt19937_64 rng(20261127);
  const int scenes = kSanitized ? 150 : 400;
  int loaded = 0, refused = 0, rays = 0;
  for (int k = 0; k < scenes; ++k) {
    const double node_scale = rng() % 2 ? positive(rng) : 2.0;
    const fs::path model =
        dir.write(fmt::format("model{}.gltf", k), model_with_node_scale(node_scale));
    const std::string text = random_scene(rng, model.string());
    SCOPED_TRACE(fmt::format("scene {} (model node scale {}):\n{}", k, node_scale, text));
    std::optional<Scene> scene;
    try {
      scene.emplace(load_scene_from_string(text, dir.path() / "random.toml"));
    } catch (const SceneError& e) {
      expect_located(e, text);
      ++refused;
      continue;
    }
    ++loaded;
    // Every camera ray starts within the world with a finite unit direction, and a packet
    // (the renderer's primary rays) has exactly the single rays.
    CameraSample cs[16];
    for (int i = 0; i < 16; ++i) cs[i].uv = {(i % 4 + 0.5) / 4, (i / 4 + 0.5) / 4};
    CameraRayBatch batch;
    scene->camera->generate_batch(cs, 16, &batch);
    for (int i = 0; i < 16; ++i) {
      const auto r = scene->camera->generate(cs[i]);
      ASSERT_EQ(bool(r), batch.valid[i]) << "sample " << i;
      if (!r) continue;
      ++rays;
      EXPECT_TRUE(within_world(r->org)) << r->org.x << " " << r->org.y << " " << r->org.z;
      EXPECT_NEAR(length(r->dir), 1, 1e-9);
      EXPECT_TRUE(r->org == batch.origin(i) && r->dir == batch.direction(i)) << "sample " << i;
    }
    // And the renderer traces them and what they hit (shadow and mirror rays) without Embree
    // ever seeing a ray it asserts on.
    const Renderer renderer(*scene);
    Film film(scene->render.width, scene->render.height, {});
    RenderOptions opt;
    opt.threads = 1;
    renderer.render(film, opt);
  }
  std::printf("%d scenes loaded and rendered (%d camera rays), %d refused at their key\n", loaded,
              rays, refused);
  EXPECT_GT(loaded, scenes / 10) << "too few scenes loaded for the renderer to be tested";
  EXPECT_GT(refused, scenes / 10);
}

// A model used twice (an Embree instance) scaled by 1e-12 and seen from 1e7 away: Embree carries
// the ray into the instance's space, 1e19 from its origin, beyond the floats it takes, and the
// model was silently missed. Such an instance is moved to world space (accel.cpp, instanceable).
TEST(CoordinateRange, ATinyInstanceFarFromTheRayIsHit) {
  TempFolder dir;
  json g = json::parse(read_text(data_dir() / "models/shared_mesh.gltf"));
  g["nodes"][1] = {{"name", "a"}, {"mesh", 0}, {"scale", {1e-12, 1e-12, 1e-12}}};
  g["nodes"][2] = {
      {"name", "b"}, {"mesh", 0}, {"scale", {1e-12, 1e-12, 1e-12}}, {"translation", {2e-12, 0, 0}}};
  const fs::path model = dir.write("tiny.gltf", g.dump());
  const Scene scene = load_scene_from_string(
      "[[object]]\ntype = \"mesh\"\nfile = \"" + model.string() + "\"\n", dir.path() / "s.toml");
  ASSERT_EQ(scene.instances.size(), 2u);
  const Accel accel(scene);
  Hit hit;
  ASSERT_TRUE(accel.intersect(Ray{{5e-13, 5e-13, 1e7}, {0, 0, -1}}, &hit));
  // Embree's t is a float: at 1e7 one step of it is 1. Its AVX-512 kernels return 1e7 here, the
  // AVX2 ones 9999999 (measured on an AVX2-only EPYC); the point is that the instance is hit.
  EXPECT_NEAR(hit.t, 1e7, 1.0);
  ASSERT_TRUE(accel.intersect(Ray{{2.5e-12, 5e-13, 1e7}, {0, 0, -1}}, &hit));
}

// The packet test in float (ray_in_range_f, which vectorizes) answers as ray_in_range does for
// every float ray: at the floats next to both limits, zero, infinity and NaN, in each component.
TEST(CoordinateRange, TheFloatRayTestAgreesWithTheDoubleOne) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::nanf("");
  std::vector<float> values{0.0f, -0.0f, 1.0f, -3.5f, inf, -inf, nan};
  for (const double limit : {kMaxCoordinate, 4 * kMaxCoordinate}) {
    const float f = float(limit);
    for (const float x : {std::nextafter(f, 0.0f), f, std::nextafter(f, inf)})
      values.insert(values.end(), {x, -x});
  }
  int tested = 0, taken = 0;
  for (int c = 0; c < 6; ++c)
    for (const float x : values) {
      float r[6] = {1, 2, 3, 0.5f, -0.25f, 1};
      r[c] = x;
      const bool want = ray_in_range({r[0], r[1], r[2]}, {r[3], r[4], r[5]});
      const int got = ray_in_range_f(r[0], r[1], r[2], r[3], r[4], r[5]);
      EXPECT_EQ(got, want ? 1 : 0) << "component " << c << " = " << fmt::format("{:.9g}", x);
      ++tested, taken += want;
    }
  // A zero direction only when all three are zero.
  EXPECT_EQ(ray_in_range_f(0, 0, 0, 0, 0, 0), 0);
  EXPECT_EQ(ray_in_range_f(0, 0, 0, 0, -0.0f, 1e-45f), 1);
  EXPECT_GT(taken, 0);
  EXPECT_LT(taken, tested);
}

// The same values as edits to the editor's document: each is taken (and previewed) or answered
// 400 with the key, and the server serves the next request.
class CoordinateRangeEditor : public ServerTest {
 protected:
  // Waits for a preview frame of the document's current version (the preview thread renders
  // it: a fault there would end the test process).
  void expect_preview_of(int64_t v) {
    int64_t seq = 0;
    for (int i = 0; i < 40; ++i) {
      const Reply r = get("/api/frame?timeout=5&after=" + std::to_string(seq));
      ASSERT_TRUE(r.status == 200 || r.status == 204) << r.status << " " << r.body;
      if (r.status == 204) continue;
      seq = std::stoll(r.header("x-frame-seq"));
      if (std::stoll(r.header("x-frame-version")) >= v) return;
    }
    ADD_FAILURE() << "no preview frame of version " << v;
  }
};

TEST_F(CoordinateRangeEditor, RandomEditsAreTakenOrAnswered400AndTheServerGoesOn) {
  std::mt19937_64 rng(7);
  int taken = 0, refused = 0;
  const int edits = kSanitized ? 30 : 80;
  for (int k = 0; k < edits; ++k) {
    static const char* const kKeys[] = {"camera.look_from", "object.0.center", "object.1.point",
                                        "light.0.position"};
    const int64_t v = version();
    const std::string which = k % 5 == 4 ? "object.0.radius" : kKeys[rng() % 4];
    const json value = which == "object.0.radius" ? json(positive(rng))
                                                  : json::array({wild(rng), wild(rng), wild(rng)});
    const Reply r = edit(which, value, v);
    SCOPED_TRACE(which + " = " + value.dump() + ": " + std::to_string(r.status) + " " + r.body);
    if (r.status == 200) {
      ++taken;
      expect_preview_of(v + 1);
    } else {
      ++refused;
      EXPECT_EQ(r.status, 400);
      // (The reader names array entries as object[0]; the edit as object.0.)
      std::string key;
      for (char c : body_of(r).value("key", ""))
        if (c != ']') key += c == '[' ? '.' : c;
      EXPECT_EQ(key.substr(0, key.rfind('.')), which.substr(0, which.rfind('.')));
    }
    ASSERT_EQ(get("/api/state").status, 200);
  }
  EXPECT_GT(taken, 0);
  EXPECT_GT(refused, 0);
}

}  // namespace
}  // namespace anamorph::test
