// The `unlit` material kind: no keys of its own (its look is `emission`), its registry entry.
#include "material/unlit.h"

#include "material/material_kinds.h"

namespace anamorph {

namespace {

std::unique_ptr<Material> create(const ParamValues&) { return std::make_unique<UnlitMaterial>(); }

}  // namespace

extern const MaterialKind kUnlitKind;  // (in the list of material_kinds.cpp)
const MaterialKind kUnlitKind{
    UnlitMaterial::kType,
    "Shows its `emission` and reflects nothing (glTF KHR_materials_unlit: the base colour).",
    {},
    create};

}  // namespace anamorph
