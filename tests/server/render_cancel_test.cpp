// The final render stops when asked: Cancel on the page, or the server stopping while it runs.
// The renderer here stands in for a long `anamorph render`: it runs until its cancel flag is set
// (or 20 s pass, which fails the test) and then throws, as the real one does when interrupted.
#include <atomic>

#include "server_fixture.h"

namespace anamorph::test {
namespace {

struct LongRender {
  std::atomic<bool> started{false}, saw_cancel{false};
  void operator()(const server::FinalRenderJob& j) {
    started = true;
    if (!eventually([&] { return j.cancel && j.cancel->load(); }, 20)) return;
    saw_cancel = true;
    throw std::runtime_error("cancelled");
  }
};

TEST(FinalRender, CancelStopsItAndSaysSo) {
  TempFolder dir;
  LongRender render;
  server::Editor editor(dir.write("scene.toml", kScene), std::ref(render));
  EXPECT_FALSE(editor.cancel_render()) << "nothing runs yet";
  ASSERT_FALSE(editor.start_render({}));
  ASSERT_TRUE(eventually([&] { return render.started.load(); }));
  EXPECT_EQ(editor.render_status()["state"], "running");
  EXPECT_TRUE(editor.start_render({})) << "one render at a time";
  EXPECT_TRUE(editor.cancel_render());
  // (compared as a std::string: GCC 12 warns, wrongly, of an out-of-bounds access when it inlines
  // json == const char* into this lambda)
  ASSERT_TRUE(eventually([&] {
    return editor.render_status()["state"].get<std::string>() == std::string("cancelled");
  })) << editor.render_status().dump();
  EXPECT_TRUE(render.saw_cancel);
  EXPECT_EQ(editor.render_status()["error"], "");
  EXPECT_FALSE(editor.render_result("png")) << "a cancelled render offers no file";
}

TEST(FinalRender, AServerThatStopsCancelsItsRender) {
  TempFolder dir;
  LongRender render;
  {
    server::Editor editor(dir.write("scene.toml", kScene), std::ref(render));
    ASSERT_FALSE(editor.start_render({}));
    ASSERT_TRUE(eventually([&] { return render.started.load(); }));
  }  // (the editor goes: its render must not run on to its end)
  EXPECT_TRUE(render.saw_cancel);
}

}  // namespace
}  // namespace anamorph::test
