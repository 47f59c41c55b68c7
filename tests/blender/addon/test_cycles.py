"""The engine against Cycles on one scene: floor, textured sphere, glossy sphere, a soft point
light (radius 0.4 m: anamorph's sphere light) and a sun; image means per channel within 3 %."""

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
for ob in list(bpy.data.objects):
    if ob.type == "MESH":
        bpy.data.objects.remove(ob)
scenes.add_plane("floor", scenes.diffuse("floor", (0.7, 0.7, 0.7)), (0, 0, 0), 20, 20)
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

mine = common.read_rgba(common.render_still(os.path.join(common.OUT, "anamorph.exr")))
common.check(bl.last_error == "", "anamorph rendered without error (%r)" % bl.last_error)

scene.render.engine = "CYCLES"
cy = scene.cycles
cy.device, cy.samples, cy.seed = "CPU", 128, 1
cy.use_adaptive_sampling = cy.use_denoising = False
cy.max_bounces = cy.diffuse_bounces = cy.glossy_bounces = cy.transmission_bounces = 8
cy.sample_clamp_direct = cy.sample_clamp_indirect = cy.light_sampling_threshold = 0.0
cy.pixel_filter_type, cy.filter_width = "BOX", 1.0
scene.render.film_transparent = False
ref = common.read_rgba(common.render_still(os.path.join(common.OUT, "cycles.exr")))

m, r = mine[..., :3].mean(axis=(0, 1)), ref[..., :3].mean(axis=(0, 1))
rel = m / r - 1
print("image mean anamorph", m, "cycles", r, "relative", rel)
common.check(bool(np.all(np.abs(rel) < 0.03)),
             "image means per channel within 3 %%: anamorph %s, Cycles %s, relative %s"
             % (np.round(m, 5), np.round(r, 5), np.round(rel, 4)))
common.finish()
