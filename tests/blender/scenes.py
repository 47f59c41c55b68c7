"""Test scenes built with bpy from an empty factory scene (Blender 3.4, Debian 12).

Each public scene function builds one scene into bpy.context.scene and returns a dict:
  frames   the frames to render as references
  export   glTF exporter options that differ from make_gltf.EXPORT_OPTIONS for this scene
  notes    what the scene is for and what to expect when comparing with Cycles

The functions take `assets`, a folder for generated image files (the checker texture). They are
used by make_gltf.py and are meant to be reused by the Blender add-on's tests (issue 35).

Axes: Blender is right-handed +Z up; the glTF exporter writes (x, y, z) -> (x, z, -y).
Units: metres, watts (point and spot: radiant power; sun: irradiance in W/m^2).
"""
import math
import os
import struct
import zlib

import bmesh
import bpy
from mathutils import Vector

FPS = 24

# The Principled BSDF's diffuse lobe in Cycles 3.4 is Disney's (retro-reflection grows with
# roughness); it equals Lambert exactly where roughness * (1 + L.V) = 0.5. Roughness 0.3 is the
# closest to Lambert for lights 30-90 degrees away from the view direction: a white sphere lit by
# a sun at 60 degrees from the view renders 1.0 % darker than Lambert at roughness 0.25, 2.0 %
# brighter at 0.5 and 7.9 % brighter at 1.0. Specular 0 removes the specular lobe entirely
# (the exporter then writes KHR_materials_specular with specularColorFactor [0, 0, 0], which per
# the glTF specification is a pure Lambertian diffuse).
DIFFUSE_ROUGHNESS = 0.3


# ---------------------------------------------------------------------------------------------
# Building blocks


def reset():
    """An empty factory scene: no objects, 24 fps, frames 1..1."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.render.fps = FPS
    sc.render.fps_base = 1.0
    # The exporter writes the camera's aspectRatio and yfov from the render size: set it first.
    sc.render.resolution_x, sc.render.resolution_y = 160, 120
    sc.render.resolution_percentage = 100
    sc.frame_start = 1
    sc.frame_end = 1
    sc.frame_set(1)
    return sc


def world_black():
    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0, 0, 0, 1)
    bg.inputs["Strength"].default_value = 0.0
    bpy.context.scene.world = world


def principled(name, color, roughness=DIFFUSE_ROUGHNESS, specular=0.0, **inputs):
    """A Principled BSDF material. `inputs` maps socket names with spaces written as
    underscores (Clearcoat_Roughness=0.1) to values. IOR is 1.5 (the glTF default) unless set,
    so the exporter writes KHR_materials_ior only where a scene asks for another index."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    p = mat.node_tree.nodes["Principled BSDF"]
    p.distribution = "GGX"
    p.inputs["Base Color"].default_value = (*color, 1.0)
    p.inputs["Roughness"].default_value = roughness
    p.inputs["Specular"].default_value = specular
    p.inputs["IOR"].default_value = 1.5
    for key, value in inputs.items():
        sock = p.inputs[key.replace("_", " ")]
        sock.default_value = (*value, 1.0) if isinstance(value, tuple) else value
    return mat


def diffuse(name, color):
    return principled(name, color)


def gltf_thickness(mat, thickness):
    """Adds the exporter's "glTF Material Output" node group with its Thickness input: the
    exporter then writes KHR_materials_volume (thicknessFactor), which tells a glTF reader that
    a transmissive mesh is a solid volume that refracts, as Cycles renders it, and not a thin
    wall. The group is not connected to anything, so Cycles ignores it."""
    from io_scene_gltf2.blender.com.gltf2_blender_material_helpers import (
        create_settings_group, get_gltf_node_name)
    name = get_gltf_node_name()
    group = bpy.data.node_groups.get(name) or create_settings_group(name)
    node = mat.node_tree.nodes.new("ShaderNodeGroup")
    node.node_tree = group
    node.inputs["Thickness"].default_value = thickness
    return node


def volume_absorption(mat, color, density):
    """A Volume Absorption node on the material's Volume output (exported as
    KHR_materials_volume attenuationColor = color, attenuationDistance = 1 / density)."""
    nt = mat.node_tree
    va = nt.nodes.new("ShaderNodeVolumeAbsorption")
    va.inputs["Color"].default_value = (*color, 1.0)
    va.inputs["Density"].default_value = density
    nt.links.new(va.outputs["Volume"], nt.nodes["Material Output"].inputs["Volume"])


def add_velvet(mat, color, sigma):
    """Principled + Velvet BSDF through an Add Shader: the 3.4 exporter reads a Velvet BSDF
    linked to the output as KHR_materials_sheen (Color -> sheenColorFactor, Sigma ->
    sheenRoughnessFactor); the Principled BSDF's own Sheen input is not exported."""
    nt = mat.node_tree
    out = nt.nodes["Material Output"]
    p = nt.nodes["Principled BSDF"]
    vel = nt.nodes.new("ShaderNodeBsdfVelvet")
    vel.inputs["Color"].default_value = (*color, 1.0)
    vel.inputs["Sigma"].default_value = sigma
    add = nt.nodes.new("ShaderNodeAddShader")
    nt.links.new(p.outputs["BSDF"], add.inputs[0])
    nt.links.new(vel.outputs["BSDF"], add.inputs[1])
    nt.links.new(add.outputs["Shader"], out.inputs["Surface"])


def _link(name, mesh, mat, location=(0, 0, 0), rotation=(0, 0, 0)):
    if mat is not None:
        mesh.materials.append(mat)
    ob = bpy.data.objects.new(name, mesh)
    ob.location = location
    ob.rotation_euler = rotation
    bpy.context.scene.collection.objects.link(ob)
    return ob


def _finish_mesh(name, bm, smooth):
    """Triangulates (so Cycles and a glTF reader see the same triangles) and makes the mesh."""
    bmesh.ops.triangulate(bm, faces=bm.faces[:])
    for f in bm.faces:
        f.smooth = smooth
    mesh = bpy.data.meshes.new(name)
    bm.to_mesh(mesh)
    bm.free()
    return mesh


def add_sphere(name, mat, location, radius, segments=32, rings=16):
    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=segments, v_segments=rings, radius=radius,
                              calc_uvs=True)
    return _link(name, _finish_mesh(name, bm, True), mat, location)


def add_plane(name, mat, location, size_x, size_y, rotation=(0, 0, 0)):
    """A rectangle in its local XY plane (normal +Z), UVs 0..1 over it."""
    bm = bmesh.new()
    uv = bm.loops.layers.uv.new("UVMap")
    hx, hy = size_x / 2, size_y / 2
    verts = [bm.verts.new((x, y, 0)) for x, y in ((-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy))]
    face = bm.faces.new(verts)
    for loop, (u, v) in zip(face.loops, ((0, 0), (1, 0), (1, 1), (0, 1))):
        loop[uv].uv = (u, v)
    return _link(name, _finish_mesh(name, bm, False), mat, location, rotation)


def add_box(name, mat, location, size, rotation=(0, 0, 0)):
    """A cube whose every face shows the whole texture upright (image up = +Z on the sides,
    +Y on the top face, as seen from outside)."""
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=size)
    uv = bm.loops.layers.uv.new("UVMap")
    for face in bm.faces:
        n = face.normal
        up = Vector((0, 0, 1)) if abs(n.z) < 0.5 else Vector((0, 1, 0))
        right = up.cross(n)
        for loop in face.loops:
            p = loop.vert.co
            loop[uv].uv = (p.dot(right) / size + 0.5, p.dot(up) / size + 0.5)
    return _link(name, _finish_mesh(name, bm, False), mat, location, rotation)


def add_cylinder(name, mat, radius, height, segments=24, rings=16):
    """An open-ended cylinder along +Z from z = 0 to `height`, with `rings` edge loops."""
    bm = bmesh.new()
    uv = bm.loops.layers.uv.new("UVMap")
    grid = []
    for r in range(rings + 1):
        z = height * r / rings
        grid.append([bm.verts.new((radius * math.cos(2 * math.pi * s / segments),
                                   radius * math.sin(2 * math.pi * s / segments), z))
                     for s in range(segments)])
    for r in range(rings):
        for s in range(segments):
            s1 = (s + 1) % segments
            f = bm.faces.new((grid[r][s], grid[r][s1], grid[r + 1][s1], grid[r + 1][s]))
            for loop, (du, dv) in zip(f.loops, ((0, 0), (1, 0), (1, 1), (0, 1))):
                loop[uv].uv = ((s + du) / segments, (r + dv) / rings)
    return _link(name, _finish_mesh(name, bm, True), mat)


def look_at(ob, target, roll_up=(0, 0, 1)):
    """Turns a camera or light so its -Z axis points at `target` with +Y towards `roll_up`."""
    d = Vector(target) - ob.location
    ob.rotation_mode = "XYZ"
    ob.rotation_euler = d.to_track_quat("-Z", "Y").to_euler()


def add_camera(name, eye, target, fov_deg):
    """A perspective camera; `fov_deg` is the horizontal field of view of a landscape image."""
    cam = bpy.data.cameras.new(name)
    cam.type = "PERSP"
    cam.sensor_fit = "AUTO"
    cam.angle = math.radians(fov_deg)
    cam.clip_start = 0.05
    cam.clip_end = 100.0
    ob = bpy.data.objects.new(name, cam)
    ob.location = eye
    bpy.context.scene.collection.objects.link(ob)
    look_at(ob, target)
    bpy.context.scene.camera = ob
    return ob


def add_light(kind, name, location, energy, color=(1, 1, 1), target=None, spot_size_deg=45.0,
              spot_blend=0.15):
    """A punctual light: radius (shadow_soft_size) 0 and sun angle 0, as glTF's lights are."""
    light = bpy.data.lights.new(name, kind)
    light.energy = energy
    light.color = color
    light.shadow_soft_size = 0.0
    if kind == "SUN":
        light.angle = 0.0
    if kind == "SPOT":
        light.spot_size = math.radians(spot_size_deg)
        light.spot_blend = spot_blend
        light.show_cone = False
    ob = bpy.data.objects.new(name, light)
    ob.location = location
    bpy.context.scene.collection.objects.link(ob)
    if target is not None:
        look_at(ob, target)
    return ob


# ---------------------------------------------------------------------------------------------
# The checker texture: 128 x 128, 4 x 4 cells numbered 0..15 in reading order from the top-left
# of the image, red growing to the right, green growing downwards, blue alternating (checker).

_DIGITS = ["111101101101111", "010110010010111", "111001111100111", "111001111001111",
           "101101111001001", "111100111001111", "111100111101111", "111001010010010",
           "111101111101111", "111101111001111"]  # 3 x 5 bitmaps, rows from the top


def checker_pixels(size=128, cells=4):
    """Rows from the top of the image, each a list of (r, g, b) bytes (sRGB-encoded)."""
    cell = size // cells
    scale = cell // 10
    rows = []
    for y in range(size):
        row = []
        for x in range(size):
            cx, cy = x // cell, y // cell
            r = int(255 * (0.15 + 0.8 * (cx + 0.5) / cells))
            g = int(255 * (0.15 + 0.8 * (cy + 0.5) / cells))
            b = 220 if (cx + cy) % 2 == 0 else 40
            text = str(cy * cells + cx)
            lx, ly = x % cell, y % cell
            width = len(text) * 4 * scale - scale
            ox, oy = (cell - width) // 2, (cell - 5 * scale) // 2
            gx, gy = (lx - ox) // scale, (ly - oy) // scale
            if 0 <= lx - ox < width and 0 <= gy < 5 and gx % 4 < 3:
                if _DIGITS[int(text[gx // 4])][gy * 3 + gx % 4] == "1":
                    r, g, b = 255, 255, 255
            row.append((r, g, b))
        rows.append(row)
    return rows


def write_png(path, rows):
    """An 8-bit RGB PNG with the standard library (no image module needed)."""
    raw = b"".join(b"\0" + bytes(c for px in row for c in px) for row in rows)

    def chunk(tag, data):
        return (struct.pack(">I", len(data)) + tag + data +
                struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF))

    png = (b"\x89PNG\r\n\x1a\n" +
           chunk(b"IHDR", struct.pack(">IIBBBBB", len(rows[0]), len(rows), 8, 2, 0, 0, 0)) +
           chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(png)
    os.replace(tmp, path)


def checker_image(assets):
    """The checker as a packed Blender image (written to assets/checker.png once)."""
    path = os.path.join(assets, "checker.png")
    if not os.path.exists(path):
        os.makedirs(assets, exist_ok=True)
        write_png(path, checker_pixels())
    img = bpy.data.images.load(path, check_existing=True)
    img.colorspace_settings.name = "sRGB"
    img.pack()
    return img


def textured(name, assets, roughness=0.5, specular=0.5):
    """A Principled material whose base colour is the checker (UV map, linear filter)."""
    mat = principled(name, (1, 1, 1), roughness=roughness, specular=specular)
    nt = mat.node_tree
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.image = checker_image(assets)
    tex.interpolation = "Linear"
    tex.extension = "REPEAT"
    nt.links.new(tex.outputs["Color"], nt.nodes["Principled BSDF"].inputs["Base Color"])
    return mat


# ---------------------------------------------------------------------------------------------
# Keyframes

def _fcurves(owner, path):
    """The F-curves of `path` on an ID (object) or a struct inside one (pose bone)."""
    full = path if isinstance(owner, bpy.types.ID) else owner.path_from_id(path)
    return [fc for fc in owner.id_data.animation_data.action.fcurves if fc.data_path == full]


def _key(ob, path, frame, value, interpolation):
    setattr(ob, path, value)
    ob.keyframe_insert(path, frame=frame)
    for fc in _fcurves(ob, path):
        for kp in fc.keyframe_points:
            if kp.co[0] == frame:
                kp.interpolation = interpolation


def key_linear(ob, path, frames_values):
    for frame, value in frames_values:
        _key(ob, path, frame, value, "LINEAR")


def key_bezier_thirds(ob, path, frames_values):
    """Bezier keys whose handles sit at 1/3 of each neighbouring interval (in time) with the
    slope of a Catmull-Rom spline. Blender's Bezier F-curve is then exactly the cubic Hermite
    that glTF's CUBICSPLINE encodes, so the exported curve equals Blender's between keys too.
    Blender's automatic handles also sit at 1/3 in time (only their slopes differ); a handle
    dragged elsewhere in time is not representable: with the left handles at 1/2, the export
    misses Blender's curve by 8.5 cm here, and make_gltf.py's check fails."""
    for frame, value in frames_values:
        _key(ob, path, frame, value, "BEZIER")
    for fc in _fcurves(ob, path):
        kps = fc.keyframe_points
        n = len(kps)
        for i, kp in enumerate(kps):
            t, v = kp.co
            if 0 < i < n - 1:
                slope = (kps[i + 1].co[1] - kps[i - 1].co[1]) / (kps[i + 1].co[0] -
                                                                  kps[i - 1].co[0])
            else:
                slope = 0.0  # the exporter writes zero tangents at the first and last key
            kp.handle_left_type = kp.handle_right_type = "FREE"
            dl = (t - kps[i - 1].co[0]) / 3 if i > 0 else 1.0
            dr = (kps[i + 1].co[0] - t) / 3 if i < n - 1 else 1.0
            kp.handle_left = (t - dl, v - slope * dl)
            kp.handle_right = (t + dr, v + slope * dr)


# ---------------------------------------------------------------------------------------------
# The stage shared by the light-only scenes


def _stage(floor_mat=None):
    """Floor (30 x 30 m at z = 0), back wall (30 x 10 m) at y = 3 facing -Y, camera 6.5 m in
    front: large enough to fill most of a 180-degree fisheye."""
    world_black()
    floor_mat = floor_mat or diffuse("floor", (0.7, 0.7, 0.7))
    add_plane("floor", floor_mat, (0, 0, 0), 30, 30)
    add_plane("wall", diffuse("wall", (0.5, 0.6, 0.7)), (0, 3, 5), 30, 10,
              rotation=(math.radians(90), 0, 0))
    add_camera("camera", (0.4, -6.5, 2.4), (0, 0.4, 0.8), 50)


def _diffuse_objects():
    add_sphere("white_sphere", diffuse("white", (0.8, 0.8, 0.8)), (-1.3, 0.2, 0.6), 0.6)
    add_box("red_box", diffuse("red", (0.8, 0.1, 0.08)), (0.9, 0.9, 0.5), 1.0,
            rotation=(0, 0, math.radians(30)))
    add_sphere("blue_sphere", diffuse("blue", (0.1, 0.2, 0.8)), (0.2, -0.9, 0.35), 0.35)


_LIGHT_NOTE = ("Diffuse objects only (Principled, specular 0, roughness %.2f: see "
               "DIFFUSE_ROUGHNESS). One punctual light, world black." % DIFFUSE_ROUGHNESS)


def point_only(assets):
    reset()
    _stage()
    _diffuse_objects()
    add_light("POINT", "point", (1.6, -1.6, 3.2), 600.0, color=(1.0, 0.95, 0.85))
    return {"frames": [1], "notes": _LIGHT_NOTE}


def alpha_shadow(assets):
    """point_only's stage and light with a grey alpha-blended square (alpha 0.4, specular 0) held
    2 m over the floor between the light and the blue sphere: Cycles' transparent shadows (the
    Principled Alpha) are the reference for the shadow rays crossing a glTF alphaMode BLEND."""
    reset()
    _stage()
    _diffuse_objects()
    veil = principled("veil", (0.3, 0.3, 0.3), Alpha=0.4)
    veil.blend_method = "BLEND"
    add_plane("veil", veil, (0.8, -1.0, 2.0), 2.0, 2.0)
    add_light("POINT", "point", (1.6, -1.6, 3.2), 600.0, color=(1.0, 0.95, 0.85))
    return {"frames": [1], "notes": _LIGHT_NOTE + " An alpha 0.4 blended square (exported as "
            "alphaMode BLEND) between the light and the floor: its shadow keeps 0.6 of the light."}


def spot_only(assets):
    reset()
    _stage()
    _diffuse_objects()
    add_light("SPOT", "spot", (-2.2, -2.6, 3.6), 1500.0, color=(0.9, 0.95, 1.0),
              target=(-0.3, 0.4, 0.4), spot_size_deg=50.0, spot_blend=0.3)
    return {"frames": [1], "notes": _LIGHT_NOTE + " Cycles 3.4's spot light has an extra "
            "cos(angle to the axis) factor inside its cone (measured; see README)."}


def sun_only(assets):
    reset()
    _stage()
    _diffuse_objects()
    sun = add_light("SUN", "sun", (0, 0, 5), 2.5, color=(1.0, 0.97, 0.9))
    sun.rotation_euler = (math.radians(40), 0, math.radians(-35))
    return {"frames": [1], "notes": _LIGHT_NOTE}


def _glass(name, thickness):
    mat = principled(name, (1, 1, 1), roughness=0.0, specular=0.5, Transmission=1.0)
    gltf_thickness(mat, thickness)
    return mat


def _studio_lights(scale=1.0):
    add_light("POINT", "point", (1.8, -1.5, 3.0), 350.0 * scale, color=(1.0, 0.9, 0.8))
    add_light("SPOT", "spot", (-2.5, -2.0, 3.5), 900.0 * scale, color=(0.8, 0.9, 1.0),
              target=(0.0, 0.6, 0.5), spot_size_deg=60.0, spot_blend=0.25)
    sun = add_light("SUN", "sun", (0, 0, 6), 1.2 * scale)
    sun.rotation_euler = (math.radians(35), 0, math.radians(30))


def _studio_objects(assets):
    add_sphere("glass_sphere", _glass("glass", 1.2), (-1.4, 0.0, 0.6), 0.6)
    add_sphere("metal_sphere", principled("gold", (0.95, 0.7, 0.35), roughness=0.25,
                                          specular=0.5, Metallic=1.0), (0.1, 0.9, 0.55), 0.55)
    add_box("textured_cube", textured("checker", assets), (1.5, -0.3, 0.5), 1.0,
            rotation=(0, 0, math.radians(-20)))


def studio(assets):
    reset()
    _stage()
    _studio_objects(assets)
    _studio_lights()
    return {"frames": [1], "notes": "Glass (transmission 1, IOR 1.5, thick via "
            "KHR_materials_volume thicknessFactor), gold metal (metallic 1, roughness 0.25), "
            "a textured cube; point + spot + sun."}


def transmission(assets):
    reset()
    world_black()
    add_plane("floor", textured("checker_floor", assets, roughness=0.6, specular=0.0),
              (0, 0, 0), 6, 6)
    add_camera("camera", (0, -4.6, 3.0), (0, 0, 0.3), 45)
    add_sphere("glass_sphere", _glass("glass", 1.0), (-0.7, 0.0, 0.5), 0.5, 48, 24)
    slab = principled("tinted_glass", (1, 1, 1), roughness=0.0, specular=0.5, Transmission=1.0,
                      IOR=1.33)
    gltf_thickness(slab, 0.3)
    volume_absorption(slab, (0.95, 0.8, 0.6), 1.5)
    add_box("tinted_slab", slab, (0.9, 0.3, 0.4), 1.0)
    bpy.data.objects["tinted_slab"].scale = (1.0, 0.3, 0.8)
    sun = add_light("SUN", "sun", (0, 0, 6), 3.0)
    sun.rotation_euler = (math.radians(30), 0, math.radians(20))
    return {"frames": [1], "notes": "Clear glass sphere (IOR 1.5) and a tinted slab (IOR 1.33, "
            "Volume Absorption colour (0.95, 0.8, 0.6), density 1.5) over the checker, sun-lit. "
            "The slab's absorption differs between Cycles and the glTF definition (README)."}


def clearcoat(assets):
    reset()
    _stage()
    for i, (name, color, ccr) in enumerate((("coat_red", (0.7, 0.05, 0.05), 0.03),
                                            ("coat_blue", (0.05, 0.1, 0.6), 0.2),
                                            ("coat_none", (0.05, 0.5, 0.1), None))):
        kw = {"Clearcoat": 1.0, "Clearcoat_Roughness": ccr} if ccr is not None else {}
        mat = principled(name, color, roughness=0.5, specular=0.5, **kw)
        add_sphere(name + "_sphere", mat, (-1.5 + 1.5 * i, 0.2, 0.6), 0.6, 48, 24)
    add_light("POINT", "point", (1.2, -2.0, 3.0), 400.0)
    sun = add_light("SUN", "sun", (0, 0, 6), 1.0)
    sun.rotation_euler = (math.radians(45), 0, math.radians(-30))
    return {"frames": [1], "notes": "Clearcoat 1 (roughness 0.03 and 0.2) over a red and a "
            "blue base (roughness 0.5, specular 0.5); the green sphere has no coat. Cycles 3.4 "
            "weights its clearcoat lobe about 1/4 of a glTF clearcoat (README)."}


def sheen(assets):
    reset()
    _stage()
    for i, (name, color, sheen_color, sigma) in enumerate((
            ("velvet_purple", (0.3, 0.05, 0.4), (0.8, 0.8, 0.8), 0.5),
            ("velvet_green", (0.05, 0.3, 0.1), (1.0, 0.9, 0.5), 0.3))):
        mat = principled(name, color, roughness=0.8, specular=0.5)
        add_velvet(mat, sheen_color, sigma)
        add_sphere(name + "_sphere", mat, (-0.8 + 1.6 * i, 0.2, 0.6), 0.6, 48, 24)
    add_light("POINT", "back", (-0.5, 1.8, 0.9), 60.0)  # behind: sheen shows at grazing angles
    add_light("POINT", "fill", (1.5, -3.0, 2.5), 250.0)
    return {"frames": [1], "notes": "Principled + Velvet BSDF (Add Shader), which the 3.4 "
            "exporter writes as KHR_materials_sheen. Cycles' Velvet is not glTF's Charlie "
            "sheen and is added on top of the base, not layered: a coverage file, not a "
            "tight reference."}


def emissive(assets):
    reset()
    _stage()
    panel = principled("panel_light", (0, 0, 0), roughness=1.0, specular=0.0,
                       Emission=(1.0, 0.9, 0.75), Emission_Strength=6.0)
    add_plane("emissive_panel", panel, (-1.0, 1.5, 2.2), 1.6, 0.8,
              rotation=(math.radians(130), 0, 0))
    orb = principled("orb_light", (0, 0, 0), roughness=1.0, specular=0.0,
                     Emission=(0.2, 0.5, 1.0), Emission_Strength=3.0)
    add_sphere("emissive_sphere", orb, (1.2, 0.5, 0.4), 0.4)
    dim = principled("dim_light", (0, 0, 0), roughness=1.0, specular=0.0,
                     Emission=(0.9, 0.3, 0.1), Emission_Strength=0.8)
    add_box("emissive_box", dim, (-0.2, -0.8, 0.25), 0.5, rotation=(0, 0, math.radians(15)))
    add_sphere("white_sphere", diffuse("white", (0.8, 0.8, 0.8)), (-1.6, -0.3, 0.5), 0.5)
    return {"frames": [1], "notes": "Light only from emissive meshes (Principled Emission, "
            "strength 6, 3 and 0.8: the first two exceed 1 and are written with "
            "KHR_materials_emissive_strength); a white diffuse sphere, floor and wall receive."}


def animated(assets):
    reset()
    sc = bpy.context.scene
    sc.frame_end = 24
    _stage()
    _studio_objects(assets)
    _studio_lights()
    metal = bpy.data.objects["metal_sphere"]
    key_bezier_thirds(metal, "location", ((1, (0.1, 0.9, 0.55)), (9, (0.9, 0.3, 0.55)),
                                          (17, (0.3, -0.6, 0.9)), (24, (-0.5, 0.2, 0.55))))
    cube = bpy.data.objects["textured_cube"]
    key_linear(cube, "location", ((1, (1.5, -0.3, 0.5)), (24, (1.8, 0.6, 0.5))))
    key_linear(cube, "rotation_euler", ((1, (0, 0, math.radians(-20))),
                                        (24, (0, 0, math.radians(100)))))
    cam = sc.camera
    start_rot = cam.rotation_euler.copy()
    end_rot = start_rot.copy()
    end_rot.z += math.radians(20)  # pan left while moving right: the objects stay in view
    key_linear(cam, "location", ((1, tuple(cam.location)), (24, (2.5, -5.5, 2.6))))
    key_linear(cam, "rotation_euler", ((1, tuple(start_rot)), (24, tuple(end_rot))))
    point = bpy.data.objects["point"]
    key_linear(point, "location", ((1, tuple(point.location)), (24, (-0.5, -2.0, 2.6))))
    return {"frames": [1, 12, 24], "fisheye": True,
            "export": {"export_force_sampling": False},
            "notes": "The studio animated over 24 frames at 24 fps: the gold sphere on Bezier "
            "keys at 1, 9, 17, 24 (handles at 1/3 in time: exported as CUBICSPLINE that "
            "equals Blender's curve), the cube moving and turning about Z on LINEAR keys, the "
            "camera moving and panning (LINEAR), the point light moving (LINEAR). Exported "
            "without forced sampling so the file keeps these interpolations."}


def _bend_weights(z, height, n_bones):
    """Weights of the bones along the cylinder: a linear blend over the middle half of each
    joint's neighbourhood."""
    seg = height / n_bones
    w = [0.0] * n_bones
    pos = z / seg - 0.5
    i = max(0, min(n_bones - 1, int(math.floor(pos))))
    f = pos - i
    if pos <= 0:
        w[0] = 1.0
    elif pos >= n_bones - 1:
        w[-1] = 1.0
    else:
        w[i], w[i + 1] = 1.0 - f, f
    return w


def skinned_morph(assets):
    reset()
    sc = bpy.context.scene
    sc.frame_end = 24
    _stage()
    height, n_bones = 2.0, 3
    arm_data = bpy.data.armatures.new("rig")
    rig = bpy.data.objects.new("rig", arm_data)
    rig.location = (-1.0, 0.3, 0.0)
    sc.collection.objects.link(rig)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode="EDIT")
    prev = None
    for i in range(n_bones):
        b = arm_data.edit_bones.new("bone%d" % i)
        b.head = (0, 0, height * i / n_bones)
        b.tail = (0, 0, height * (i + 1) / n_bones)
        if prev is not None:
            b.parent = prev
            b.use_connect = True
        prev = b
    bpy.ops.object.mode_set(mode="OBJECT")
    tube = add_cylinder("bending_tube", diffuse("tube", (0.85, 0.6, 0.2)), 0.22, height,
                        segments=24, rings=18)
    tube.parent = rig
    groups = [tube.vertex_groups.new(name="bone%d" % i) for i in range(n_bones)]
    for v in tube.data.vertices:
        for g, w in zip(groups, _bend_weights(v.co.z, height, n_bones)):
            if w > 0:
                g.add([v.index], w, "REPLACE")
    mod = tube.modifiers.new("Armature", "ARMATURE")
    mod.object = rig
    for i, bone in enumerate(rig.pose.bones):
        bone.rotation_mode = "XYZ"
        if i == 0:
            continue
        angle = math.radians(35 if i == 1 else 45)  # about the bone's Z: sideways in the image
        key_linear(bone, "rotation_euler", ((1, (0, 0, 0)), (12, (0, 0, angle)),
                                            (24, (0, 0, -angle * 0.5))))
    # The morphing mesh: a sphere with two shape keys.
    blob = add_sphere("morph_blob", diffuse("blob", (0.2, 0.6, 0.7)), (1.1, 0.3, 0.7), 0.6)
    basis = blob.shape_key_add(name="Basis")
    squash = blob.shape_key_add(name="Squash", from_mix=False)
    spike = blob.shape_key_add(name="Bulge", from_mix=False)
    for i, p in enumerate(basis.data):
        co = p.co
        squash.data[i].co = (co.x * 1.35, co.y * 1.35, co.z * 0.55)
        spike.data[i].co = co + co.normalized() * 0.3 * max(0.0, co.x / 0.6) ** 2
    for key, frames_values in ((squash, ((1, 0.0), (12, 1.0), (24, 0.2))),
                               (spike, ((1, 0.0), (8, 0.0), (20, 1.0), (24, 1.0)))):
        for frame, value in frames_values:
            key.value = value
            key.keyframe_insert("value", frame=frame)
        for fc in blob.data.shape_keys.animation_data.action.fcurves:
            for kp in fc.keyframe_points:
                kp.interpolation = "LINEAR"
    add_light("POINT", "point", (1.5, -2.0, 3.2), 500.0)
    sun = add_light("SUN", "sun", (0, 0, 6), 1.0)
    sun.rotation_euler = (math.radians(40), 0, math.radians(-30))
    return {"frames": [1, 12, 24], "notes": "A tube skinned to a 3-bone chain (bones 1 and 2 "
            "bend sideways, LINEAR keys at 1, 12, 24) and a sphere with two shape keys "
            "(Squash, Bulge) whose weights are animated (LINEAR). Exported with the default "
            "forced sampling (bones and weights baked at every frame)."}


def vector_motion(assets):
    reset()
    sc = bpy.context.scene
    sc.frame_end = 24
    world_black()
    add_plane("floor", textured("checker_floor", assets, roughness=0.6, specular=0.0),
              (0, 0, 0), 6, 6)
    add_camera("camera", (0, -5.0, 3.0), (0, 0, 0.5), 50)
    ball = add_sphere("moving_sphere", textured("checker_ball", assets), (-1.5, 0.0, 0.5),
                      0.45)
    key_linear(ball, "location", ((1, (-1.5, 0.0, 0.5)), (24, (1.5, 0.3, 1.2))))
    key_linear(ball, "rotation_euler", ((1, (0, 0, 0)), (24, (0, 0, math.radians(180)))))
    for fc in ball.animation_data.action.fcurves:
        fc.extrapolation = "LINEAR"  # Cycles' Vector pass looks at frame 0 for frame 1
    sun = add_light("SUN", "sun", (0, 0, 6), 3.0)
    sun.rotation_euler = (math.radians(30), 0, math.radians(25))
    return {"frames": [1, 2], "vector": True, "notes": "A static perspective camera, a "
            "textured sphere moving (x +3 m, y +0.3 m, z +0.7 m over frames 1..24, LINEAR, "
            "turning 180 degrees about Z) across the checker floor; Cycles' Vector and Depth "
            "passes at frames 1 and 2. The F-curves extrapolate linearly (frame 0 is on the "
            "line); glTF clamps before its first key."}


def motion_blur(assets):
    reset()
    sc = bpy.context.scene
    sc.frame_end = 24
    world_black()
    add_plane("floor", diffuse("grey", (0.5, 0.5, 0.5)), (0, 0, 0), 6, 6)
    add_camera("camera", (0, -5.0, 3.0), (0, 0, 0.5), 50)
    ball = add_sphere("moving_sphere", diffuse("white", (0.8, 0.8, 0.8)), (-1.5, 0.0, 0.5),
                      0.45)
    key_linear(ball, "location", ((1, (-1.5, 0.0, 0.5)), (24, (4.5, 0.0, 0.5))))
    box = add_box("turning_box", diffuse("red", (0.8, 0.1, 0.05)), (1.2, 0.8, 0.4), 0.8)
    key_linear(box, "rotation_euler", ((1, (0, 0, 0)), (24, (0, 0, math.radians(24 * 20)))))
    for ob in (ball, box):
        for fc in ob.animation_data.action.fcurves:
            fc.extrapolation = "LINEAR"  # (the shutter before frame 1 sees the same line)
    sun = add_light("SUN", "sun", (0, 0, 6), 3.0)
    sun.rotation_euler = (math.radians(30), 0, math.radians(25))
    return {"frames": [1, 12], "motion_blur": 0.5,
            "notes": "Object motion blur: a white sphere moving +x at 0.26 m per frame (LINEAR) "
            "and a red box turning 20 degrees per frame about Z, under a sun; Cycles' motion "
            "blur on, shutter 0.5 frame centred on the frame (position CENTER), i.e. anamorph's "
            "camera.shutter = [-0.25, 0.25]. Exported with the default forced sampling (a key "
            "at every frame)."}


SCENES = {f.__name__: f for f in (point_only, spot_only, sun_only, alpha_shadow, studio,
                                   transmission, clearcoat, sheen, emissive, animated,
                                   skinned_morph, vector_motion, motion_blur)}
