"""The engine against Cycles on one scene: a floor without a material (Blender's default
surface), a textured box, a diffuse, a gold and a glass sphere (transmission 1, IOR 1.45,
roughness 0: a solid that refracts), a soft point light (radius 0.4 m: anamorph's sphere light)
and a sun: image means per channel within 3 % (measured +0.5 to +1.1 % over two seeds) and
15 x 15 block means within 10 % (measured 4.2 and 5.5 %; the same engine at two seeds differs by
up to 4.7 %, the caustic of the glass). Then Blender's equirectangular and 180-degree
equidistant fisheye cameras (the sun alone: Cycles 3.4 does not show lights to the camera,
anamorph's sphere light is geometry): the same, and 8 x 8 block means within 6 % (measured
1.0 % and 1.7 %), which a turned or mirrored view would break."""

import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
import scenes  # noqa: E402

scene = common.small_scene(width=120, height=90)
bpy.data.objects.remove(bpy.data.objects["Sphere"])  # the plane stays, without a material
tex = scenes.textured("checker", common.OUT, roughness=0.3, specular=0.0)
scenes.add_box("box", tex, (1.4, 0.5, 0.6), 1.2, rotation=(0, 0, math.radians(25)))
scenes.add_sphere("white", scenes.diffuse("white", (0.8, 0.8, 0.8)), (-1.2, 0.0, 0.9), 0.9)
scenes.add_sphere("gold", scenes.principled("gold", (1.0, 0.7, 0.3), roughness=0.35,
                                            Metallic=1.0), (0.3, -1.5, 0.5), 0.5)
glass = scenes.principled("glass", (1.0, 1.0, 1.0), roughness=0.0, specular=0.5,
                          Transmission=1.0, IOR=1.45)
scenes.gltf_thickness(glass, 1.0)  # a solid that refracts, as Cycles renders it
scenes.add_sphere("glass", glass, (-1.6, -2.4, 0.55), 0.55)
sun = bpy.data.lights.new("sun", "SUN")
sun.energy = 1.5
sun.angle = 0.0
sun_ob = bpy.data.objects.new("sun", sun)
sun_ob.rotation_euler = (math.radians(40), 0, math.radians(-35))
scene.collection.objects.link(sun_ob)
scene.anamorph.spp = 64
scene.anamorph.max_depth = 9

mine, ref = common.both_engines("perspective", 128)
common.compare_means("perspective", mine, ref)
common.compare_blocks("perspective", mine, ref, 15, 0.1)

bpy.data.objects["lamp"].hide_render = True
cam = scene.camera.data
cam.type = "PANO"
for kind, (w, h) in (("EQUIRECTANGULAR", (64, 32)), ("FISHEYE_EQUIDISTANT", (48, 48))):
    cam.cycles.panorama_type = kind
    cam.cycles.fisheye_fov = math.pi
    scene.render.resolution_x, scene.render.resolution_y = w, h
    mine, ref = common.both_engines(kind.lower(), 64)
    common.compare_means(kind.lower(), mine, ref)
    common.compare_blocks(kind.lower(), mine, ref, 8, 0.06)
common.finish()
