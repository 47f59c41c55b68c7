"""The engine against Cycles on one scene: a floor without a material (Blender's default
surface), a textured box, a diffuse and a gold sphere, a soft point light (radius 0.4 m:
anamorph's sphere light) and a sun: image means per channel within 3 %. Then Blender's
equirectangular and 180-degree equidistant fisheye cameras (the sun alone: Cycles 3.4 does not
show lights to the camera, anamorph's sphere light is geometry): the same, and 8 x 8 block
means within 6 % (measured 0.9 % and 2.2 %), which a turned or mirrored view would break."""

import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
import scenes  # noqa: E402

scene = common.small_scene(width=120, height=90)
from anamorph_blender import bl  # noqa: E402
bpy.data.objects.remove(bpy.data.objects["Sphere"])  # the plane stays, without a material
tex = scenes.textured("checker", common.OUT, roughness=0.3, specular=0.0)
scenes.add_box("box", tex, (1.4, 0.5, 0.6), 1.2, rotation=(0, 0, math.radians(25)))
scenes.add_sphere("white", scenes.diffuse("white", (0.8, 0.8, 0.8)), (-1.2, 0.0, 0.9), 0.9)
scenes.add_sphere("gold", scenes.principled("gold", (1.0, 0.7, 0.3), roughness=0.35,
                                            Metallic=1.0), (0.3, -1.5, 0.5), 0.5)
sun = bpy.data.lights.new("sun", "SUN")
sun.energy = 1.5
sun.angle = 0.0
sun_ob = bpy.data.objects.new("sun", sun)
sun_ob.rotation_euler = (math.radians(40), 0, math.radians(-35))
scene.collection.objects.link(sun_ob)
scene.anamorph.spp = 64
scene.anamorph.max_depth = 9



def both(name, cycles_spp):
    """(anamorph's image, Cycles') of the current settings."""
    scene.render.engine = "ANAMORPH"
    mine = common.read_rgba(common.render_still(os.path.join(common.OUT, name + "_a.exr")))
    common.check(bl.last_error == "", "%s: anamorph rendered without error (%r)"
                 % (name, bl.last_error))
    scene.render.engine = "CYCLES"
    cy = scene.cycles
    cy.device, cy.samples, cy.seed = "CPU", cycles_spp, 1
    cy.use_adaptive_sampling = cy.use_denoising = False
    cy.max_bounces = cy.diffuse_bounces = cy.glossy_bounces = cy.transmission_bounces = 8
    cy.sample_clamp_direct = cy.sample_clamp_indirect = cy.light_sampling_threshold = 0.0
    cy.pixel_filter_type, cy.filter_width = "BOX", 1.0
    scene.render.film_transparent = False
    ref = common.read_rgba(common.render_still(os.path.join(common.OUT, name + "_c.exr")))
    return mine, ref


def compare_means(name, mine, ref):
    m, r = mine[..., :3].mean(axis=(0, 1)), ref[..., :3].mean(axis=(0, 1))
    rel = m / r - 1
    common.check(bool(np.all(np.abs(rel) < 0.03)),
                 "%s: image means per channel within 3 %%: anamorph %s, Cycles %s, relative %s"
                 % (name, np.round(m, 5), np.round(r, 5), np.round(rel, 4)))


compare_means("perspective", *both("perspective", 128))

bpy.data.objects["lamp"].hide_render = True
cam = scene.camera.data
cam.type = "PANO"
for kind, (w, h) in (("EQUIRECTANGULAR", (64, 32)), ("FISHEYE_EQUIDISTANT", (48, 48))):
    cam.cycles.panorama_type = kind
    cam.cycles.fisheye_fov = math.pi
    scene.render.resolution_x, scene.render.resolution_y = w, h
    mine, ref = both(kind.lower(), 64)
    compare_means(kind.lower(), mine, ref)
    blocks = [img[..., :3].reshape(h // 8, 8, w // 8, 8, 3).mean(axis=(1, 3))
              for img in (mine, ref)]
    worst = np.abs(blocks[0] - blocks[1]) / (blocks[1] + 0.02)
    at = np.unravel_index(np.argmax(worst), worst.shape)
    common.check(worst.max() < 0.06, "%s: 8 x 8 block means within 6 %% (+0.02): worst %.3f at "
                 "block %s, anamorph %s, Cycles %s" % (kind.lower(), worst.max(), at[:2],
                                                       blocks[0][at[:2]], blocks[1][at[:2]]))
common.finish()
