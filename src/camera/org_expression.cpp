// Expression origin function, and the thread-safe muParser wrapper it shares with the
// expression direction function.
//
// muParser's Parser::Eval is const but mutates internal stacks, and variables are bound by
// address, so one Parser cannot serve concurrent rays; copying a Parser would even keep the
// original's variable addresses. Each thread therefore compiles its own Parser with its own
// variable storage, the first time it evaluates a given ExpressionSet, and keeps it in a small
// thread_local cache keyed by the set's unique id. After that warm-up the hot path is a lookup in
// a fixed array and one bytecode evaluation: no locks, no allocation. The cache is bounded
// (kCacheSlots per thread); a camera uses at most a few sets, so eviction is rare, and an evicted
// set is simply compiled again.
#include "camera/org_expression.h"

#include <muParser.h>

#include <atomic>
#include <cctype>
#include <cmath>

#include "camera/org_common.h"

namespace anamorph {

struct ExpressionSet::Compiled {
  double vars[kMaxVars] = {};
  mu::Parser parser;
};

namespace {

constexpr int kCacheSlots = 8;

struct CacheEntry {
  uint64_t id = 0;
  std::unique_ptr<ExpressionSet::Compiled> compiled;
};

std::atomic<uint64_t> g_next_id{1};

bool valid_name(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

void define(mu::Parser& p, const std::vector<std::string>& vars, double* storage,
            const std::map<std::string, double>& constants) {
  for (size_t i = 0; i < vars.size(); ++i) p.DefineVar(vars[i], &storage[i]);
  for (const auto& [name, value] : constants) p.DefineConst(name, value);
  if (!constants.count("pi")) p.DefineConst("pi", kPi);
}

thread_local CacheEntry t_cache[kCacheSlots];
thread_local int t_next_slot = 0;

}  // namespace

ExpressionSet::ExpressionSet(std::vector<std::string> variables,
                             std::array<std::string, 3> formulas,
                             std::array<std::string_view, 3> keys,
                             std::map<std::string, double> constants)
    : id_(g_next_id.fetch_add(1)), vars_(std::move(variables)), constants_(std::move(constants)) {
  if (vars_.size() > size_t(kMaxVars)) throw ParamError("", "internal: too many variables");
  for (const auto& [name, value] : constants_) {
    if (!valid_name(name))
      throw ParamError("constants", "constant name '" + name +
                                        "' is not a valid identifier (letters, digits, _)");
    for (const auto& v : vars_)
      if (v == name)
        throw ParamError("constants",
                         "constant '" + name + "' clashes with the variable of the same name");
  }
  // Compile each formula alone first, so an error names its key.
  double scratch[kMaxVars] = {};
  for (int k = 0; k < 3; ++k) {
    const std::string key(keys[size_t(k)]);
    if (formulas[size_t(k)].find_first_not_of(" \t\r\n") == std::string::npos)
      throw ParamError(key, key + ": the formula is empty");
    try {
      mu::Parser p;
      define(p, vars_, scratch, constants_);
      p.SetExpr(formulas[size_t(k)]);
      int n = 0;
      p.Eval(n);
      if (n != 1)
        throw ParamError(key, key + ": expected one expression, got " + std::to_string(n));
    } catch (const mu::Parser::exception_type& e) {
      std::string allowed;
      for (const auto& v : vars_) allowed += (allowed.empty() ? "" : ", ") + v;
      const std::string& f = formulas[size_t(k)];
      const std::string shown = f.size() <= 200 ? f : f.substr(0, 100) + "...";  // (not 20 KB)
      throw ParamError(key, key + ": " + e.GetMsg() + " in \"" + shown +
                                "\" (variables: " + allowed + "; constants: pi and `constants`)");
    }
  }
  joined_ = "(" + formulas[0] + "), (" + formulas[1] + "), (" + formulas[2] + ")";
  try {
    compile();  // the joined form must compile too
  } catch (const mu::Parser::exception_type& e) {
    // (Each formula alone compiled; together they can pass muParser's 20,000 characters. Its
    // errors are not std::exceptions: one let through ended the process.)
    const std::string key(keys[0]);
    throw ParamError(key, key + ", " + std::string(keys[1]) + " and " + std::string(keys[2]) +
                              " together: " + e.GetMsg());
  }
}

ExpressionSet::~ExpressionSet() = default;

std::unique_ptr<ExpressionSet::Compiled> ExpressionSet::compile() const {
  auto c = std::make_unique<Compiled>();
  define(c->parser, vars_, c->vars, constants_);
  c->parser.SetExpr(joined_);
  int n = 0;
  c->parser.Eval(n);  // parse now; later Evals run the bytecode
  return c;
}

ExpressionSet::Compiled& ExpressionSet::for_this_thread() const {
  for (auto& e : t_cache)
    if (e.id == id_) return *e.compiled;
  CacheEntry& e = t_cache[t_next_slot];
  t_next_slot = (t_next_slot + 1) % kCacheSlots;
  e.compiled = compile();
  e.id = id_;
  return *e.compiled;
}

Vec3 ExpressionSet::eval(const double* vars) const {
  Compiled& c = for_this_thread();
  for (size_t i = 0; i < vars_.size(); ++i) c.vars[i] = vars[i];
  int n = 0;
  const double* r = c.parser.Eval(n);
  return {r[0], r[1], r[2]};
}

namespace {

// p(s, t) from formulas; derivatives by central differences on a 3x3 stencil in the function's
// own parameters (step 1e-4 of each range: balances truncation against rounding for the second
// derivatives the normal's derivatives need).
class ExpressionOrg final : public OrgFunctionLoop<ExpressionOrg> {
 public:
  ExpressionOrg(std::unique_ptr<ExpressionSet> f, ParamRange ur, ParamRange vr, bool flip)
      : f_(std::move(f)), ur_(ur), vr_(vr), flip_(flip) {}

  bool eval(Vec2 uv, SurfaceSample* out) const override {
    const double s = ur_(uv.x), t = vr_(uv.y);
    const double hs = 1e-4 * std::abs(ur_.scale()), ht = 1e-4 * std::abs(vr_.scale());
    const auto at = [&](double ds, double dt) {
      const double x[2] = {s + ds, t + dt};
      return f_->eval(x);
    };
    const Vec3 p = at(0, 0), pe = at(hs, 0), pw = at(-hs, 0), pn = at(0, ht), pso = at(0, -ht);
    const Vec3 pne = at(hs, ht), pnw = at(-hs, ht), pse = at(hs, -ht), psw = at(-hs, -ht);
    if (!is_finite(p)) return false;
    LocalGeom g;
    g.p = p;
    g.ps = (pe - pw) / (2 * hs);
    g.pt = (pn - pso) / (2 * ht);
    g.pss = (pe - p * 2 + pw) / (hs * hs);
    g.ptt = (pn - p * 2 + pso) / (ht * ht);
    g.pst = (pne - pnw - pse + psw) / (4 * hs * ht);
    set_position(g, ur_.scale(), vr_.scale(), out);
    set_cross_normal(g, ur_.scale(), vr_.scale(), flip_, out);
    return true;
  }

 private:
  std::unique_ptr<ExpressionSet> f_;
  ParamRange ur_, vr_;
  bool flip_;
};

const ParamSpec kParams[] = {
    {"x", ParamType::String, "",
     "Formula for x(u, v) (muParser syntax: + - * / ^, sin, cos, "
     "tan, exp, log, sqrt, abs, min, max, ...; `pi` is defined)."},
    {"y", ParamType::String, "", "Formula for y(u, v)."},
    {"z", ParamType::String, "", "Formula for z(u, v)."},
    {"constants", ParamType::StringMap, "{}",
     "Named constants usable in the formulas, e.g. { r = 2, k = 0.5 }."},
    {"u_range", ParamType::Vec2, "[0, 1]",
     "Values of the variable u across the image, left to right (reversed if decreasing)."},
    {"v_range", ParamType::Vec2, "[0, 1]",
     "Values of the variable v across the image, top to bottom (reversed if decreasing)."},
    kFlipNormalParam,
};

std::unique_ptr<OrgFunction> create(const ParamValues& v) {
  check_params(kParams, v);
  auto f = std::make_unique<ExpressionSet>(
      std::vector<std::string>{"u", "v"},
      std::array<std::string, 3>{v.string("x"), v.string("y"), v.string("z")},
      std::array<std::string_view, 3>{"x", "y", "z"}, v.string_map("constants"));
  return std::make_unique<ExpressionOrg>(std::move(f), read_range(v, "u_range"),
                                         read_range(v, "v_range"), v.boolean("flip_normal"));
}

}  // namespace

const OrgFunctionInfo kExpressionOrgInfo{
    "expression",
    "A surface given by three formulas x(u, v), y(u, v), z(u, v) (u, v mapped through u_range "
    "and v_range) and named constants, compiled once with muParser. Derivatives by central "
    "differences; normal = dp/du x dp/dv as for any open surface. No ray where a formula is not "
    "finite.",
    kParams, create};

}  // namespace anamorph
