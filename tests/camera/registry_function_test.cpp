// The registry and what is generated from the parameter tables: every function builds from its
// defaults, tables are well-formed, the Markdown reference lists every parameter, and evaluation
// allocates nothing after warm-up.
#include <gtest/gtest.h>

#include <cstdlib>
#include <new>
#include <set>
#include <sstream>
#include <string>

#include "camera/functions.h"
#include "function_test_util.h"

// Counts heap allocations of the current thread (the whole test binary uses this operator new;
// it only counts). Not inlined, so GCC does not pair its malloc/free with new/delete call sites
// (-Wmismatched-new-delete).
namespace {
thread_local long g_allocations = 0;
}
__attribute__((noinline)) void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
__attribute__((noinline)) void operator delete(void* p) noexcept { std::free(p); }
__attribute__((noinline)) void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace anamorph {
namespace {

using test::cat;

// The smallest valid definition of each function: its required keys only.
std::string required_keys(std::string_view kind, std::string_view type) {
  const std::string net =
      "points = [[[0, 0, 0], [1, 0, 0], [2, 0, 1], [3, 0, 0]], "
      "[[0, -1, 0], [1, -1, 1], [2, -1, 0], [3, -1, 0]], "
      "[[0, -2, 0], [1, -2, 0], [2, -2, 0], [3, -2, 1]], "
      "[[0, -3, 1], [1, -3, 0], [2, -3, 0], [3, -3, 0]]]";
  if (type == "bezier" || type == "bspline") return net;
  if (type == "nurbs")
    return net + "\nweights = [[1, 2, 1, 1], [1, 1, 1, 1], [1, 1, 0.5, 1], [1, 1, 1, 1]]";
  if (type == "expression")
    return kind == "org" ? "x = \"u\"\ny = \"v\"\nz = \"u * v\""
                         : "x = \"nx\"\ny = \"ny\"\nz = \"nz + u\"";
  if (type == "from_surface") return "surface = { type = \"sphere\" }";
  if (type == "table") return "samples = [[[-1, 1, -1], [1, 1, -1]], [[-1, -1, -1], [1, -1, -1]]]";
  if (type == "scattered" || type == "scattered_sphere")
    return "points = [[0.2, 0.2, 0, 0, -1], [0.8, 0.3, 1, 0, -1], [0.4, 0.9, 0, 1, -1], "
           "[0.6, 0.6, 0.5, 0.2, -0.5]]";
  return {};
}

TEST(FunctionRegistry, TablesAreWellFormed) {
  std::set<std::string_view> org_names, dir_names;
  const auto check_table = [](std::string_view name, std::string_view doc,
                              std::span<const ParamSpec> params) {
    EXPECT_FALSE(doc.empty()) << name;
    std::set<std::string_view> keys;
    for (const ParamSpec& p : params) {
      EXPECT_TRUE(keys.insert(p.name).second) << name << ": duplicate key " << p.name;
      EXPECT_FALSE(p.doc.empty()) << name << "." << p.name << " has no doc";
      EXPECT_LE(p.min, p.max) << name << "." << p.name;
      if (!p.choices.empty()) {
        EXPECT_EQ(p.type, ParamType::String) << name << "." << p.name;
      }
    }
  };
  for (const auto& f : org_functions()) {
    EXPECT_TRUE(org_names.insert(f.name).second) << "duplicate org " << f.name;
    check_table(f.name, f.doc, f.params);
    EXPECT_EQ(find_org_function(f.name), &f);
  }
  for (const auto& f : dir_functions()) {
    EXPECT_TRUE(dir_names.insert(f.name).second) << "duplicate dir " << f.name;
    check_table(f.name, f.doc, f.params);
    EXPECT_EQ(find_dir_function(f.name), &f);
  }
  EXPECT_EQ(find_org_function("nonexistent"), nullptr);
  // The list.
  for (const char* n :
       {"point", "plane", "sphere", "cylinder", "cone", "torus", "ellipsoid", "quadric",
        "superquadric", "bezier", "bspline", "nurbs", "mesh", "expression", "scattered"})
    EXPECT_TRUE(org_names.count(n)) << "missing org " << n;
  for (const char* n :
       {"constant", "from_surface", "toward", "away_from", "normal", "tangent_u", "tangent_v",
        "deviated_normal", "expression", "scattered", "scattered_sphere"})
    EXPECT_TRUE(dir_names.count(n)) << "missing dir " << n;
}

TEST(FunctionRegistry, EveryFunctionBuildsFromItsDefaults) {
  // Defaults are TOML text: they must parse as their type, lie in their own range and be
  // consistent with each other.
  for (const auto& f : org_functions()) {
    if (f.name == "mesh") continue;  // needs a file (mesh_function_test)
    EXPECT_NO_THROW(make_org(f.name, required_keys("org", f.name))) << f.name;
  }
  for (const auto& f : dir_functions())
    EXPECT_NO_THROW(make_dir(f.name, required_keys("dir", f.name))) << f.name;
}

TEST(FunctionRegistry, MarkdownListsEveryParameter) {
  const std::string md = function_params_markdown();
  const auto check = [&](std::string_view kind, std::string_view name,
                         std::span<const ParamSpec> params) {
    const std::string header = cat("### ", kind, " `", name, "`\n");
    const size_t at = md.find(header);
    ASSERT_NE(at, std::string::npos) << "no section " << header;
    const size_t end = md.find("### ", at + header.size());
    const std::string section =
        md.substr(at, end == std::string::npos ? std::string::npos : end - at);
    size_t rows = 0;
    std::istringstream lines(section);
    for (std::string line; std::getline(lines, line);) rows += line.rfind("| `", 0) == 0;
    EXPECT_EQ(rows, params.size()) << section;
    for (const ParamSpec& p : params)
      EXPECT_NE(section.find(cat("| `", p.name, "` | ")), std::string::npos)
          << name << " lacks a row for " << p.name;
  };
  for (const auto& f : org_functions()) check("org", f.name, f.params);
  for (const auto& f : dir_functions()) check("dir", f.name, f.params);
  // Ranges and choices appear in their column.
  EXPECT_NE(md.find("| `degree_u` | integer | `3` |  | [1, 15] |"), std::string::npos);
  EXPECT_NE(md.find("| `radius` | number | `1` |  | (0, inf) |"), std::string::npos);
  EXPECT_NE(md.find("| `u_range` | [a, b] | `[-180, 180]` | degrees |"), std::string::npos);
  EXPECT_NE(md.find("`\"clamped\"`, `\"uniform\"`"), std::string::npos);
}

TEST(FunctionRegistry, EvaluationAllocatesNothingAfterWarmUp) {
  struct Combo {
    const char* org;
    std::string org_toml;
    const char* dir;
    std::string dir_toml;
  };
  const Combo combos[] = {
      {"sphere", "", "normal", ""},
      {"plane", "", "from_surface", "surface = { type = \"torus\" }"},
      {"bspline", required_keys("org", "bspline"), "deviated_normal", "angle = 20"},
      {"nurbs", required_keys("org", "nurbs"), "tangent_u", ""},
      {"bezier", required_keys("org", "bezier"), "toward", "point = [0, 0, 5]"},
      {"superquadric", "exponent_ns = 0.5", "away_from", ""},
      {"quadric", "kind = \"paraboloid\"", "constant", ""},
      {"cone", "", "tangent_v", ""},
      {"expression", required_keys("org", "expression"), "expression",
       required_keys("dir", "expression")},
  };
  const long at_start = g_allocations;
  ASSERT_NE(make_org("sphere"), nullptr);
  ASSERT_GT(g_allocations, at_start) << "the counting operator new is not in use";
  for (const Combo& c : combos) {
    const auto org = make_org(c.org, c.org_toml);
    const auto dir = make_dir(c.dir, c.dir_toml);
    SurfaceSample s;
    DirSample d;
    const double us[] = {0.1, 0.2, 0.3, 0.9, 0.1, 0.2, 0.3, 0.9};
    const double vs[] = {0.4, 0.4, 0.4, 0.4, 0.5, 0.5, 0.5, 0.5};
    SurfaceBatch orgs;
    DirBatch dirs;
    org->eval({0.5, 0.5}, &s);  // warm-up (expression: this thread compiles its parser)
    dir->eval({0.5, 0.5}, s, &d);
    const long before = g_allocations;
    double sum = 0;
    for (int i = 0; i < 200; ++i) {
      const Vec2 uv{(i % 20) / 19.0, (i / 20) / 9.0};
      org->eval(uv, &s);
      dir->eval(uv, s, &d);
      sum += d.d.x;
    }
    org->eval_batch(us, vs, 8, &orgs);
    dir->eval_batch(us, vs, 8, orgs, &dirs);
    const long used = g_allocations - before;
    EXPECT_EQ(used, 0) << c.org << " + " << c.dir << " allocated " << used << " times (sum " << sum
                       << ")";
  }
}

}  // namespace
}  // namespace anamorph
