"""The camera panel's properties reach anamorph: a preset switch with its keys, Blender's own
panoramic lens types as the matching presets, org/dir functions, and coin edits on the empty.
Also the Depth and Normal passes in the render result, against ray casts computed here."""

import math
import os
import subprocess
import sys
import tomllib

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

scene = common.small_scene(width=48, height=48, spp=2)
from anamorph_blender import bl  # noqa: E402

keep = os.path.join(common.OUT, "scenes")
scene.anamorph.keep_folder = keep
cam = scene.camera.data
n = [0]


def render():
    """Renders frame 1; returns (the scene file's tables, RGBA)."""
    n[0] += 1
    path = common.render_still(os.path.join(common.OUT, "r%02d.exr" % n[0]))
    common.check(bl.last_error == "", "render %d without error (%r)" % (n[0], bl.last_error))
    with open(os.path.join(keep, "frame_0001.toml"), "rb") as f:
        return tomllib.load(f), common.read_rgba(path)


# Preset switch: a 180-degree equisolid fisheye from the panel's properties.
cam.anamorph.preset = "fisheye"
cam.anamorph.p_fisheye.mapping = "equisolid"
cam.anamorph.p_fisheye.fov = 170.0
toml, img = render()
c = toml["camera"]
common.check(c["preset"] == "fisheye" and c["mapping"] == "equisolid"
             and abs(c["fov"] - 170) < 1e-9 and "fit" not in c,
             "the fisheye's set keys, and only those, reach the scene: %s" % c)
common.check(img[0, 0, 3] == 0 and img[24, 24, 3] == 1,
             "outside the image circle no ray (alpha %g), inside one (alpha %g)"
             % (img[0, 0, 3], img[24, 24, 3]))

# Blender's own lens types: the matching presets.
cam.anamorph.preset = "BLENDER"
cam.type = "PANO"
cam.cycles.panorama_type = "FISHEYE_EQUIDISTANT"
cam.cycles.fisheye_fov = math.radians(150)
toml, _ = render()
c = toml["camera"]
common.check(c["preset"] == "fisheye" and c["mapping"] == "equidistant"
             and abs(c["fov"] - 150) < 1e-4, "Blender's equidistant fisheye: %s" % c)
cam.cycles.panorama_type = "EQUIRECTANGULAR"
toml, _ = render()
c = toml["camera"]
common.check(c["preset"] == "equirectangular"
             and np.allclose(c["longitude_range"], [-180, 180])
             and np.allclose(c["latitude_range"], [-90, 90]),
             "Blender's equirectangular: %s" % c)
cam.type = "PERSP"
cam.lens_unit = "FOV"
cam.angle = math.radians(60)
toml, plain = render()
c = toml["camera"]
common.check(c["preset"] == "perspective" and abs(c["fov"] - 60) < 1e-4,
             "Blender's perspective: %s" % c)
# The camera's pose: Blender's camera looks along its -Z; in anamorph's +Y-up world the rig's
# third column (camera +z) is minus the view direction.
m = np.array(c["transform"]["matrix"]).reshape(4, 4)
view_b = scene.camera.matrix_world.to_3x3() @ __import__("mathutils").Vector((0, 0, -1))
common.check(np.allclose(-m[:3, 2], [view_b.x, view_b.z, -view_b.y], atol=1e-6)
             and np.allclose(m[:3, 3], [scene.camera.location.x, scene.camera.location.z,
                                        -scene.camera.location.y], atol=1e-6),
             "the rig is Blender's camera in glTF axes: %s" % m[:3])

# Blender's depth of field: Cycles' aperture radius and the focus distance.
cam.dof.use_dof = True
cam.dof.aperture_fstop = 2.0
cam.dof.focus_distance = 6.5
toml, _ = render()
c = toml["camera"]
common.check(abs(c["aperture_radius"] - cam.lens * 1e-3 / 4) < 1e-9
             and abs(c["focus_distance"] - 6.5) < 1e-6,
             "Blender's depth of field: aperture_radius %s (lens %s mm, f/2), focus_distance %s"
             % (c.get("aperture_radius"), cam.lens, c.get("focus_distance")))
cam.dof.use_dof = False

# A NURBS surface as the image surface: a flat cubic patch (endpoint knots, control points
# evenly spaced: p(u, v) is linear) on the camera's plane, u to its right, v down, 6 m square,
# rays along its normal, is Blender's orthographic camera of scale 6.
cam.type, cam.ortho_scale = "ORTHO", 6.0
_, ortho = render()
bpy.ops.surface.primitive_nurbs_surface_surface_add()
surf = bpy.context.active_object
surf.matrix_world = scene.camera.matrix_world.copy()
surf.hide_render = True
sp = surf.data.splines[0]
sp.order_u = sp.order_v = 4
sp.use_endpoint_u = sp.use_endpoint_v = True
for k, p in enumerate(sp.points):
    p.co = (-3.0 + 2.0 * (k % 4), 3.0 - 2.0 * (k // 4), 0.0, 1.0)
cam.anamorph.image_surface = surf
toml, on_surface = render()
c = toml["camera"]
diff = np.abs(on_surface - ortho).mean() / ortho.mean()
common.check(c["org"]["type"] == "nurbs" and c["org"]["knot_type_u"] == "clamped"
             and c["org"]["degree_v"] == 3 and c["dir"]["type"] == "normal"
             and "preset" not in c and np.allclose(c["org"]["points"][0][3], [3, 3, 0], atol=1e-5)
             and diff < 1e-3,
             "a flat NURBS image surface is the orthographic camera: org %s, mean |difference| "
             "%.2g of the mean (mirrored: %.2g)" % (c["org"], diff, np.abs(
                 on_surface[:, ::-1] - ortho).mean() / ortho.mean()))
cam.anamorph.image_surface = None
bpy.data.objects.remove(surf)

# org/dir functions chosen in the panel: a bilinear Bezier patch (its grid typed as TOML text)
# on the camera's plane, 6 m square, rays along a constant direction (-z, camera space): the
# orthographic camera again. The tables written are exactly the set keys, and the image is
# `anamorph render` of the kept scene file bit for bit.
grid = [[[-3, 3, 0], [3, 3, 0]], [[-3, -3, 0], [3, -3, 0]]]
cam.anamorph.preset = "FUNCTIONS"
cam.anamorph.org_type = "bezier"
cam.anamorph.org_bezier.points = str(grid)
cam.anamorph.dir_type = "constant"
cam.anamorph.dir_constant.direction = (0.0, 0.0, -1.0)
toml, functions = render()
c = toml["camera"]
diff = np.abs(functions - ortho).mean() / ortho.mean()
common.check(c["org"] == {"type": "bezier", "points": grid} and "preset" not in c
             and c["dir"] == {"type": "constant", "direction": [0.0, 0.0, -1.0]}
             and diff < 1e-3, "org/dir functions from the panel: org %s, dir %s, mean "
             "|difference| from the orthographic camera %.2g of the mean"
             % (c["org"], c["dir"], diff))
cli = os.path.join(common.OUT, "functions_cli.exr")
run = subprocess.run([common.ANAMORPH_BIN, "render", os.path.join(keep, "frame_0001.toml"),
                      "-o", cli, "--quiet"], capture_output=True, text=True)
ref = common.read_rgba(cli) if run.returncode == 0 else np.zeros_like(functions)
ref[..., :3] *= ref[..., 3:4]  # Blender's result is premultiplied
common.check(np.array_equal(functions, ref), "org/dir functions: equal to `anamorph render` "
             "of the kept scene bit for bit (%d values differ; %s)"
             % (np.sum(functions != ref), run.stderr.strip()))
cam.anamorph.preset = "BLENDER"
cam.type = "PERSP"

# Coin edits through the empty's properties.
coin = bl.add_coin(scene.camera, (0.0, 0.0, -7.0))
coin.anamorph_coin.strength = 0.0
toml, zero = render()
common.check(toml["camera"]["coin"][0]["strength"] == 0.0 and np.array_equal(zero, plain),
             "a coin of strength 0 changes no bit of the image")
coin.anamorph_coin.strength = 0.7
coin.anamorph_coin.radius = 0.4
coin.anamorph_coin.falloff = "gaussian"
toml, strong = render()
k = toml["camera"]["coin"][0]
common.check(abs(k["strength"] - 0.7) < 1e-6 and abs(k["radius"] - 0.4) < 1e-6
             and k["falloff"] == "gaussian", "the coin's edited keys: %s" % k)
common.check(not np.array_equal(strong, plain), "a coin of strength 0.7 changes the image")
coin.anamorph_coin.is_coin = False
toml, _ = render()
common.check("coin" not in toml["camera"], "an empty no longer marked as coin is not one")

# Albedo and object index passes: the sphere gets a Principled base colour and Pass Index 7,
# the floor (no material: Blender's grey 0.8) Pass Index 3; the sky pixel has neither.
sphere, floor = bpy.data.objects["Sphere"], bpy.data.objects["Plane"]
base = (0.7, 0.2, 0.1)
mat = bpy.data.materials.new("red")
mat.use_nodes = True
mat.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (*base, 1)
sphere.data.materials.append(mat)
sphere.pass_index, floor.pass_index = 7, 3
vl = scene.view_layers[0]
vl.anamorph_albedo = vl.use_pass_object_index = True
# The compositor sees the passes: the Render Layers node gains their sockets.
scene.use_nodes = True
rl = scene.node_tree.nodes.new("CompositorNodeRLayers")
vl.use_pass_z = vl.use_pass_normal = True
for name in ("Depth", "Normal", "Albedo", "IndexOB"):
    common.check(rl.outputs[name].enabled,
                 "the compositor's Render Layers node has the socket %s" % name)
vl.anamorph_albedo = False
common.check(not rl.outputs["Albedo"].enabled, "the Albedo socket goes with the pass")
vl.anamorph_albedo = True
scene.use_nodes = False

# Depth and Normal passes: the distance along the ray and the world normal in Blender's axes,
# at a floor pixel and a sphere pixel, against the ray through the pixel centre intersected here
# with the plane z = 0 and the sphere (radius 1 at (0, 0, 1); its 16 rings of faces lie up to
# 0.02 m inside).
bpy.data.objects.remove(coin)
vl = scene.view_layers[0]
vl.use_pass_z = vl.use_pass_normal = True
scene.anamorph.sampler = "center"  # one sample, at the pixel centre
scene.anamorph.spp = 1
scene.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
scene.render.filepath = os.path.join(common.OUT, "passes.exr")
bpy.ops.render.render(write_still=True)
ch = common.exr_io.read_exr(scene.render.filepath)
mw = scene.camera.matrix_world
t = math.tan(cam.angle / 2)
for (i, j), hit_sphere in (((24, 44), False), ((24, 26), True)):
    x, y = (2 * (i + 0.5) / 48 - 1) * t, (1 - 2 * (j + 0.5) / 48) * t
    d = (mw.to_3x3() @ __import__("mathutils").Vector((x, y, -1))).normalized()
    o = mw.translation
    if hit_sphere:
        oc = o - __import__("mathutils").Vector((0, 0, 1))
        b = oc.dot(d)
        dist = -b - math.sqrt(b * b - (oc.dot(oc) - 1))
        normal = (oc + dist * d).normalized()
        tol = 0.02
    else:
        dist, normal, tol = -o.z / d.z, (0, 0, 1), 1e-4
    depth = ch["ViewLayer.Depth.Z"][j, i]
    nrm = [ch["ViewLayer.Normal." + c][j, i] for c in "XYZ"]
    common.check(abs(depth - dist) < tol and max(abs(a - b) for a, b in zip(nrm, normal)) < 0.02,
                 "pixel (%d, %d): Depth %.5f (ray cast %.5f), Normal %s (%s)"
                 % (i, j, depth, dist, np.round(nrm, 4), np.round(list(normal), 4)))
for (i, j), albedo, index in (((24, 44), (0.8,) * 3, 3), ((24, 26), base, 7),
                              ((24, 0), (0.0,) * 3, 0)):
    got = [ch["ViewLayer.Albedo." + c][j, i] for c in "RGB"]
    got_index = ch["ViewLayer.IndexOB.X"][j, i]
    common.check(max(abs(a - b) for a, b in zip(got, albedo)) < 1e-6 and got_index == index,
                 "pixel (%d, %d): Albedo %s (base colour %s), IndexOB %g (Pass Index %d)"
                 % (i, j, got, albedo, got_index, index))
common.finish()
