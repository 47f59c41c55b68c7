// Every reader of recursive input has a depth limit: for each one, input nested just past its
// limit and 100,000 levels deep is refused with a message saying so (and the process, and the
// editor's server, go on), while input nested just within it reads on (whatever else it then
// finds wrong). A reader added without a bound joins the table below and fails here.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "camera/functions.h"
#include "math/input_limits.h"
#include "params/toml_parse.h"
#include "scene/loaders.h"
#include "scene/scene_loader.h"
#include "server/server_fixture.h"

namespace anamorph::test {
namespace {

std::string repeat(const std::string& s, int n) {
  std::string r;
  r.reserve(s.size() * size_t(n));
  for (int i = 0; i < n; ++i) r += s;
  return r;
}
// "a.a.a" with n parts.
std::string dotted(int n) {
  std::string r = "a";
  for (int i = 1; i < n; ++i) r += ".a";
  return r;
}
std::string arrays(int n) { return repeat("[", n) + repeat("]", n); }
std::string json_arrays(int n) { return arrays(n); }

// The editor's server of a test, its requests open to the readers below.
class Editor : public ServerTest {
 public:
  using ServerTest::get;
  using ServerTest::post;
  using ServerTest::version;
  const TempFolder& folder() const { return dir; }
};

// What a reader does with input nested n levels deep: "" when it reads it without a nesting
// error (it may still refuse it for another reason), else the error.
using Read = std::function<std::string(int n, Editor& server)>;

struct Reader {
  const char* name;
  int limit;         // the deepest input it reads
  const char* says;  // in its message beyond the limit
  Read read;
  int first_refused = 0;  // the shallowest input it refuses (0: limit + 1)
};

// The message of what `f` throws, "" when it throws nothing about nesting.
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

std::string scene_text(const std::string& body) {
  return error_of([&] { load_scene_from_string(body, "deep.toml"); });
}

// The editor's answer to an edit, as "status: body".
std::string edit_answer(Editor& s, const std::string& body) {
  const Reply r = s.post("/api/edit", body);
  return r.status == 200 ? "" : std::to_string(r.status) + ": " + r.body;
}
std::string edit_body(Editor& s, const std::string& edit) {
  return "{\"version\": " + std::to_string(s.version()) + ", \"edits\": [" + edit + "]}";
}

// A .glb of `json` as its JSON chunk (padded with spaces, as the format asks), no binary chunk.
std::string glb(std::string json) {
  while (json.size() % 4) json += ' ';
  std::string out = "glTF";
  const auto u32 = [&](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
  u32(2);
  u32(uint32_t(12 + 8 + json.size()));
  u32(uint32_t(json.size()));
  out += "JSON";
  return out + json;
}

std::string model_file(Editor& s, const std::string& name, const std::string& bytes) {
  const fs::path p = s.folder().write(name, bytes);
  return error_of([&] { load_model(p); });
}

const Reader kReaders[] = {
    {"scene_dotted_key", kMaxNesting, "nested more than",
     [](int n, Editor&) { return scene_text(dotted(n) + " = 1\n"); }},
    {"scene_table_header", kMaxNesting, "nested more than",
     [](int n, Editor&) { return scene_text("[" + dotted(n) + "]\n"); }},
    {"scene_array_of_tables_header", kMaxNesting - 1, "nested more than",
     [](int n, Editor&) { return scene_text("[[" + dotted(n) + "]]\n"); }},
    {"scene_dotted_key_under_a_header", kMaxNesting - 1, "nested more than",
     [](int n, Editor&) { return scene_text("[image]\n\"a\"." + dotted(n - 1) + " = 1\n"); }},
    {"scene_arrays", kMaxNesting - 1, "nested more than",
     [](int n, Editor&) { return scene_text("x = " + arrays(n) + "\n"); }},
    {"scene_inline_tables", kMaxNesting - 1, "nested more than",
     [](int n, Editor&) {
       return scene_text("x = " + repeat("{ a = ", n) + "1" + repeat(" }", n) + "\n");
     }},
    {"scene_included_file", kMaxNesting, "nested more than",
     [](int n, Editor& s) {
       s.folder().write("deep_part.toml", dotted(n) + " = 1\n");
       const fs::path main = s.folder().write("main.toml", "include = \"deep_part.toml\"\n");
       return error_of([&] { load_scene(main); });
     }},
    {"set_key", kMaxNesting, "nests deeper than",
     [](int n, Editor&) {
       return error_of([&] { load_scene_from_string(kScene, "s.toml", {dotted(n) + "=1"}); });
     }},
    {"set_value", kMaxNesting - 1, "nested more than",
     [](int n, Editor&) {
       return error_of(
           [&] { load_scene_from_string(kScene, "s.toml", {"camera.fov=" + arrays(n)}); });
     }},
    {"animate_key", kMaxNesting, "nests deeper than",
     [](int n, Editor&) {
       return scene_text(kScene + "[[animate]]\nkey = \"" + dotted(n) +
                         "\"\nkeys = [[0, 1], [1, 2]]\n");
     }},
    {"camera_table_text", kMaxNesting - 1, "nested more than",
     [](int n, Editor&) { return error_of([&] { make_org("sphere", "radius = " + arrays(n)); }); }},
    {"editor_edit_value_json", kMaxNesting - 3, "nested more than",
     [](int n, Editor& s) {
       return edit_answer(
           s, edit_body(s, "{\"key\": \"camera.fov\", \"value\": " + json_arrays(n) + "}"));
     }},
    {"editor_edit_key", kMaxNesting, "nests deeper than",
     [](int n, Editor& s) {
       return edit_answer(s, edit_body(s, "{\"key\": \"" + dotted(n) + "\", \"value\": 1}"));
     }},
    // (The value sits under camera.fov: two levels more in the document.)
    {"editor_edit_toml_text", kMaxNesting - 2, "nested more than",
     [](int n, Editor& s) {
       return edit_answer(
           s, edit_body(s, "{\"key\": \"camera.fov\", \"toml\": \"" + arrays(n) + "\"}"));
     }},
    {"editor_request_body", kMaxNesting - 1, "nested more than",
     [](int n, Editor& s) {
       const Reply r = s.post("/api/preview", "{\"x\": " + json_arrays(n) + "}");
       return r.status == 200 ? "" : std::to_string(r.status) + ": " + r.body;
     }},
    {"gltf_json", kMaxNesting - 1, "nested more than",
     [](int n, Editor& s) {
       return model_file(s, "deep.gltf",
                         "{\"asset\": {\"version\": \"2.0\"}, \"extras\": " + json_arrays(n) + "}");
     }},
    {"glb_json_chunk", kMaxNesting - 1, "nested more than",
     [](int n, Editor& s) {
       return model_file(
           s, "deep.glb",
           glb("{\"asset\": {\"version\": \"2.0\"}, \"extras\": " + json_arrays(n) + "}"));
     }},
    // muParser bounds an expression's length (20,000 characters), which bounds its parentheses:
    // 9,000 levels parse, 10,000 are refused. (Its parser keeps stacks of its own, no recursion.)
    {"camera_expression", 9000, "Expression too long",
     [](int n, Editor&) {
       return scene_text(
           "[camera.org]\ntype = \"point\"\n[camera.dir]\ntype = \"expression\"\nx = \"" +
           repeat("(", n) + "u" + repeat(")", n) + "\"\ny = \"v\"\nz = \"-1\"\n");
     },
     10000},
};

void PrintTo(const Reader& r, std::ostream* os) { *os << r.name; }

class DepthLimit : public Editor, public ::testing::WithParamInterface<Reader> {};

TEST_P(DepthLimit, DeepInputIsRefusedAndShallowInputIsRead) {
  const Reader& r = GetParam();
  const std::string within = r.read(r.limit, *this);
  EXPECT_EQ(within.find(r.says), std::string::npos)
      << r.name << " refused input " << r.limit << " levels deep: " << within.substr(0, 400);
  for (int n : {r.first_refused ? r.first_refused : r.limit + 1, 100000}) {
    const std::string beyond = r.read(n, *this);
    EXPECT_NE(beyond.find(r.says), std::string::npos)
        << r.name << ", " << n << " levels deep: " << beyond.substr(0, 400);
    EXPECT_LT(beyond.size(), 2000u) << r.name << ": the message quotes the input whole";
  }
  // The editor's server answers the next request as before.
  EXPECT_EQ(get("/api/state").status, 200);
}

INSTANTIATE_TEST_SUITE_P(Readers, DepthLimit, ::testing::ValuesIn(kReaders),
                         [](const ::testing::TestParamInfo<Reader>& i) { return i.param.name; });

// The scan counts structure only: brackets in strings (every kind), comments and quoted keys
// with dots do not nest; a header, the dotted keys under it, arrays and inline tables add up.
TEST(TomlNesting, CountsStructureNotStringsOrComments) {
  const std::string brackets = repeat("[{", 70);
  const std::string text = "# " + brackets + "\n" +  //
                           "a = \"" + brackets + " \\\" still in the string " + brackets +
                           "\"\n" +                                                             //
                           "b = '" + brackets + "\\'\n" +                                       //
                           "c = \"\"\"\n" + brackets + "\n\"\"\" # " + brackets + "\n" +        //
                           "d = '''\n" + brackets + "''''\n" +                                  //
                           "\"" + dotted(70) + "\" = 1\n" +                                     //
                           "e = [ # " + brackets + "\n  [1, 2], # ]]]\n  [3, \"]]]\"],\n]\n" +  //
                           "[table.\"" + dotted(70) + "\"]\nf = { g = [1, { h = 2 }], i.j = 3 }\n";
  int line = 0, column = 0;
  EXPECT_EQ(toml_nesting_error(text, &line, &column), "") << line << ":" << column;
  EXPECT_NO_THROW((void)toml::parse(text)) << text;
  // 20 header parts, 20 key parts, 12 arrays, 12 inline tables: 64 levels, read; 65 are not.
  const auto mixed = [](int arrays_deep) {
    return "[" + dotted(20) + "]\n" + dotted(20) + " = " + repeat("[", arrays_deep) +
           repeat("{a = ", 12) + "1" + repeat("}", 12) + repeat("]", arrays_deep) + "\n";
  };
  EXPECT_EQ(toml_nesting_error(mixed(12), &line, &column), "");
  EXPECT_NE(toml_nesting_error(mixed(13), &line, &column), "");
  EXPECT_EQ(line, 2) << column;
}

}  // namespace
}  // namespace anamorph::test
