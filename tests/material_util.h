// Tests that check what a loader made read a material's own keys through its kind's class.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "material/material.h"

namespace anamorph::test {

// `m` as the class of its kind; throws (failing the test with both names) for another kind.
template <class Kind>
const Kind& material_as(const Material& m) {
  if (const auto* k = dynamic_cast<const Kind*>(&m)) return *k;
  throw std::runtime_error("material '" + m.name + "' is of type " + std::string(m.type()) +
                           ", not " + std::string(Kind::kType));
}

// The materials of a list as references, for range-for loops.
inline std::vector<std::reference_wrapper<const Material>> each(const MaterialList& list) {
  std::vector<std::reference_wrapper<const Material>> out;
  for (const auto& m : list) out.push_back(*m);
  return out;
}

}  // namespace anamorph::test
