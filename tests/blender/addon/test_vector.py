"""blender.addon.vector: the Vector pass (and the Flow passes) of a render through the engine.

A floor, a cube moving and turning and a camera moving (linear keys over frames 1-3), frame 2
at 64 x 48, one sample at each pixel centre: the Vector pass equals Cycles' own Vector pass of
the same scene (Cycles with a 0.01-pixel filter: its samples at the pixel centres too) where
both see the same object and its 8 neighbours do; the kept scene file rendered by `anamorph
render --aov motion` gives the same bits; the Flow passes are the Vector pass's halves
(docs/vision.md: motion = (fb.x, -fb.y, -ff.x, ff.y)) where their points are seen."""

import os
import subprocess
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import common  # noqa: E402

WIDTH, HEIGHT = 64, 48
# Pixels: both renderers intersect the same triangles at the same pixel centres, in single
# precision; Cycles moves its points by its own float matrices.
TOLERANCE = 0.01


def linear_keys(ob, path, values):
    for frame, value in values:
        setattr(ob, path, value)
        ob.keyframe_insert(path, frame=frame)
    for fc in ob.animation_data.action.fcurves:
        for k in fc.keyframe_points:
            k.interpolation = "LINEAR"


scene = common.small_scene(WIDTH, HEIGHT, spp=1)
bl = common.enable_addon()
floor, sphere = scene.objects["Plane"], scene.objects["Sphere"]
bpy.data.objects.remove(sphere)
bpy.ops.mesh.primitive_cube_add(size=1.5, location=(0, 0, 0.75))
cube = bpy.context.object
floor.pass_index, cube.pass_index = 1, 2
linear_keys(cube, "location", ((1, (-0.4, 0.0, 0.75)), (3, (0.4, 0.3, 0.75))))
linear_keys(cube, "rotation_euler", ((1, (0.0, 0.0, 0.0)), (3, (0.0, 0.0, 0.5))))
linear_keys(scene.camera, "location", ((1, (0.2, -7.0, 2.5)), (3, (-0.2, -6.6, 2.7))))
scene.frame_start, scene.frame_end = 1, 3
scene.frame_set(2)
vl = scene.view_layers[0]
vl.use_pass_vector = vl.use_pass_object_index = vl.anamorph_flow = True
scene.anamorph.sampler = "center"
scene.anamorph.keep_folder = os.path.join(common.OUT, "kept")
scene.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
scene.render.image_settings.color_depth = "32"


def render(engine, name):
    scene.render.engine = engine
    scene.render.filepath = os.path.join(common.OUT, name)
    bpy.ops.render.render(write_still=True)
    return common.exr_io.read_exr(scene.render.filepath)


mine = render("ANAMORPH", "vector_a.exr")
common.check(bl.last_error == "", "anamorph rendered without error (%r)" % bl.last_error)
common.check(scene.frame_current == 2, "the scene is back at frame 2 (%d)" % scene.frame_current)
common.cycles_settings(scene, 1)
scene.cycles.filter_width = 0.01
scene.render.use_motion_blur = False
ref = render("CYCLES", "vector_c.exr")


def channels(ch, name, letters):
    return np.stack([ch["ViewLayer.%s.%s" % (name, c)] for c in letters], axis=-1)


vec_a, vec_c = channels(mine, "Vector", "XYZW"), channels(ref, "Vector", "XYZW")
ids_a, ids_c = mine["ViewLayer.IndexOB.X"], ref["ViewLayer.IndexOB.X"]
# Pixels whose 3 x 3 neighbourhood shows one object (the floor or the cube) in both renders.
same = np.ones_like(ids_a, dtype=bool)
for dy in (-1, 0, 1):
    for dx in (-1, 0, 1):
        same &= np.roll(ids_a, (dy, dx), axis=(0, 1)) == ids_c
same[[0, -1], :] = same[:, [0, -1]] = False
# Where a point leaves the image at frame 2 -/+ 1 (by Cycles' own vector, from the pixel
# centre, y up), anamorph's half is 0 (docs/vision.md) and Cycles' the projection outside.
jj, ii = np.mgrid[0:HEIGHT, 0:WIDTH]
centre = np.stack([ii + 0.5, HEIGHT - jj - 0.5], axis=-1)
for half, sign in ((slice(0, 2), 1), (slice(2, 4), -1)):
    to = centre + sign * vec_c[..., half]

    def outside(margin):
        return (to[..., 0] < margin) | (to[..., 0] > WIDTH - margin) | \
            (to[..., 1] < margin) | (to[..., 1] > HEIGHT - margin)

    out = same & outside(-0.01)
    common.check(np.all(vec_a[out][:, half] == 0),
                 "%d pixels whose point leaves the image at frame 2 %s 1: anamorph's half 0"
                 % (out.sum(), "-" if sign > 0 else "+"))
    near = outside(1.0)  # (at the border: either)
    vec_c[near, half] = vec_a[near, half]
for index, what in ((1, "floor"), (2, "cube")):
    at = same & (ids_a == index)
    diff = np.abs(vec_a[at] - vec_c[at]).max(axis=1)
    worst = int(np.argmax(diff)) if diff.size else 0
    common.check(at.sum() > 50 and diff.max() < TOLERANCE,
                 "%s: Vector pass equals Cycles' within %g px at %d pixels: worst %.2g "
                 "(anamorph %s, Cycles %s), median %.2g; motion up to %.2f px"
                 % (what, TOLERANCE, at.sum(), diff.max() if diff.size else -1,
                    np.round(vec_a[at][worst], 4) if diff.size else None,
                    np.round(vec_c[at][worst], 4) if diff.size else None,
                    np.median(diff) if diff.size else -1, np.abs(vec_c[at]).max()))
sky = ids_c == 0
common.check(np.all(vec_a[sky] == 0), "no motion where nothing is hit (%d pixels)" % sky.sum())

# The kept scene file holds the motion: the CLI's motion layer gives the same bits.
kept = os.path.join(common.OUT, "kept", "frame_0002.toml")
cli = os.path.join(common.OUT, "vector_cli.exr")
subprocess.run([common.ANAMORPH_BIN, "render", kept, "-o", cli, "--aov", "motion", "-q"],
               check=True)
ch = common.exr_io.read_exr(cli)
vec_cli = np.stack([ch["motion." + c] for c in "XYZW"], axis=-1)
common.check(np.array_equal(vec_cli, vec_a),
             "`anamorph render --aov motion` of the kept file equals the Vector pass (max "
             "difference %g)" % np.abs(vec_cli - vec_a).max())

# Flow passes: forward (x right, y down) and backward flows are the Vector pass's halves.
fwd, bwd = channels(mine, "Flow Forward", "XYZ"), channels(mine, "Flow Backward", "XYZ")
both = (fwd[..., 2] == 1) & (bwd[..., 2] == 1)
halves = np.stack([bwd[..., 0], -bwd[..., 1], -fwd[..., 0], fwd[..., 1]], axis=-1)
gap = np.abs(halves[both] - vec_a[both]).max() if both.any() else -1
common.check(both.sum() > 100 and gap < 1e-4,
             "Flow passes: (fb.x, -fb.y, -ff.x, ff.y) equals the Vector pass at %d pixels "
             "seen in both frames (worst %.2g)" % (both.sum(), gap))
common.finish()
