// The declarations of scene_schema.h. A key is added here, once; the reader, the docs and the
// JSON Schema follow.
#include "scene/scene_schema.h"

#include <iterator>
#include <limits>
#include <vector>

#include "camera/presets.h"
#include "material/material_kinds.h"

namespace anamorph {

namespace {

constexpr double kMaxInt64 = double(std::numeric_limits<int64_t>::max());

// ---- [image] ----------------------------------------------------------------------------------

const ParamSpec kImage[] = {
    {"width", ParamType::Integer, "640", "Image width.", 1, 65536, {}, false, false, "pixels"},
    {"height", ParamType::Integer, "480", "Image height.", 1, 65536, {}, false, false, "pixels"},
};

// ---- [render] ---------------------------------------------------------------------------------

// The integrators (render/'s registry makes them by these names: tests/render/integrator_test.cpp
// holds the lists equal), then the views (View after Beauty, in its order); `integrator` takes
// either.
constexpr IntegratorDecl kIntegratorDecls[] = {{"whitted", true}, {"path", false}};
constexpr std::string_view kViews[] = {"albedo", "normal", "depth", "position", "id", "uv"};
constexpr std::string_view kIntegrators[] = {"whitted", "path",     "albedo", "normal",
                                             "depth",   "position", "id",     "uv"};
constexpr bool integrator_choices_are_integrators_then_views() {
  constexpr size_t n = std::size(kIntegratorDecls);
  if (std::size(kIntegrators) != n + std::size(kViews)) return false;
  for (size_t i = 0; i < std::size(kIntegrators); ++i)
    if (kIntegrators[i] != (i < n ? kIntegratorDecls[i].name : kViews[i - n])) return false;
  return true;
}
static_assert(integrator_choices_are_integrators_then_views());
constexpr std::string_view kSamplers[] = {"center", "stratified", "random"};
constexpr std::string_view kFilters[] = {"box", "gaussian"};
constexpr std::string_view kAntialias[] = {"uniform", "adaptive", "lattice", "pixel"};

// clang-format off
const ParamSpec kRender[] = {
    {"integrator", ParamType::String, "\"whitted\"",
     "What a pixel shows. `whitted`: the paper's ray tracer (hard shadows, mirror reflection, "
     "refraction with Fresnel, one sample of area lights per hit; a shadow ray passes a "
     "transparent surface scaled by its `transmission`, unrefracted, as in Whitted's paper and "
     "POV-Ray). `path`: unidirectional path tracing with next-event estimation, MIS and Russian "
     "roulette. The others are views: the image shows one AOV instead of radiance (see Views below).",
     -kInf, kInf, kIntegrators},
    {"spp", ParamType::Integer, "1", "Samples per pixel.", 1, 1 << 20},
    {"sampler", ParamType::String, "\"stratified\"",
     "`center`: exactly the pixel center (for exact comparisons with other renderers). "
     "`stratified`: every number of a pixel's samples (position, lens, time, each bounce's "
     "light, BSDF and roulette numbers) comes from Owen-scrambled Sobol' points, one 2D point "
     "per dimension pair, so any number of them (and any prefix, as per-pixel adaptive "
     "sampling takes) is well stratified in every pair. "
     "`random`: independent uniform.",
     -kInf, kInf, kSamplers},
    {"max_depth", ParamType::Integer, "5",
     "Whitted: recursion depth of reflection/refraction. Path: bounces.", 0, 1000},
    {"bailout", ParamType::Number, "0.00392156862745098",
     "Whitted: a reflected or refracted ray is traced only while the product of the "
     "coefficients leading to it (mirror reflectivity, transmission x Fresnel) is at least this, "
     "as POV-Ray's `adc_bailout` (default 1/255). It bounds the ray tree of glass between "
     "mirrors at any `max_depth`. 0 traces every branch to `max_depth`.",
     0, 1},
    {"seed", ParamType::Integer, "0",
     "Random seed. Each sample's random numbers depend only on (pixel, sample index, seed): "
     "images are bit-identical for any thread count or tile size.",
     0, kMaxInt64},
    {"filter", ParamType::String, "\"box\"",
     "Pixel reconstruction. Gaussian is done by filter importance sampling (sigma = radius/3): "
     "sample positions spread over the filter, each with weight 1.",
     -kInf, kInf, kFilters},
    {"filter_radius", ParamType::Number, "1.5", "Gaussian radius.", 0.5, 8, {}, false, false,
     "pixels"},
    {"tile_size", ParamType::Integer, "32",
     "Square tiles rendered in parallel. Does not change the image.", 4, 1024, {}, false, false,
     "pixels"},
    {"antialias", ParamType::String, "none",
     "`uniform` (spp samples per pixel), `adaptive` (the integrator's scheme: lattice for "
     "whitted, pixel for the others), `lattice` (the paper's corner subdivision, not for path) "
     "or `pixel` (per-pixel progressive sampling); see antialiasing.md.",
     -kInf, kInf, kAntialias, false, false, {},
     "`\"adaptive\"` for whitted unless `spp` or `sampler` is given, else `\"uniform\"`"},
    {"aa_threshold", ParamType::Number, "0.1", "Lattice: the contrast that splits a square.", 0,
     kInf},
    {"aa_depth", ParamType::Integer, "3", "Lattice: the most subdivision levels per pixel.", 0, 6},
    {"aa_distortion", ParamType::Bool, "true",
     "Lattice: pixels the camera stretches start subdivided."},
    {"min_spp", ParamType::Integer, "none", "Pixel: samples of the first pass.", 1, 1 << 20, {},
     false, false, {}, "2 with whitted, 8 otherwise"},
    {"max_spp", ParamType::Integer, "none",
     "Pixel: the most samples a pixel takes (at least `min_spp`).", 1, 1 << 20, {}, false,
     false, {}, "`spp` when given, else 1024"},
    {"noise_threshold", ParamType::Number, "0.01",
     "Pixel: the estimated relative error at which a pixel stops.", 0, kInf},
    {"time_limit", ParamType::Number, "0",
     "A time budget (0 = none): no tile starts after it, so the image holds whole tiles (uniform "
     "sampling renders in progressive passes then, every pixel sampled after the first); with "
     "--checkpoint, --resume continues to the uninterrupted render's exact image.", 0, kInf, {},
     false, false, "seconds"},
};
// clang-format on

// ---- textures (of [[material]]; the material keys are declared by each kind, material/) ------

// clang-format off
constexpr std::string_view kTextureTypes[] = {"checker", "grid", "image"};
constexpr std::string_view kSpaces[] = {"uv", "object", "world"};
constexpr std::string_view kWraps[] = {"repeat", "clamp", "mirror"};

const ParamSpec kTextureCommon[] = {
    {"type", ParamType::String, "", "The kind of texture.", -kInf, kInf, kTextureTypes},
};
const ParamSpec kPattern[] = {
    {"space", ParamType::String, "none",
     "Where the pattern lives. In object and world space the axis closest to the surface normal "
     "is ignored, so a floor at y = 0 shows a clean 2D pattern.",
     -kInf, kInf, kSpaces, false, false, {}, "`\"world\"` for checker, `\"uv\"` for grid"},
    {"scale", ParamType::Number, "1", "Pattern period (checker cell size, grid spacing).", 1e-9,
     kInf, {}, false, false, "scene units or uv"},
    {"line_width", ParamType::Number, "0.05", "Grid: line width as a fraction of the period.", 0,
     1},
    {"color_a", ParamType::Color, "0.9", "Checker: one cell colour; grid: the background.", 0,
     kMaxRadiance},
    {"color_b", ParamType::Color, "0.1", "Checker: the other cell colour; grid: the lines.", 0,
     kMaxRadiance},
    {"transform", ParamType::Transform, "none", "Places the pattern in its space."},
};
const ParamSpec kImageTexture[] = {
    {"file", ParamType::String, "",
     "PNG, JPEG, BMP, TGA, HDR or EXR (8-bit files are sRGB), relative to the file naming it."},
    {"scale_color", ParamType::Color, "1", "Multiplies the image.", 0, kMaxRadiance},
    {"wrap", ParamType::String, "\"repeat\"", "Outside [0, 1]: repeat, clamp or mirror.", -kInf,
     kInf, kWraps},
    {"nearest", ParamType::Bool, "false", "No filtering."},
    {"uv_offset", ParamType::Vec3, "[0, 0, 0]", "uv offset [u, v, 0] (KHR_texture_transform)."},
    {"uv_scale", ParamType::Vec3, "[1, 1, 1]", "uv scale [u, v, 1] (KHR_texture_transform)."},
    {"uv_rotation", ParamType::Number, "0", "uv rotation (KHR_texture_transform).", -kInf, kInf,
     {}, false, false, "degrees"},
};
const TableVariant kTextureVariants[] = {
    {"checker", "Two colours in a 3D (or uv) checkerboard.", kPattern},
    {"grid", "Lines on a background.", kPattern},
    {"image", "An image file, mip-mapped and filtered by the ray footprint.", kImageTexture},
};
// clang-format on

// ---- [[object]] -------------------------------------------------------------------------------

constexpr std::string_view kObjectTypes[] = {"mesh",     "sphere", "plane",    "box",
                                             "cylinder", "disk",   "rectangle"};

// clang-format off
const ParamSpec kObjectCommon[] = {
    {"type", ParamType::String, "", "The kind of object.", -kInf, kInf, kObjectTypes},
    {"name", ParamType::String, "none", "A name for messages and `info`.", -kInf, kInf, {}, false,
     false, {}, "type and index, e.g. `\"sphere2\"`"},
    {"transform", ParamType::Transform, "none",
     "Applied after the shape's own placement (or to the whole model)."},
    {"material", ParamType::String, "none",
     "A material name (default grey); for a mesh, replaces the file's materials."},
};
constexpr std::string_view kSpotFalloffs[] = {"gltf", "cycles"};
const ParamSpec kMesh[] = {
    {"file", ParamType::String, "",
     "glTF 2.0 (.gltf, .glb, data URIs), OBJ/MTL, PLY, STL and every other format assimp "
     "reads, relative to the file naming it."},
    {"lights", ParamType::Bool, "true",
     "glTF: the file's KHR_lights_punctual lights join the scene's lights (gltf.md: units)."},
    {"cameras", ParamType::Bool, "true",
     "glTF: the file's cameras join the cameras `camera.gltf_camera` chooses from."},
    {"animation", ParamType::Bool, "true",
     "glTF: the file's animations play (all at once, at time = frame / animation.fps); false "
     "keeps its static pose."},
    {"spot_falloff", ParamType::String, "\"gltf\"",
     "glTF spot lights: `gltf` is KHR_lights_punctual's recommended falloff; `cycles` is "
     "Blender 3.4 Cycles' spot (an extra cos of the angle to the axis, the blend band in the "
     "cosine), to match renders of files Blender exported (gltf.md).",
     -kInf, kInf, kSpotFalloffs},
};
const ParamSpec kSphere[] = {
    {"center", ParamType::Vec3, "[0, 0, 0]", "Center.", -kInf, kInf, {}, false, false,
     "scene units"},
    {"radius", ParamType::Number, "1", "Radius.", 0, kInf, {}, true, false, "scene units"},
};
const ParamSpec kPlane[] = {
    {"point", ParamType::Vec3, "[0, 0, 0]", "A point of the plane.", -kInf, kInf, {}, false, false,
     "scene units"},
    {"normal", ParamType::Vec3, "[0, 1, 0]", "Its normal (not zero)."},
};
const ParamSpec kBox[] = {
    {"center", ParamType::Vec3, "[0, 0, 0]", "Center (without min/max).", -kInf, kInf, {}, false,
     false, "scene units"},
    {"size", ParamType::Vec3, "[1, 1, 1]", "Edge lengths, each > 0 (without min/max).", -kInf,
     kInf, {}, false, false, "scene units"},
    {"min", ParamType::Vec3, "none", "Lowest corner (with max; default [-0.5, -0.5, -0.5]).",
     -kInf, kInf, {}, false, false, "scene units"},
    {"max", ParamType::Vec3, "none", "Highest corner (with min; default [0.5, 0.5, 0.5]).", -kInf,
     kInf, {}, false, false, "scene units"},
};
const ParamSpec kCylinder[] = {
    {"base", ParamType::Vec3, "[0, 0, 0]", "Center of the bottom.", -kInf, kInf, {}, false, false,
     "scene units"},
    {"top", ParamType::Vec3, "[0, 1, 0]", "Center of the top (not the base).", -kInf, kInf, {},
     false, false, "scene units"},
    {"radius", ParamType::Number, "0.5", "Radius.", 0, kInf, {}, true, false, "scene units"},
    {"capped", ParamType::Bool, "true", "Closed by disks at both ends."},
};
const ParamSpec kDisk[] = {
    {"center", ParamType::Vec3, "[0, 0, 0]", "Center.", -kInf, kInf, {}, false, false,
     "scene units"},
    {"normal", ParamType::Vec3, "[0, 1, 0]", "Its normal (not zero)."},
    {"radius", ParamType::Number, "1", "Radius.", 0, kInf, {}, true, false, "scene units"},
};
const ParamSpec kRectangle[] = {
    {"center", ParamType::Vec3, "[0, 0, 0]", "Center.", -kInf, kInf, {}, false, false,
     "scene units"},
    {"edge_u", ParamType::Vec3, "[1, 0, 0]", "One full edge (its texture u direction).", -kInf,
     kInf, {}, false, false, "scene units"},
    {"edge_v", ParamType::Vec3, "[0, 0, -1]",
     "The other full edge (texture v); need not be perpendicular to edge_u (a parallelogram). "
     "The normal is edge_u x edge_v: the side it faces.",
     -kInf, kInf, {}, false, false, "scene units"},
};
const TableVariant kObjectVariants[] = {
    {"mesh",
     "A model file; glTF node hierarchies and transforms are kept, a mesh used by several nodes "
     "is built once and instanced.",
     kMesh},
    {"sphere", "An exact sphere.", kSphere},
    {"plane", "An infinite plane (exact; bounded at 1e6 for the BVH).", kPlane},
    {"box", "An axis-aligned box (rotate it with `transform`).", kBox},
    {"cylinder", "A cylinder between two points.", kCylinder},
    {"disk", "A flat disk.", kDisk},
    {"rectangle", "A flat rectangle (or parallelogram): a finite plane patch.", kRectangle},
};
// clang-format on

// ---- [[light]] --------------------------------------------------------------------------------

constexpr std::string_view kLightTypes[] = {"point", "spot", "directional", "quad", "sphere"};

// clang-format off
const ParamSpec kLightCommon[] = {
    {"type", ParamType::String, "", "The kind of light.", -kInf, kInf, kLightTypes},
    {"name", ParamType::String, "none", "A name for messages and `info`.", -kInf, kInf, {}, false,
     false, {}, "type and index, e.g. `\"point0\"`"},
    {"strength", ParamType::Number, "1", "Multiplies the light's colour.", 0, kMaxRadiance},
};
const ParamSpec kPointLight[] = {
    {"position", ParamType::Vec3, "[0, 0, 0]", "Where it is.", -kInf, kInf, {}, false, false,
     "scene units"},
    {"intensity", ParamType::Color, "1", "Radiant intensity.", 0, kMaxRadiance, {}, false, false,
     "W/sr"},
};
const ParamSpec kSpotLight[] = {
    {"position", ParamType::Vec3, "[0, 0, 0]", "Where it is.", -kInf, kInf, {}, false, false,
     "scene units"},
    {"intensity", ParamType::Color, "1", "Radiant intensity on the axis.", 0, kMaxRadiance, {},
     false, false, "W/sr"},
    {"direction", ParamType::Vec3, "[0, -1, 0]", "The axis (not zero); ignored with look_at."},
    {"look_at", ParamType::Vec3, "none", "A point on the axis, instead of direction.", -kInf, kInf,
     {}, false, false, "scene units"},
    {"cone_angle", ParamType::Number, "30", "Full intensity within this angle of the axis.", 0,
     180, {}, false, false, "degrees"},
    {"cone_falloff", ParamType::Number, "5", "Smooth falloff over this angle beyond the cone.", 0,
     180, {}, false, false, "degrees"},
};
const ParamSpec kDirectionalLight[] = {
    {"direction", ParamType::Vec3, "[0, -1, 0]", "The way the light travels (not zero)."},
    {"irradiance", ParamType::Color, "1", "Irradiance on a surface facing the light.", 0,
     kMaxRadiance},
};
const ParamSpec kQuadLight[] = {
    {"corner", ParamType::Vec3, "[0, 0, 0]", "One corner.", -kInf, kInf, {}, false, false,
     "scene units"},
    {"edge_u", ParamType::Vec3, "[1, 0, 0]", "First edge from the corner.", -kInf, kInf, {}, false,
     false, "scene units"},
    {"edge_v", ParamType::Vec3, "[0, 0, 1]",
     "Second edge; emits on the side of edge_u x edge_v.", -kInf, kInf, {}, false, false,
     "scene units"},
    {"radiance", ParamType::Color, "1", "Emitted radiance.", 0, kMaxRadiance},
    {"two_sided", ParamType::Bool, "false", "Emits on both sides."},
};
const ParamSpec kSphereLight[] = {
    {"center", ParamType::Vec3, "[0, 0, 0]", "Center.", -kInf, kInf, {}, false, false,
     "scene units"},
    {"radius", ParamType::Number, "0.5", "Radius.", 0, kInf, {}, true, false, "scene units"},
    {"radiance", ParamType::Color, "1", "Emitted radiance.", 0, kMaxRadiance},
};
const TableVariant kLightVariants[] = {
    {"point", "A point light.", kPointLight},
    {"spot", "A spot light: full intensity in a cone, smooth falloff beyond.", kSpotLight},
    {"directional", "Light from infinitely far away in one direction.", kDirectionalLight},
    {"quad", "An emissive parallelogram (real geometry, seen by the camera).", kQuadLight},
    {"sphere", "An emissive sphere (real geometry, seen by the camera).", kSphereLight},
};
// clang-format on

// ---- [environment], [[animate]], the camera, the top level -------------------------------------

// clang-format off
const ParamSpec kEnvironment[] = {
    {"color", ParamType::Color, "0", "Constant radiance from every direction.", 0, kMaxRadiance},
    {"file", ParamType::String, "none",
     "An equirectangular image (HDR, EXR, PNG, ...); longitude 0 (image center) is -z, u grows "
     "toward +x, the top row is +y."},
    {"strength", ParamType::Number, "1", "Multiplier.", 0, kMaxRadiance},
    {"rotation", ParamType::Number, "0", "Rotation about +y.", -kInf, kInf, {}, false, false,
     "degrees"},
};

constexpr std::string_view kInterpolations[] = {"linear", "smooth", "step"};
const ParamSpec kAnimate[] = {
    {"key", ParamType::String, "",
     "The dotted scene key, as for --set (array entries by index), e.g. "
     "\"camera.coin.0.strength\"."},
    {"keys", ParamType::NumberGrid, "",
     "[[frame, value], ...] with increasing frames; values are numbers or arrays of numbers of "
     "one shape."},
    {"interpolation", ParamType::String, "\"linear\"",
     "`linear`, `smooth` (C1 Catmull-Rom) or `step` (holds each value as written).", -kInf, kInf,
     kInterpolations},
};

constexpr std::string_view kRolling[] = {"none",          "top_to_bottom", "bottom_to_top",
                                         "left_to_right", "right_to_left", "angle"};
const ParamSpec kCameraCommon[] = {
    {"transform", ParamType::Transform, "none",
     "Moves, rotates and scales the whole camera rig (after the preset's look-at)."},
    {"aperture_radius", ParamType::Number, "0",
     "Depth of field for any camera: the ray origin moves on a disk perpendicular to the ray; 0 "
     "= pinhole.",
     0, kInf, {}, false, false, "scene units"},
    {"focus_distance", ParamType::Number, "1", "Distance along each ray that stays sharp.", 0,
     kInf, {}, false, false, "scene units"},
    {"shutter", ParamType::Vec2, "[0, 0]",
     "[open, close] relative to the frame rendered. With animated camera keys the rig is built "
     "at open and close and interpolated per ray: camera motion blur. Objects a glTF animation "
     "moves blur too (animation.motion_steps). Blender's shutter S centred on the frame is "
     "[-S/2, S/2].",
     -kInf, kInf, {}, false, false, "frames"},
    {"rolling_shutter", ParamType::String, "\"none\"",
     "A ray's time is its position along the readout direction instead of a random time in the "
     "shutter.",
     -kInf, kInf, kRolling},
    {"rolling_shutter_angle", ParamType::Number, "none",
     "With rolling_shutter = \"angle\": the readout direction from +u toward +v.", -kInf, kInf, {},
     false, false, "degrees", "90 (top to bottom)"},
    {"gltf_camera", ParamType::Integer, "none",
     "Camera N of the loaded glTF files (in the order objects load them) gives the camera its "
     "pose, following its animation. Alone, the camera is that glTF camera (its perspective "
     "yfov, widened to the image's aspect, or orthographic xmag and ymag); with a preset or "
     "org/dir, that camera rides the glTF camera node (look_from, look_at and up are then not given). See "
     "gltf.md.",
     0, 1 << 20},
};

// The camera's goals (`anamorph solve`, docs/solve.md): [[camera.constraint]], [[camera.free]]
// and [camera.solve].
constexpr std::string_view kConstraintKinds[] = {"pin", "size", "magnification", "keep",
                                                  "straight"};
const ParamSpec kConstraintCommon[] = {
    {"kind", ParamType::String, "",
     "What the constraint asks: `pin`, `size`, `magnification`, `keep` or `straight`.", -kInf,
     kInf,
     kConstraintKinds},
    {"weight", ParamType::Number, "1", "Multiplies the constraint's residuals in the solve.", 0,
     1e6, {}, true},
    {"tolerance", ParamType::Number, "none",
     "The constraint is met when its residual is at most this (in its unit: pixels for pin, "
     "keep and straight, percent for size and magnification).",
     0, kInf, {}, true, false, {}, "0.5 (pixels or percent); keep: its epsilon"},
};
const ParamSpec kPinConstraint[] = {
    {"point", ParamType::Vec3, "none", "The world point pinned (or `object`).", -kInf, kInf, {},
     false, false, "scene units"},
    {"object", ParamType::String, "none",
     "An object's name: the centre of its bounding box is pinned (or `point`)."},
    {"uv", ParamType::Vec2, "",
     "Where the point should appear: (u, v) in [0, 1]^2, u left to right, v top to bottom.", 0,
     1},
};
const ParamSpec kSizeConstraint[] = {
    {"from", ParamType::Vec3, "", "One end of the world segment.", -kInf, kInf, {}, false, false,
     "scene units"},
    {"to", ParamType::Vec3, "", "The other end.", -kInf, kInf, {}, false, false, "scene units"},
    {"fraction", ParamType::Number, "",
     "The distance between the ends' image positions as a fraction of the image's width.", 0,
     1e6, {}, true},
};
const ParamSpec kMagnificationConstraint[] = {
    {"point", ParamType::Vec3, "none", "The world point (or `object`).", -kInf, kInf, {}, false,
     false, "scene units"},
    {"object", ParamType::String, "none", "An object's name: the centre of its bounding box."},
    {"magnification", ParamType::Number, "",
     "Linear magnification at the point's image position: sqrt(A_ref / A) with A the ray beam's "
     "footprint |dP/du x dP/dv| at the point and A_ref the same through the camera without its "
     "coins (the editor's magnification map).",
     0, 1e6, {}, true},
};
const ParamSpec kKeepConstraint[] = {
    {"samples", ParamType::Integer, "8",
     "An N x N grid of image positions, each held where the starting camera shows it.", 2, 64},
    {"epsilon", ParamType::Number, "1", "How far a sample may move.", 0, kInf, {}, true, false,
     "pixels"},
    {"distance", ParamType::Number, "10",
     "Each sample is the point this far along the starting camera's ray.", 0, kInf, {}, true,
     false, "scene units"},
};
constexpr std::string_view kStraightShapes[] = {"line", "circle"};
const ParamSpec kStraightConstraint[] = {
    {"from", ParamType::Vec3, "", "One end of the world segment (e.g. a stretch of the horizon).",
     -kInf, kInf, {}, false, false, "scene units"},
    {"to", ParamType::Vec3, "", "The other end.", -kInf, kInf, {}, false, false, "scene units"},
    {"samples", ParamType::Integer, "16",
     "Points of the segment, evenly spaced from `from` to `to`, whose image positions must lie "
     "on one line (or circle).",
     4, 1024},
    {"shape", ParamType::String, "\"line\"",
     "What the segment must look like: `line` (a straight image line) or `circle` (an arc of a "
     "circle about `center`: on a dome master or a centred fisheye, a circle of constant angle "
     "from the axis, e.g. a level horizon).",
     -kInf, kInf, kStraightShapes},
    {"center", ParamType::Vec2, "[0.5, 0.5]",
     "With shape = \"circle\": the circle's centre (u, v) in the image (the image circle's "
     "centre for a dome master).",
     -kInf, kInf},
};
const TableVariant kConstraintVariants[] = {
    {"pin", "A world point (or an object's centre) appears at an image position.",
     kPinConstraint},
    {"size", "A world segment appears with a given length.", kSizeConstraint},
    {"magnification", "The camera magnifies the image at a point by a given factor.",
     kMagnificationConstraint},
    {"keep", "A regularizer: the image elsewhere moves at most epsilon pixels.", kKeepConstraint},
    {"straight", "A world segment appears straight (or as a circle about a centre).",
     kStraightConstraint},
};

const ParamSpec kFree[] = {
    {"key", ParamType::String, "",
     "A number, vector or list of numbers of the camera, dotted as for --set: \"camera.fov\", "
     "\"camera.look_at\", \"camera.coin.0.strength\", \"camera.org.points\"; indices after it "
     "select part of it: \"camera.look_at.1\", \"camera.org.points.1.2\" (row 1, column 2), "
     "\"camera.org.points.1.2.0\" (its x)."},
    {"min", ParamType::Number, "none",
     "Narrows the key's declared range (every component) from below."},
    {"max", ParamType::Number, "none", "Narrows the key's declared range from above."},
};

constexpr std::string_view kLosses[] = {"none", "huber", "cauchy"};
const ParamSpec kSolve[] = {
    {"loss", ParamType::String, "\"huber\"",
     "Robust loss on each constraint's residuals (`none` is plain least squares).", -kInf, kInf,
     kLosses},
    {"loss_scale", ParamType::Number, "1",
     "Where the loss stops being quadratic, in the residual's unit (pixels or percent).", 0, kInf,
     {}, true},
    {"max_iterations", ParamType::Integer, "200", "Iterations of the solver at most.", 1, 100000},
};

const ParamSpec kAnimation[] = {
    {"fps", ParamType::Number, "24",
     "Frames per second of the animation clock: a glTF animation is at time frame / fps "
     "(seconds), as Blender's glTF exporter writes its frames (frame 1 at 1/24 s at 24 fps).",
     0, 1e6, {}, true, false, "frames/s"},
    {"motion_steps", ParamType::Integer, "3",
     "Object motion blur: while the camera's shutter is open, the glTF animation is posed at this "
     "many evenly spaced times from shutter open to close (instances and deforming meshes), and "
     "each ray sees the pose at its own time, linearly interpolated between them. More steps "
     "follow rotations and curved paths more closely. See gltf.md.",
     2, 64},
};

const ParamSpec kTopLevel[] = {
    {"include", ParamType::String, "none",
     "A file or a list of files merged in first: tables merge key by key, arrays of tables are "
     "concatenated (included entries first), other values of this file win."},
};
// clang-format on

const TableSchema kImageSchema{"image",
                               "Output size. Pixel (i, j) of a W x H image covers image "
                               "positions [i/W, (i+1)/W] x [j/H, (j+1)/H].",
                               false, kImage};
const TableSchema kRenderSchema{"render", "Integrator and sampling.", false, kRender};
const TableSchema kTextureSchema{
    "texture", "A texture: the table form of a colour (`color`, `emission`).",
    false,     kTextureCommon,
    "type",    kTextureVariants};
const TableSchema kObjectSchema{"object", "Meshes from files and analytic shapes.",
                                true,     kObjectCommon,
                                "type",   kObjectVariants};
const TableSchema kLightSchema{"light",      "Light sources.", true,
                               kLightCommon, "type",           kLightVariants};
const TableSchema kEnvironmentSchema{"environment", "Light from infinitely far away.", false,
                                     kEnvironment};
const TableSchema kAnimateSchema{"animate", "Keyframes of any numeric key.", true, kAnimate};
const TableSchema kConstraintSchema{"camera.constraint",
                                    "A goal the camera is solved for (`anamorph solve`).",
                                    true,
                                    kConstraintCommon,
                                    "kind",
                                    kConstraintVariants};
const TableSchema kFreeSchema{"camera.free", "A camera key `anamorph solve` may change.", true,
                              kFree};
const TableSchema kSolveSchema{"camera.solve", "Options of `anamorph solve`.", false, kSolve};
const TableSchema kAnimationSchema{"animation", "The animation clock (glTF animations).", false,
                                   kAnimation};

}  // namespace

const TableVariant* TableSchema::variant(std::string_view name) const {
  for (const TableVariant& v : variants)
    if (v.name == name) return &v;
  return nullptr;
}

const ParamSpec& camera_preset_spec() {
  static const std::vector<std::string_view> names = [] {
    std::vector<std::string_view> v;
    for (const PresetInfo& p : camera_presets()) v.push_back(p.name);
    return v;
  }();
  static const ParamSpec spec{"preset",
                              ParamType::String,
                              "\"perspective\"",
                              "A named camera (see cameras.md), instead of org/dir functions.",
                              -kInf,
                              kInf,
                              names};
  return spec;
}

std::span<const std::string_view> integrator_names() { return kIntegrators; }
std::span<const std::string_view> sampler_names() { return kSamplers; }
std::span<const std::string_view> filter_names() { return kFilters; }
std::span<const IntegratorDecl> declared_integrators() { return kIntegratorDecls; }
std::string_view name_of(View v) { return v == View::Beauty ? "" : kViews[size_t(v) - 1]; }

bool select_integrator(RenderSettings& rs, std::string_view name) {
  for (size_t i = 0; i < std::size(kViews); ++i)
    if (kViews[i] == name) {
      rs.view = View(i + 1);
      return true;
    }
  for (const IntegratorDecl& d : kIntegratorDecls)
    if (d.name == name) {
      rs.integrator = std::string(name);
      rs.view = View::Beauty;
      return true;
    }
  return false;
}

bool RenderSettings::deterministic() const {
  if (view != View::Beauty) return false;
  for (const IntegratorDecl& d : kIntegratorDecls)
    if (d.name == integrator) return d.deterministic;
  return false;
}

std::string_view RenderSettings::shown() const {
  return view == View::Beauty ? std::string_view(integrator) : name_of(view);
}
std::string_view name_of(SamplerKind k) { return kSamplers[size_t(k)]; }
std::string_view name_of(PixelFilter k) { return kFilters[size_t(k)]; }
std::string_view name_of(Antialias k) {
  static constexpr std::string_view kResolved[] = {"uniform", "lattice", "pixel"};
  return kResolved[size_t(k)];
}

std::string_view name_of(AnalyticShape::Kind k) {
  switch (k) {
    case AnalyticShape::Kind::Sphere:
      return "sphere";
    case AnalyticShape::Kind::Plane:
      return "plane";
    case AnalyticShape::Kind::Box:
      return "box";
    case AnalyticShape::Kind::Cylinder:
      return "cylinder";
    case AnalyticShape::Kind::Disk:
      return "disk";
    case AnalyticShape::Kind::Rectangle:
      return "rectangle";
  }
  return "?";
}

std::string_view name_of(Light::Kind k) {
  switch (k) {
    case Light::Kind::Point:
      return "point";
    case Light::Kind::Spot:
      return "spot";
    case Light::Kind::Directional:
      return "directional";
  }
  return "?";
}

const TableSchema& image_schema() { return kImageSchema; }
const TableSchema& render_schema() { return kRenderSchema; }
// [[material]]: the common keys and each kind's, from the kinds' registry (material/).
const TableSchema& material_schema() {
  static const std::vector<TableVariant> variants = [] {
    std::vector<TableVariant> v;
    for (const MaterialKind* k : material_kinds()) v.push_back({k->name, k->doc, k->params});
    return v;
  }();
  static const TableSchema schema{
      "material", "Named materials.", true, material_common_params(), "type", variants};
  return schema;
}
const TableSchema& texture_schema() { return kTextureSchema; }
const TableSchema& object_schema() { return kObjectSchema; }
const TableSchema& light_schema() { return kLightSchema; }
const TableSchema& environment_schema() { return kEnvironmentSchema; }
const TableSchema& animate_schema() { return kAnimateSchema; }
const TableSchema& animation_schema() { return kAnimationSchema; }
const TableSchema& constraint_schema() { return kConstraintSchema; }
const TableSchema& free_schema() { return kFreeSchema; }
const TableSchema& solve_schema() { return kSolveSchema; }
std::span<const ParamSpec> camera_common_params() { return kCameraCommon; }
std::span<const ParamSpec> top_level_params() { return kTopLevel; }
std::span<const TableSchema* const> scene_tables() {
  static const TableSchema* const tables[] = {
      &kImageSchema,     &kRenderSchema,     &material_schema(),  &kTextureSchema,
      &kObjectSchema,    &kLightSchema,      &kEnvironmentSchema, &kAnimateSchema,
      &kAnimationSchema, &kConstraintSchema, &kFreeSchema,        &kSolveSchema};
  return tables;
}

}  // namespace anamorph
