"""An animation render (-a, frames 1-3) with a coin empty and the sphere moving: each frame
Blender shows equals, bit for bit, `anamorph render` of the scene file the add-on kept for that
frame; the coin's position and keyframed strength follow the empty, the exported sphere is
where Blender has it at that frame, and the frames differ. Frames where only the coin moves
reuse the last frame's meshes (no export), a keyframed material colour exports them again; a
frame where only the sphere moves exports nothing more once the sphere has a file of its own."""

import os
import subprocess
import sys
import tomllib

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
import gltf_inspect  # noqa: E402

scene = common.small_scene(width=64, height=48, spp=4)
from anamorph_blender import bl  # noqa: E402

keep = os.path.join(common.OUT, "scenes")
scene.anamorph.keep_folder = keep
coin = bl.add_coin(scene.camera, (0.0, 0.0, -7.0))
coin.anamorph_coin.strength = 0.6
coin.anamorph_coin.radius = 0.3
for frame, x in ((1, -1.5), (2, 0.0), (3, 1.5)):
    coin.location = (x, 0.2, -7.0)
    coin.keyframe_insert("location", frame=frame)
coin.anamorph_coin.keyframe_insert("strength", frame=1)
coin.anamorph_coin.strength = 0.4
coin.anamorph_coin.keyframe_insert("strength", frame=3)
sphere = bpy.data.objects["Sphere"]
for frame, y in ((1, 0.0), (3, 1.0)):
    sphere.location.y = y
    sphere.keyframe_insert("location", frame=frame)
scene.frame_start, scene.frame_end = 1, 3
common.exr_settings(scene)
scene.render.filepath = os.path.join(common.OUT, "blender_")
bpy.ops.render.render(animation=True)
common.check(bl.last_error == "", "the animation rendered without error (%r)" % bl.last_error)

positions, images = [], []
for frame in (1, 2, 3):
    toml = os.path.join(keep, "frame_%04d.toml" % frame)
    with open(toml, "rb") as f:
        coins = tomllib.load(f)["camera"]["coin"]
    positions.append(coins[0]["position"])
    common.check(len(coins) == 1, "frame %d: one coin (%d)" % (frame, len(coins)))
    cli = os.path.join(common.OUT, "cli_%04d.exr" % frame)
    run = subprocess.run([common.ANAMORPH_BIN, "render", toml, "-o", cli, "--quiet"],
                         capture_output=True, text=True)
    common.check(run.returncode == 0, "anamorph render %s: %s" % (toml, run.stderr))
    mine = common.read_rgba(os.path.join(common.OUT, "blender_%04d.exr" % frame))
    ref = common.read_rgba(cli)
    ref[..., :3] *= ref[..., 3:4]  # Blender's result is premultiplied
    diff = np.argwhere(mine != ref)
    common.check(mine.shape == ref.shape and diff.size == 0,
                 "frame %d: Blender's EXR equals `anamorph render` bit for bit (%d values "
                 "differ%s)" % (frame, len(diff), "" if not diff.size else ", first at %s: %s vs %s"
                                % (diff[0], mine[tuple(diff[0])], ref[tuple(diff[0])])))
    images.append(mine)
    scene.frame_set(frame)
    want = [sphere.location.x, sphere.location.z, -sphere.location.y]
    got, file = common.exported_translation(toml, "Sphere")
    common.check(got is not None and max(abs(a - b) for a, b in zip(got, want)) < 1e-6,
                 "frame %d: the scene file places the sphere (%s) at %s, Blender's %s"
                 % (frame, file, got, want))
    strength = coins[0]["strength"]
    expect = {1: 0.6, 2: 0.5, 3: 0.4}[frame]
    common.check(abs(strength - expect) < 1e-6,
                 "frame %d: the keyframed strength %.6f (%.1f)" % (frame, strength, expect))
# The empty moved along Blender's camera x (the camera looks along -Y, so x stays x).
xs = [p[0] for p in positions]
common.check(abs(xs[1] - xs[0] - 1.5) < 1e-5 and abs(xs[2] - xs[1] - 1.5) < 1e-5,
             "the coin's x follows the empty: %s" % xs)
common.check(not np.array_equal(images[0], images[1]) and not np.array_equal(images[1],
                                                                            images[2]),
             "the frames differ")
# Transform-only frames: frame 2 exports the floor and the moved sphere apart (two exports),
# frame 3 exports nothing: its scene file moves frame 2's sphere by a transform.
common.check(bl.render_exports == [1, 2, 2], "the moving sphere: exports at frames %s (frame "
             "1 everything, frame 2 the floor and the sphere apart, frame 3 none)"
             % bl.render_exports)
with open(os.path.join(keep, "frame_0003.toml"), "rb") as f:
    objects = tomllib.load(f)["object"]
common.check([o["file"] for o in objects] == ["frame_0002.glb", "frame_0002_1.glb"]
             and "transform" not in objects[0] and "transform" in objects[1],
             "frame 3 names frame 2's files, the sphere's with a transform: %s" % objects)

# Frames 4-7: the sphere stays at frame 3's place and the coin moves on; the sphere gets a
# material at frame 4 whose base colour is keyframed to change at frame 7. Only frames 4 (the
# new material) and 7 (its new colour) export the meshes; frames 5 and 6 name frame 4's file,
# and each frame still equals `anamorph render` of its scene file bit for bit.
for frame, x in ((4, 3.0), (7, -3.0)):
    coin.location = (x, 0.2, -7.0)
    coin.keyframe_insert("location", frame=frame)
mat = bpy.data.materials.new("keyed")
mat.use_nodes = True
base = mat.node_tree.nodes["Principled BSDF"].inputs["Base Color"]
for frame, colour in ((6, (0.8, 0.1, 0.1, 1)), (7, (0.1, 0.8, 0.1, 1))):
    base.default_value = colour
    base.keyframe_insert("default_value", frame=frame)
sphere.data.materials.append(mat)
scene.frame_start, scene.frame_end = 4, 7
before = len(bl.render_exports)
bpy.ops.render.render(animation=True)
common.check(bl.last_error == "", "frames 4-7 rendered without error (%r)" % bl.last_error)
common.check(bl.render_exports[before:] == [4, 7], "frames 4 and 7 exported the meshes, 5 and "
             "6 did not (%s)" % bl.render_exports[before:])
files = []
for frame in (4, 5, 6, 7):
    toml = os.path.join(keep, "frame_%04d.toml" % frame)
    with open(toml, "rb") as f:
        files.append(tomllib.load(f)["object"][0]["file"])
    cli = os.path.join(common.OUT, "cli_%04d.exr" % frame)
    run = subprocess.run([common.ANAMORPH_BIN, "render", toml, "-o", cli, "--quiet"],
                         capture_output=True, text=True)
    common.check(run.returncode == 0, "anamorph render %s: %s" % (toml, run.stderr))
    mine = common.read_rgba(os.path.join(common.OUT, "blender_%04d.exr" % frame))
    ref = common.read_rgba(cli)
    ref[..., :3] *= ref[..., 3:4]
    common.check(np.array_equal(mine, ref), "frame %d: Blender's EXR equals `anamorph render` "
                 "bit for bit (%d values differ)" % (frame, np.count_nonzero(mine != ref)))
    images.append(mine)
common.check(files == ["frame_0004.glb"] * 3 + ["frame_0007.glb"],
             "the scene files name the meshes %s" % files)
doc, _ = gltf_inspect.read_glb(os.path.join(keep, "frame_0007.glb"))
colour = doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"]
common.check(max(abs(a - b) for a, b in zip(colour, (0.1, 0.8, 0.1, 1))) < 1e-6,
             "frame 7's meshes have the keyed colour (%s)" % colour)
common.check(not np.array_equal(images[3], images[4]) and not np.array_equal(images[5],
                                                                            images[6]),
             "the coin still moves the picture in frames 4-5 and 6-7")
common.finish()
