"""An HDRI world (Environment Texture of an equirectangular EXR, through a Mapping node's Z
rotation, strength 1.5) against Cycles. The image is made here and lopsided on purpose: red
toward Blender's +X, green toward +Y, blue 45 degrees up, dim elsewhere, so a turn, a mirror or a
flip of the world changes which side of everything is which colour.

1. The world alone seen by Blender's equirectangular camera (Cycles' own image lookups at every
   pixel's direction), turned 40 degrees by a Mapping node of type Point, 0 degrees, and 40
   degrees by one of type Texture (the inverse turn): 4 x 4 block means within 2 %.
2. A floor and a sphere lit by that world only: image means per channel within 3 % and
   10 x 10 block means within noise (5 %).
3. The world alone again with the image packed into the .blend (its file gone) and generated
   (Blender's colour grid in float, a plain 8-bit colour): 4 x 4 block means within 2 %.
   Rotations about X and Y: the Z turn kept and a warning naming them."""

import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
import exr_io  # noqa: E402


def lopsided_hdri(path, width=64, height=32):
    """Writes the EXR: each texel's colour from its direction in Blender's world axes, by
    Blender's equirectangular convention (rows from the top, +Z at the top row)."""
    u = (np.arange(width) + 0.5) / width
    v = 1 - (np.arange(height) + 0.5) / height  # Blender's v grows upward
    phi = (0.5 - u[None, :]) * 2 * math.pi  # = atan2(y, x): the centre faces +X
    lat = (v[:, None] - 0.5) * math.pi
    x = np.cos(lat) * np.cos(phi)
    y = np.cos(lat) * np.sin(phi)
    z = np.sin(lat) * np.ones_like(phi)
    lobe = lambda d: np.maximum(d, 0.0) ** 2  # noqa: E731
    # Blue peaks 45 degrees up and fades at both poles: Cycles' lookup within half a texel of
    # a pole mixes in the other pole's row (seen), anamorph's clamps; equal rows agree.
    rgb = {"R": 0.05 + 2.0 * lobe(x), "G": 0.05 + 1.2 * lobe(y),
           "B": 0.05 + 3.2 * lobe(z) * (1 - z * z)}
    exr_io.write_exr(path, {k: a.astype(np.float32) for k, a in rgb.items()})
    return path


def hdri_world(path, z_rotation_deg, strength=1.5):
    """Texture Coordinate (Generated) -> Mapping (Z rotation) -> Environment Texture ->
    Background."""
    world = bpy.context.scene.world
    nt = world.node_tree
    env = nt.nodes.new("ShaderNodeTexEnvironment")
    env.image = bpy.data.images.load(path)
    coords = nt.nodes.new("ShaderNodeTexCoord")
    mapping = nt.nodes.new("ShaderNodeMapping")
    mapping.inputs["Rotation"].default_value = (0, 0, math.radians(z_rotation_deg))
    nt.links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
    nt.links.new(mapping.outputs["Vector"], env.inputs["Vector"])
    bg = nt.nodes["Background"]
    nt.links.new(env.outputs["Color"], bg.inputs["Color"])
    bg.inputs["Strength"].default_value = strength
    # Cycles' importance map at the image's size, not its default 1024 (seconds to build).
    world.cycles.sampling_method, world.cycles.sample_map_resolution = "MANUAL", 64
    return mapping


def written_environment():
    """The [environment] table the add-on writes for the current scene, and its warnings."""
    from anamorph_blender import bl

    data, warnings = bl.scene_data(bpy.context.evaluated_depsgraph_get(), "", 1, export=False,
                                   folder=common.OUT)
    return data["environment"], warnings


scene = common.small_scene(width=80, height=60)
bpy.data.objects["lamp"].hide_render = True
hdri_path = lopsided_hdri(os.path.join(common.OUT, "lopsided.exr"))
mapping = hdri_world(hdri_path, 40.0)
env, warnings = written_environment()
common.check(env.get("file", "").endswith("lopsided.exr") and abs(env["rotation"] - 130) < 1e-4
             and env["strength"] == 1.5 and not warnings,
             "the world becomes [environment] file, rotation 130 (40 + 90), strength 1.5, no "
             "warning: %r %r" % (env, warnings))

sun = bpy.data.objects.new("wide_sun", bpy.data.lights.new("wide_sun", "SUN"))
sun.data.angle = math.radians(10.0)
scene.collection.objects.link(sun)
_, warnings = written_environment()
common.check(any("wide_sun" in w and "angle (10 degrees)" in w for w in warnings),
             "a sun of angle 10 degrees gives a warning that its angle is not carried over: %r"
             % warnings)
bpy.data.objects.remove(sun)

# A Mapping node turning about X and Y too: anamorph's environment turns about its up axis only
# (the schema's [environment] rotation); the Z turn is kept, X and Y named in a warning.
mapping.inputs["Rotation"].default_value = (math.radians(10), math.radians(-5), math.radians(40))
env, warnings = written_environment()
common.check(abs(env.get("rotation", 0) - 130) < 1e-4 and any(
    "about X (10 degrees) and Y (-5 degrees) is not carried over" in w for w in warnings),
    "X/Y rotations: the image turned about Z only (rotation %r), a warning names them: %r"
    % (env.get("rotation"), warnings))
mapping.inputs["Rotation"].default_value = (0, 0, math.radians(40))

# 1. The world alone, through Blender's equirectangular camera.
for ob in bpy.data.objects:
    ob.hide_render = ob.type != "CAMERA"
cam = scene.camera.data
cam.type = "PANO"
cam.cycles.panorama_type = "EQUIRECTANGULAR"
scene.render.resolution_x, scene.render.resolution_y = 64, 32
scene.anamorph.spp = 16
for kind, z_deg in (("POINT", 40.0), ("POINT", 0.0), ("TEXTURE", 40.0)):
    mapping.vector_type = kind
    mapping.inputs["Rotation"].default_value[2] = math.radians(z_deg)
    name = "world_%s_z%d" % (kind.lower(), z_deg)
    mine, ref = common.both_engines(name, 16)
    common.compare_blocks(name, mine, ref, 4, 0.02)

# 2. A floor and a sphere lit by the world only.
for ob in bpy.data.objects:
    ob.hide_render = ob.name == "lamp"
cam.type = "PERSP"
scene.render.resolution_x, scene.render.resolution_y = 80, 60
scene.anamorph.spp = 64
scene.anamorph.max_depth = 9
mapping.vector_type = "POINT"
mapping.inputs["Rotation"].default_value[2] = math.radians(40.0)
mine, ref = common.both_engines("lit", 128)
common.compare_means("lit", mine, ref)
common.compare_blocks("lit", mine, ref, 10, 0.05)

# 3. Images that are no file on disk, the world alone again: the add-on writes them for anamorph
# (a packed image's bytes as packed; a generated one saved by Blender, 8-bit as PNG, float as
# EXR), Cycles reads them from Blender's memory.
for ob in bpy.data.objects:
    ob.hide_render = ob.type != "CAMERA"
cam.type = "PANO"
scene.render.resolution_x, scene.render.resolution_y = 64, 32
scene.anamorph.spp = 16
tex = next(n for n in scene.world.node_tree.nodes if n.type == "TEX_ENVIRONMENT")
tex.image.pack()
os.rename(hdri_path, hdri_path + ".gone")
env, warnings = written_environment()
with open(env.get("file", os.devnull), "rb") as f:
    same = f.read() == tex.image.packed_file.data
common.check(os.path.dirname(env.get("file", "")) == common.OUT and same and not warnings,
             "a packed image (its file gone) is written as packed: %r %r" % (env, warnings))
mine, ref = common.both_engines("world_packed", 16)
common.compare_blocks("world_packed", mine, ref, 4, 0.02)
for float_buffer in (False, True):
    grid = bpy.data.images.new("grid", 64, 32, float_buffer=float_buffer)
    # The float one a colour grid (lopsided); the 8-bit one plain: Cycles filters 8-bit sRGB
    # texels before decoding them, anamorph after (a grid's block means then part by 7 %).
    grid.generated_type = "COLOR_GRID" if float_buffer else "BLANK"
    grid.generated_color = (0.8, 0.3, 0.1, 1.0)
    tex.image = grid
    env, warnings = written_environment()
    common.check(env.get("file", "").endswith(".exr" if float_buffer else ".png")
                 and not warnings, "a generated image is written: %r %r" % (env, warnings))
    name = "world_generated_%s" % ("float" if float_buffer else "8bit")
    mine, ref = common.both_engines(name, 16)
    # Without the rows at the poles: the grid's top and bottom rows differ, and within half a
    # texel of a pole Cycles mixes in the other pole's row (measured there: 2.5 %).
    common.compare_blocks(name, mine[4:-4], ref[4:-4], 4, 0.02)
common.finish()
