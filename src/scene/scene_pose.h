// Posing a scene's glTF rigs at a frame: the instances, lights, cameras and deforming meshes
// their animations drive. glTF animation time is in seconds: time = frame / fps ([animation]
// fps, default 24), the mapping Blender's glTF exporter writes (its frame F at F / fps), so a
// Blender file's frame F renders as anamorph's frame F. Before a sampler's first key and after
// its last its value is held.
#pragma once

#include <utility>
#include <vector>

#include "scene/scene.h"

namespace anamorph {

// Whether some rig of the scene animates.
bool has_gltf_animation(const Scene& s);
// The frames the scene's glTF animations span, [first key, last key] x fps (0, 0 without any).
std::pair<double, double> gltf_frame_range(const Scene& s);

// Whether some rig's animation moves geometry or lights (not only cameras): then every frame
// needs the whole scene posed again, not only its view.
bool gltf_moves_world(const Scene& s);

// Which of the scene's instances the animation moves (their transforms change between frames:
// an acceleration structure keeps them as instances of their own, to move them without
// rebuilding their meshes), and which prototypes it deforms (skins, morph weights).
std::vector<bool> moving_instances(const Scene& s);
std::vector<bool> deforming_prototypes(const Scene& s);

// Whether the scene's objects blur: the camera's shutter is open (Scene::shutter_open <
// shutter_close) and the glTF animation moves geometry or lights.
bool object_motion_blur(const Scene& s);

// Poses every animating rig at `frame`: its instances' transforms, its lights' positions and
// directions, its deforming meshes' vertices. Model cameras are left alone (pose_model_cameras).
// Under object_motion_blur, also the moving instances' Instance::motion and the deforming meshes'
// TriangleMesh::motion_positions (and motion_normals): the pose at Scene::motion_steps times
// evenly spaced from frame + shutter_open to frame + shutter_close (lights keep the frame's).
void pose_scene(Scene& s, double frame);

// Moves the mesh objects of `s` to the transforms `want` gives them (PlacedObject entries by
// table index, e.g. a view's from load_view with `object.N.transform` overrides; objects it does
// not name keep theirs) as a load with those transforms places them, bit for bit: each instance at
// the transform times its place in the model, the animated rigs posed again at s.frame. Updates
// s.placed_objects. Whether an object moved (then the renderer's repose() takes it). Throws
// std::invalid_argument, s unchanged, for a table that is no mesh object of s, an object that
// brought lights or cameras, or a transform taking a part beyond the world.
bool place_objects(Scene& s, const std::vector<PlacedObject>& want);

// `cameras` (a scene's model cameras, in its order) at `frame`, as `rigs` move them.
void pose_model_cameras(const std::vector<SceneRig>& rigs, double fps, double frame,
                        std::vector<ModelCamera>& cameras);

}  // namespace anamorph
