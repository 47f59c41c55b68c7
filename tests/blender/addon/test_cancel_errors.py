"""Esc during a render stops it at the next progress report (the engine's test_break, replaced
here: a headless Blender has no key to press); a bad setting is a Blender error report naming
the key, and Blender goes on rendering."""

import os
import sys
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

scene = common.small_scene(width=160, height=120, spp=1024)
from anamorph_blender import bl  # noqa: E402

calls = []


def cancel_on_third(engine):
    calls.append(time.monotonic())
    return len(calls) >= 3


bl.break_requested = cancel_on_third
start = time.monotonic()
bpy.ops.render.render()
end = time.monotonic()
common.check(len(calls) == 3, "the render stopped at the progress report that asked "
             "(%d reports; 3 expected)" % len(calls))
common.check(bl.last_error == "", "a cancel is no error (%r)" % bl.last_error)
if len(calls) >= 3:
    print("measured: cancel to return %.3f s, render before it %.3f s"
          % (end - calls[2], calls[2] - start))
bl.break_requested = lambda engine: engine.test_break()


def expect_error(what, *words):
    try:
        bpy.ops.render.render()
        raised = ""
    except RuntimeError as e:
        raised = str(e)
    common.check(all(w in raised for w in words) and all(w in bl.last_error for w in words),
                 "%s: an error report naming %s (report %r, raised %r)"
                 % (what, words, bl.last_error, raised))


scene.anamorph.spp = 1
cam = scene.camera.data
cam.anamorph.preset = "perspective"
cam.anamorph.p_perspective.fov = 0.0
expect_error("fov 0", "camera.fov", "out of range", "frame_0001.toml")
cam.anamorph.p_perspective.fov = 50.0
cam.anamorph.preset = "fisheye"
cam.anamorph.p_fisheye.poly = "[0, 1.5"
expect_error("a broken number list", "camera.poly")
cam.anamorph.p_fisheye.property_unset("poly")
cam.anamorph.p_fisheye.mapping = "polynomial"
expect_error("polynomial without poly", "poly")
cam.anamorph.p_fisheye.mapping = "equidistant"
coin = bl.add_coin(scene.camera, (0, 0, -5))
coin.anamorph_coin.radius = 0.0
expect_error("a coin of radius 0", "camera.coin[0].radius", "out of range")
coin.anamorph_coin.radius = 0.2
bpy.ops.render.render()
common.check(bl.last_error == "", "after the errors a good render runs (%r)" % bl.last_error)
common.finish()
