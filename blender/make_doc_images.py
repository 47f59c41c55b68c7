"""The pictures of docs/blender.md, rendered headless through the add-on:

  blender -b --factory-startup -noaudio --python blender/make_doc_images.py -- OUTDIR

A 180-degree fisheye (the camera panel's fisheye preset) of a small scene, without and with two
coins on empties; PNGs written by Blender from the render result (Standard view transform)."""

import math
import os
import sys
import tempfile

import addon_utils
import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "tests", "blender"))
import scenes  # noqa: E402

out = sys.argv[sys.argv.index("--") + 1]
bpy.ops.wm.read_factory_settings(use_empty=True)
addon_utils.enable("anamorph_blender", default_set=True, handle_error=None)
from anamorph_blender import bl  # noqa: E402

sc = bpy.context.scene
sc.render.engine = "ANAMORPH"
sc.render.resolution_x = sc.render.resolution_y = 320
sc.render.resolution_percentage = 100
sc.view_settings.view_transform = "Standard"
sc.anamorph.spp = 64
scenes.world_black()
bg = sc.world.node_tree.nodes["Background"]
bg.inputs["Color"].default_value, bg.inputs["Strength"].default_value = (0.3, 0.4, 0.55, 1), 1.0
floor = scenes.textured("floor", tempfile.mkdtemp(), roughness=0.4, specular=0.0)
scenes.add_plane("floor", floor, (0, 0, 0), 12, 12)
scenes.add_sphere("white", scenes.diffuse("white", (0.8, 0.8, 0.8)), (-1.2, 0.5, 0.7), 0.7)
scenes.add_box("red", scenes.diffuse("red", (0.8, 0.1, 0.08)), (1.3, 0.8, 0.5), 1.0,
               rotation=(0, 0, math.radians(30)))
scenes.add_sphere("gold", scenes.principled("gold", (1.0, 0.7, 0.3), roughness=0.3,
                                            Metallic=1.0), (0.1, -0.6, 0.4), 0.4)
lamp = scenes.add_light("POINT", "lamp", (2.0, -2.0, 3.5), 900.0)
lamp.data.shadow_soft_size = 0.3
cam = scenes.add_camera("camera", (0.0, -4.0, 1.4), (0.0, 0.4, 0.6), 60)
cam.data.anamorph.preset = "fisheye"
cam.data.anamorph.p_fisheye.fov = 180.0
sc.render.image_settings.file_format = "PNG"
sc.render.image_settings.color_mode = "RGBA"
sc.render.filepath = os.path.join(out, "fisheye_no_coins.png")
bpy.ops.render.render(write_still=True)
for name, target, strength in (("coin_sphere", (-1.2, 0.5, 0.7), 0.5),
                               ("coin_box", (1.3, 0.8, 0.5), 0.5)):
    coin = bl.add_coin(cam, (0, 0, 0), name=name)
    coin.matrix_world.translation = target
    coin.anamorph_coin.strength = strength
    coin.anamorph_coin.radius = 0.3
bpy.context.view_layer.update()
sc.render.filepath = os.path.join(out, "fisheye_two_coins.png")
bpy.ops.render.render(write_still=True)
if bl.last_error:
    sys.exit("make_doc_images: " + bl.last_error)
