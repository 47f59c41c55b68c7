// The live preview's frames (long poll), picking and projecting through the scene's camera, the
// preview's settings, and the final render.
#include "server_fixture.h"

#include <cmath>

namespace anamorph::test {
namespace {

class PreviewTest : public ServerTest {
 protected:
  // The final render's status once it is no longer running (within 60 s), as text.
  std::string render_status_when_ended() {
    std::string last;
    EXPECT_TRUE(eventually(
        [&] {
          last = get("/api/render").body;
          const json s = json::parse(last, nullptr, false);
          return s.is_object() && s.value("state", "") != "running";
        },
        60))
        << last;
    return last;
  }
};

int64_t header_int(const Reply& r, const std::string& name) {
  const std::string v = r.header(name);
  return v.empty() ? -1 : std::stoll(v);
}

TEST_F(PreviewTest, FrameCarriesItsSizeVersionAndPixels) {
  const Reply r = get("/api/frame?after=0");
  ASSERT_EQ(r.status, 200) << r.body;
  const int64_t w = header_int(r, "x-frame-width"), h = header_int(r, "x-frame-height");
  EXPECT_GT(w, 0);
  EXPECT_GT(h, 0);
  EXPECT_LE(w, 64);
  EXPECT_LE(h, 48);
  EXPECT_EQ(header_int(r, "x-frame-version"), 1);
  EXPECT_GE(header_int(r, "x-frame-seq"), 1);
  EXPECT_EQ(int64_t(r.body.size()), w * h * 4) << w << " x " << h;
  EXPECT_EQ(r.header("content-type"), "application/octet-stream");
}

TEST_F(PreviewTest, FramesOfAnEditFollow) {
  Reply r = get("/api/frame?after=0");
  ASSERT_EQ(r.status, 200);
  int64_t seq = header_int(r, "x-frame-seq");
  const Reply e = edit("camera.fov", 30, version());
  ASSERT_EQ(e.status, 200) << e.body;
  const int64_t v = body_of(e)["version"];
  int64_t shown = -1;
  // The frames of version 1 still in flight come first; the new version's within a bound.
  for (int i = 0; i < 200 && shown != v; ++i) {
    r = get("/api/frame?timeout=5&after=" + std::to_string(seq));
    if (r.status != 200) break;  // (204: the preview rests)
    EXPECT_GT(header_int(r, "x-frame-seq"), seq);
    seq = header_int(r, "x-frame-seq");
    shown = header_int(r, "x-frame-version");
    EXPECT_EQ(int64_t(r.body.size()),
              header_int(r, "x-frame-width") * header_int(r, "x-frame-height") * 4);
  }
  EXPECT_EQ(shown, v);
  // The last pass of the new version is the full preview size.
  auto last_pass = [](const Reply& f) {
    return f.header("x-frame-coarse") == "0" &&
           f.header("x-frame-pass") == f.header("x-frame-passes");
  };
  for (int i = 0; i < 200 && !last_pass(r); ++i) {
    const Reply next = get("/api/frame?timeout=5&after=" + std::to_string(seq));
    if (next.status != 200) break;
    r = next;
    seq = header_int(r, "x-frame-seq");
  }
  EXPECT_TRUE(last_pass(r)) << "pass " << r.header("x-frame-pass") << " of "
                            << r.header("x-frame-passes") << ", coarse "
                            << r.header("x-frame-coarse");
  EXPECT_EQ(header_int(r, "x-frame-version"), v);
  EXPECT_EQ(header_int(r, "x-frame-width"), 64);
  EXPECT_EQ(header_int(r, "x-frame-height"), 48);
}

TEST_F(PreviewTest, NoNewFrameIs204) {
  const Reply r = get("/api/frame?after=1000000000&timeout=0.2");
  EXPECT_EQ(r.status, 204) << r.body;
  EXPECT_TRUE(r.body.empty());
  EXPECT_EQ(get("/api/frame?after=x").status, 400);
  // (a NaN timeout would never run out)
  const Reply nan = get("/api/frame?after=1000000000&timeout=nan");
  EXPECT_EQ(nan.status, 400) << nan.body;
}

TEST_F(PreviewTest, ClientLeavingALongPollFreesItsConnection) {
  ASSERT_TRUE(eventually([&] { return http->connections() == 0; }, 10)) << http->connections();
  {
    Connection c(port());
    c.send({"GET",
            "/api/frame?after=1000000000&timeout=30",
            "",
            {{"X-Anamorph-Token", kToken}},
            true});
    ASSERT_TRUE(eventually([&] { return http->connections() == 1; }, 10)) << http->connections();
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // (the poll is waiting)
    EXPECT_EQ(http->connections(), 1);
  }  // (closes)
  EXPECT_TRUE(eventually([&] { return http->connections() == 0; }, 5))
      << http->connections() << " connections 5 s after the client left";
  EXPECT_EQ(get("/api/state").status, 200);
}

TEST_F(PreviewTest, PickHitsTheSphereAndProjectsBack) {
  const int64_t v = version();
  const Reply r = post("/api/pick", json{{"u", 0.5}, {"v", 0.5}, {"version", v}});
  ASSERT_EQ(r.status, 200) << r.body;
  const json pick = body_of(r);
  ASSERT_EQ(pick["hit"], true) << r.body;
  EXPECT_EQ(pick["ray"], true) << r.body;
  const json p = pick["position"];
  const double dist =
      std::sqrt(p[0].get<double>() * p[0].get<double>() + p[1].get<double>() * p[1].get<double>() +
                p[2].get<double>() * p[2].get<double>());
  EXPECT_NEAR(dist, 1.0, 1e-6) << p.dump();
  EXPECT_NEAR(p[2].get<double>(), 1.0, 1e-6) << p.dump();  // the near side, facing the camera
  EXPECT_NEAR(pick["distance"].get<double>(), 4.0, 1e-6) << r.body;

  const Reply back = post("/api/project", json{{"position", p}, {"version", v}});
  ASSERT_EQ(back.status, 200) << back.body;
  const json uvs = body_of(back)["uv"];
  ASSERT_FALSE(uvs.empty()) << back.body;
  double nearest = 1e9;
  for (const json& uv : uvs)
    nearest = std::min(nearest, std::hypot(uv[0].get<double>() - 0.5, uv[1].get<double>() - 0.5));
  EXPECT_LT(nearest, 1e-6) << back.body;
}

TEST_F(PreviewTest, PickSeesTheEditedScene) {
  const Reply e = edit("object.0.center", json::array({0.0, 0.0, -1.0}), version());
  ASSERT_EQ(e.status, 200) << e.body;
  const Reply r =
      post("/api/pick", json{{"u", 0.5}, {"v", 0.5}, {"version", body_of(e)["version"]}});
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_NEAR(body_of(r)["position"][2].get<double>(), 0.0, 1e-6) << r.body;
}

TEST_F(PreviewTest, PickOutsideTheImageIs400) {
  for (const json& body :
       {json{{"u", 1.5}, {"v", 0.5}}, json{{"u", -0.1}, {"v", 0.5}}, json{{"u", 0.5}, {"v", 2}},
        json{{"u", "0.5"}, {"v", 0.5}}, json{{"v", 0.5}}}) {
    const Reply r = post("/api/pick", body);
    EXPECT_EQ(r.status, 400) << body.dump() << ": " << r.body;
  }
  const Reply r = post("/api/project", json{{"position", json::array({1, 2})}});
  EXPECT_EQ(r.status, 400) << r.body;
}

TEST_F(PreviewTest, PreviewSettingsAreReflected) {
  const Reply r = post("/api/preview", json{{"integrator", "albedo"}, {"max_spp", 2}});
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(body_of(r)["integrator"], "albedo") << r.body;
  EXPECT_EQ(body_of(r)["max_spp"], 2) << r.body;
  const Reply g = get("/api/preview");
  EXPECT_EQ(body_of(g)["integrator"], "albedo") << g.body;
  EXPECT_EQ(body_of(g)["max_spp"], 2) << g.body;

  const Reply bad = post("/api/preview", json{{"integrator", "raymarcher"}});
  EXPECT_EQ(bad.status, 400) << bad.body;
  EXPECT_NE(body_of(bad).value("error", "").find("raymarcher"), std::string::npos) << bad.body;
  EXPECT_EQ(post("/api/preview", json{{"integrator", 3}}).status, 400);
  EXPECT_EQ(post("/api/preview", json{{"max_spp", 0}}).status, 400);
  EXPECT_EQ(body_of(get("/api/preview"))["integrator"], "albedo");

  const Reply scene = post("/api/preview", json{{"integrator", "scene"}});
  EXPECT_EQ(body_of(scene)["integrator"], "scene") << scene.body;
}

// With denoise on, the settled path-traced preview (4 samples a pixel) is followed by a denoised
// frame of the same version and size: other pixels (the noise filtered), the same mean colour
// within 10 %.
TEST_F(PreviewTest, DenoisedFrameFollowsTheSettledOne) {
  EXPECT_EQ(post("/api/preview", json{{"denoise", 1}}).status, 400);
  const Reply e = edit("render.spp", 4, version());  // (the scene's 1 sample cannot be halved)
  ASSERT_EQ(e.status, 200) << e.body;
  const Reply s =
      post("/api/preview", json{{"integrator", "path"}, {"max_spp", 4}, {"denoise", true}});
  ASSERT_EQ(s.status, 200) << s.body;
  EXPECT_EQ(body_of(s)["denoise"], true) << s.body;
  const auto mean = [](const std::string& rgba) {
    double m = 0;
    for (size_t i = 0; i < rgba.size(); ++i)
      if (i % 4 != 3) m += uint8_t(rgba[i]);
    return m / double(rgba.size());
  };
  Reply settled, denoised;
  int64_t seq = 0;
  for (int i = 0; i < 200 && denoised.status != 200; ++i) {
    const Reply r = get("/api/frame?timeout=5&after=" + std::to_string(seq));
    ASSERT_EQ(r.status, 200) << "no denoised frame came";
    seq = header_int(r, "x-frame-seq");
    if (r.header("x-frame-denoised") == "1") {
      denoised = r;
    } else if (header_int(r, "x-frame-pass") == header_int(r, "x-frame-passes") &&
               header_int(r, "x-frame-pass") > 0) {
      settled = r;
    }
  }
  ASSERT_EQ(settled.status, 200) << "no settled frame before the denoised one";
  EXPECT_EQ(denoised.header("x-frame-version"), settled.header("x-frame-version"));
  EXPECT_EQ(denoised.header("x-frame-width"), settled.header("x-frame-width"));
  EXPECT_EQ(denoised.header("x-frame-height"), settled.header("x-frame-height"));
  ASSERT_EQ(denoised.body.size(), settled.body.size());
  EXPECT_NE(denoised.body, settled.body) << "the denoiser changed nothing";
  EXPECT_NEAR(mean(denoised.body) / mean(settled.body), 1.0, 0.1);
}

TEST_F(PreviewTest, FinalRenderGivesAPng) {
  EXPECT_EQ(get("/api/render/result.png").status, 404);
  const Reply start = post("/api/render", json{{"png", true}});
  ASSERT_EQ(start.status, 200) << start.body;
  const std::string last = render_status_when_ended();
  EXPECT_EQ(json::parse(last, nullptr, false).value("state", ""), "done") << last;
  const Reply png = get("/api/render/result.png");
  ASSERT_EQ(png.status, 200) << png.body.substr(0, 200);
  EXPECT_EQ(png.header("content-type"), "image/png");
  EXPECT_EQ(png.body.substr(0, 4), "\x89PNG");
  // The bytes of the file the render wrote, named for the download.
  const std::string disposition = png.header("content-disposition");
  const size_t q = disposition.find("filename=\"");
  ASSERT_NE(q, std::string::npos) << disposition;
  const std::string name = disposition.substr(q + 10, disposition.size() - q - 11);
  const auto written = fs::path(json::parse(last)["folder"].get<std::string>()) / name;
  EXPECT_TRUE(png.body == read_text(written)) << "the download differs from " << written;
  EXPECT_EQ(get("/api/render/result.exr").status, 404);              // (none asked for)
  EXPECT_EQ(post("/api/render", json{{"png", false}}).status, 400);  // (neither file asked for)
  // Formats by the sinks' names: each offered in the status, an unknown one refused by name.
  const json status = json::parse(last);
  std::vector<std::string> available;
  for (const json& f : status["available"]) available.push_back(f["name"]);
  EXPECT_EQ(available, (std::vector<std::string>{"png", "exr"})) << last;
  EXPECT_EQ(status["formats"], json::array({"png"})) << last;
  const Reply tiff = post("/api/render", json{{"formats", {"exr", "tiff"}}});
  EXPECT_EQ(tiff.status, 400) << tiff.body;
  EXPECT_CONTAINS(tiff.body, "'tiff' (png, exr)");
  // (A .flo file holds flow only: not a format of the editor's final render.)
  const Reply flo = post("/api/render", json{{"formats", {"flo"}}});
  EXPECT_EQ(flo.status, 400) << flo.body;
  EXPECT_EQ(post("/api/render", json{{"formats", json::array()}}).status, 400);
  EXPECT_EQ(post("/api/render", json{{"formats", "exr"}}).status, 400);
}

TEST_F(PreviewTest, FinalRenderGivesAnExrByItsSinkName) {
  const Reply start = post("/api/render", json{{"formats", {"exr"}}});
  ASSERT_EQ(start.status, 200) << start.body;
  const std::string last = render_status_when_ended();
  const json s = json::parse(last);
  EXPECT_EQ(s["formats"], json::array({"exr"})) << last;
  EXPECT_EQ(s["exr"], true);
  EXPECT_EQ(s["png"], false);
  EXPECT_EQ(get("/api/render/result.png").status, 404);
  const Reply exr = get("/api/render/result.exr");
  ASSERT_EQ(exr.status, 200) << exr.body.substr(0, 200);
  EXPECT_EQ(exr.header("content-type"), "image/x-exr");
  EXPECT_EQ(exr.body.substr(0, 4), "\x76\x2f\x31\x01") << "OpenEXR's magic number";
  EXPECT_EQ(get("/api/render/result.tif").status, 404);
}

}  // namespace
}  // namespace anamorph::test
