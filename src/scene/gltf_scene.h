// A glTF file as a whole scene: `anamorph render scene.glb` with no scene file. The file is read
// as if a scene file held only the defaults below and the file as its one object; --set and the
// command's options change the rest (docs/gltf.md, "render scene.glb").
//   [render]       integrator "path", spp 64, max_depth 9 (Cycles' 8 bounces)
//   [environment]  color 0.05 (Blender's default world grey; glTF has no world)
//   [image]        the height follows the width (640 by default) at the camera's aspectRatio,
//                  4:3 when it has none
//   [camera]       the file's first camera (gltf_camera = 0), or, when it has none, a
//                  perspective view (fov 60 horizontal) framing
//                  the scene: looking at the centre of its bounding box from the front-right and
//                  above (+x, +y, +z), far enough for the bounding sphere to fit the image
// What the user gives (camera.look_from / look_at / gltf_camera / org / dir, image.height) wins.
#pragma once

#include <filesystem>
#include <vector>

#include <toml++/toml.h>

#include "scene/scene.h"

namespace anamorph {

// .gltf or .glb (any case): a file `render` reads as a glTF scene.
bool is_gltf_scene_file(const std::filesystem::path& file);

// The scene table of such a file: the defaults above and the file as its one [[object]].
toml::table gltf_scene_table(const std::filesystem::path& file);

// Completes the camera and the image height of a glTF scene once its world is read: `geometry`
// holds the instances and prototypes (for the framing view), `cameras` its model cameras.
void complete_gltf_view(toml::table& root, const Scene& geometry,
                        const std::vector<ModelCamera>& cameras, RenderSettings& render);

}  // namespace anamorph
