"""examples/demo.toml built in Blender (bpy), for the viewport bench (viewport_latency.py).

The same objects, placements, lights, world and camera as the demo, in Blender's axes
((x, y, z) of anamorph = (x, -z, y) of Blender): the floor is a 200 m plane (anamorph's plane is
infinite), the spheres are smooth UV spheres (64 x 32), the torus knot is examples/models'
OBJ, the materials are Principled BSDFs close to the demo's (no procedural checker or grid: the
glTF exporter does not carry node textures), the render settings the demo's (Whitted, depth 6,
960 x 540)."""

import math
import os

import bpy
import mathutils


def blender_xyz(p):
    """anamorph's (glTF's) axes to Blender's."""
    return (p[0], -p[2], p[1])


def material(name, color, metallic=0.0, roughness=0.5, transmission=0.0, ior=1.45):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    p = m.node_tree.nodes["Principled BSDF"]
    p.inputs["Base Color"].default_value = (*color, 1.0)
    p.inputs["Metallic"].default_value = metallic
    p.inputs["Roughness"].default_value = roughness
    p.inputs["Transmission"].default_value = transmission
    p.inputs["IOR"].default_value = ior
    return m


def added(op, **kw):
    """The object an operator added (found by name: a timer's context has no active object)."""
    before = set(bpy.data.objects.keys())
    op(**kw)
    return next(bpy.data.objects[n] for n in bpy.data.objects.keys() if n not in before)


def add(op, mat, smooth=False, **kw):
    ob = added(op, **kw)
    ob.data.materials.append(mat)
    if smooth:
        for poly in ob.data.polygons:
            poly.use_smooth = True
    return ob


def build(repo):
    """The demo in the current (empty) scene; returns the scene. Operators need a window's
    context (bpy.context.temp_override(window=...)) when called from a timer."""
    scene = bpy.context.scene
    mats = {
        "floor": material("floor", (0.5, 0.5, 0.49), roughness=0.6),
        "glass": material("glass", (1, 1, 1), roughness=0.0, transmission=0.95, ior=1.5),
        "mirror": material("mirror", (0.9, 0.9, 0.9), metallic=1.0, roughness=0.0),
        "matte_red": material("matte_red", (0.75, 0.12, 0.1), roughness=0.4),
        "column": material("column", (0.6, 0.57, 0.5), roughness=0.6),
        "gold": material("gold", (1.0, 0.77, 0.34), metallic=1.0, roughness=0.3),
    }
    add(bpy.ops.mesh.primitive_plane_add, mats["floor"], size=200)
    for centre, name in (((-1.6, 0.8, 0.6), "glass"), ((0.0, 0.8, -0.6), "mirror"),
                         ((1.6, 0.8, 0.6), "matte_red")):
        add(bpy.ops.mesh.primitive_uv_sphere_add, mats[name], smooth=True, radius=0.8,
            segments=64, ring_count=32, location=blender_xyz(centre))
    knot = added(bpy.ops.wm.obj_import, filepath=os.path.join(
        repo, "examples", "models", "torus_knot.obj"), forward_axis="NEGATIVE_Z", up_axis="Y")
    knot.name = "torus_knot"
    knot.scale = (0.8, 0.8, 0.8)
    knot.location = blender_xyz((0.0, 0.5, 2.4))
    knot.data.materials.clear()
    knot.data.materials.append(mats["gold"])
    for x in (-4.5, -1.5, 1.5, 4.5):
        add(bpy.ops.mesh.primitive_cylinder_add, mats["column"], radius=0.3, depth=3,
            vertices=48, location=blender_xyz((x, 1.5, -4)))
    box = add(bpy.ops.mesh.primitive_cube_add, mats["column"], size=1,
              location=blender_xyz((0, 3.15, -4)))
    box.scale = (10, 0.8, 0.3)
    box.name = "box"
    for name, pos, intensity in (("key", (4.0, 6.0, 5.0), (90, 86, 80)),
                                 ("fill", (-5.0, 4.0, 2.0), (18, 20, 26))):
        light = bpy.data.lights.new(name, "POINT")
        top = max(intensity)
        light.energy = 4 * math.pi * top  # the add-on's point: intensity = P / 4 pi
        light.color = [c / top for c in intensity]
        light.shadow_soft_size = 0.0
        ob = bpy.data.objects.new(name, light)
        ob.location = blender_xyz(pos)
        scene.collection.objects.link(ob)
    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.22, 0.28, 0.38, 1)
    scene.world = world
    cam = bpy.data.cameras.new("camera")
    cam.sensor_fit, cam.angle = "HORIZONTAL", math.radians(55)
    cam_ob = bpy.data.objects.new("camera", cam)
    eye = mathutils.Vector(blender_xyz((0.0, 2.2, 7.5)))
    cam_ob.location = eye
    look = mathutils.Vector(blender_xyz((0.0, 0.8, 0.0))) - eye
    cam_ob.rotation_euler = look.to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(cam_ob)
    scene.camera = cam_ob
    r = scene.render
    r.resolution_x, r.resolution_y, r.resolution_percentage = 960, 540, 100
    return scene
