// Formula-defined functions: three muParser expressions x, y, z over named variables and user
// constants. ExpressionSet is shared by the expression origin and direction functions.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "camera/functions.h"

namespace anamorph {

class ExpressionSet {
 public:
  static constexpr int kMaxVars = 16;

  // Compiles each formula once to report errors against its key (`keys`, e.g. "x"), then keeps
  // the sources for per-thread compiled copies. Throws ParamError.
  ExpressionSet(std::vector<std::string> variables, std::array<std::string, 3> formulas,
                std::array<std::string_view, 3> keys, std::map<std::string, double> constants);
  ~ExpressionSet();

  // The three formulas at `vars` (one value per variable, in order). Thread-safe; allocates only
  // the first time a thread evaluates this set (see org_expression.cpp).
  Vec3 eval(const double* vars) const;

  struct Compiled;  // one thread's parser (opaque; defined in org_expression.cpp)

 private:
  std::unique_ptr<Compiled> compile() const;
  Compiled& for_this_thread() const;

  uint64_t id_;  // unique for the process lifetime: a key that never aliases a dead instance
  std::vector<std::string> vars_;
  std::string joined_;  // "x, y, z" evaluated in one pass
  std::map<std::string, double> constants_;
};

extern const OrgFunctionInfo kExpressionOrgInfo;

}  // namespace anamorph
