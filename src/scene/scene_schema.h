// The scene format's own tables, declared once: [image], [render], [[material]] (and the
// textures in its colours), [[object]], [[light]], [environment], [[animate]], the camera's
// common keys. The scene reader walks them (read_params), and docs/scene-format.md's key tables
// and `anamorph schema` are generated from them. Camera functions, presets and coins declare
// their own tables beside their code (camera/functions.h, presets.h, coins.h).
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "params/params.h"
#include "scene/scene.h"

namespace anamorph {

// One form of a table chosen by its selector key (an object's `type`, say), with its own keys.
struct TableVariant {
  std::string_view name;
  std::string_view doc;
  std::span<const ParamSpec> params;
};

struct TableSchema {
  std::string_view key;  // "image", "object", "material.color (texture)", ...
  std::string_view doc;
  bool array = false;                 // [[key]] entries
  std::span<const ParamSpec> common;  // keys of every form (the selector among them)
  std::string_view selector = {};     // "type", or "" when the table has one form
  std::span<const TableVariant> variants = {};
  const TableVariant* variant(std::string_view name) const;
};

const TableSchema& image_schema();
const TableSchema& render_schema();
const TableSchema& material_schema();
const TableSchema& texture_schema();
const TableSchema& object_schema();
const TableSchema& light_schema();
const TableSchema& environment_schema();
const TableSchema& animate_schema();
const TableSchema& animation_schema();
// The camera's goals for `anamorph solve` (docs/solve.md): [[camera.constraint]] (by `kind`),
// [[camera.free]] and [camera.solve]. The camera reader checks them; the solver reads them.
const TableSchema& constraint_schema();
const TableSchema& free_schema();
const TableSchema& solve_schema();
// The keys every camera takes, besides its preset's or its org/dir functions' (`preset`, `org`,
// `dir`, `coin` and the common ones, `gltf_camera` among them).
std::span<const ParamSpec> camera_common_params();
// The top level: include and the tables above.
std::span<const ParamSpec> top_level_params();

// `preset`: the camera presets by name (camera/presets.h), default "perspective".
const ParamSpec& camera_preset_spec();

// `integrator`'s choices: the integrators, then the views (what select_integrator() takes).
std::span<const std::string_view> integrator_names();
// An integrator the scene reader knows (render/'s registry makes it by this name) and whether
// its samples of a pixel differ only by where they fall (RenderSettings::deterministic()).
struct IntegratorDecl {
  std::string_view name;
  bool deterministic;
};
std::span<const IntegratorDecl> declared_integrators();
// Sets rs.integrator (and the view back to Beauty), or rs.view (the integrator kept), from a
// name of integrator_names(); false for any other name.
bool select_integrator(RenderSettings& rs, std::string_view name);
std::string_view name_of(View v);  // "albedo", ...; "" for Beauty

// The names of [render]'s other closed sets (an enum's value is its name's index) and back.
std::span<const std::string_view> sampler_names();
std::span<const std::string_view> filter_names();
std::string_view name_of(SamplerKind k);
std::string_view name_of(PixelFilter k);
std::string_view name_of(Antialias k);            // "uniform", "lattice" or "pixel"
std::string_view name_of(AnalyticShape::Kind k);  // an object's `type`: "sphere", "plane", ...
std::string_view name_of(Light::Kind k);          // a light's `type`: "point", "spot", ...

// Every table above, in the order the docs list them.
std::span<const TableSchema* const> scene_tables();

// The key tables of docs/scene-format.md, one generated block per table ("top", "image",
// "render", "camera", "material", "texture", "object", "light", "environment", "animate",
// "animation"), and
// the function reference docs/functions.md (block "functions"), from the declarations.
std::span<const std::string_view> scene_doc_blocks();
std::string scene_doc_block(std::string_view name);
std::string function_reference_markdown();

// `doc` with the text between "<!-- generated:NAME -->\n" and "<!-- /generated:NAME -->"
// replaced by `content`; throws std::runtime_error when the markers are missing.
std::string with_generated_block(const std::string& doc, std::string_view name,
                                 const std::string& content);
// The generated block NAME of `doc` ("" when absent), for the tests that hold docs to the code.
std::string generated_block(const std::string& doc, std::string_view name);

// The whole scene format as a JSON Schema (draft 2020-12), for editors and validators.
std::string scene_json_schema();

}  // namespace anamorph
