"""What an animation render (-a) spends on exporting meshes, on the demo scene (not a test).

Run: blender -b --factory-startup -noaudio --python bench/blender/animation_exports.py --
REPO OUT [ADDON_DIR]  (ADDON_DIR: the folder holding anamorph_blender, default REPO/blender:
point it at another checkout's to compare). The demo scene (demo_scene.py) at 160 x 90, Whitted
depth 6, 1 spp; FRAMES frames (default 12) of: *still* (only the camera moves), *knot* (the
torus knot moves every frame). Prints the exports, the seconds in them and the whole render's."""

import os
import sys
import time

import addon_utils
import bpy

args = sys.argv[sys.argv.index("--") + 1:]
REPO, OUT = args[:2]
ADDON_DIR = args[2] if len(args) > 2 else os.path.join(REPO, "blender")
FRAMES = int(os.environ.get("FRAMES", "12"))
sys.path.insert(0, ADDON_DIR)
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import demo_scene  # noqa: E402

scene = demo_scene.build(REPO)
addon_utils.enable("anamorph_blender", default_set=True, handle_error=None)
from anamorph_blender import bl  # noqa: E402

spent = []
export = bl._export_glb


def timed_export(*a, **kw):
    t = time.monotonic()
    try:
        return export(*a, **kw)
    finally:
        spent.append(time.monotonic() - t)


bl._export_glb = timed_export
scene.render.engine = "ANAMORPH"
scene.anamorph.integrator = "whitted"
scene.anamorph.max_depth = 6
scene.anamorph.spp = 1
scene.render.resolution_x, scene.render.resolution_y = 160, 90
scene.render.resolution_percentage = 100
scene.render.image_settings.file_format = "OPEN_EXR"
scene.frame_start, scene.frame_end = 1, FRAMES
cam, knot = scene.camera, bpy.data.objects["torus_knot"]
for f in (1, FRAMES):
    cam.location.x += 0.5
    cam.keyframe_insert("location", frame=f)
for case in ("still", "knot"):
    if case == "knot":
        for f in (1, FRAMES):
            knot.location.x += 1.0
            knot.keyframe_insert("location", frame=f)
    scene.render.filepath = os.path.join(OUT, case + "_")
    spent.clear()
    t = time.monotonic()
    bpy.ops.render.render(animation=True)
    total = time.monotonic() - t
    print("RESULT %s: %d frames, %d exports, %.3f s exporting, %.3f s in all (%s)"
          % (case, FRAMES, len(spent), sum(spent), total, ADDON_DIR), flush=True)
