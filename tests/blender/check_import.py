"""Imports each .glb of a folder back into Blender with Blender's glTF importer and compares
what comes back with the scene it was made from (NAME.reference.json): the light types, powers
and spot cones, the camera, the animated objects, the skin's bones, the shape keys and the
material inputs the extensions carry. A round trip through a second, independent reader of
the same files (the importer shares no code path with gltf_inspect.py).

  blender -b --factory-startup --python tests/blender/check_import.py -- DIR

Prints one line per file and the differences; exit code 1 when a light, camera, animation,
skin or morph target did not come back.
"""
import glob
import json
import math
import os
import sys

import bpy
import numpy

if "bool" not in numpy.__dict__:
    numpy.bool = bool  # Debian 12's Blender 3.4 importer uses np.bool, which numpy 1.24 removed


def principled_inputs(mat):
    p = next((n for n in mat.node_tree.nodes if n.type == "BSDF_PRINCIPLED"), None)
    if p is None:
        return {}
    names = ("Transmission", "Clearcoat", "Clearcoat Roughness", "IOR", "Metallic",
             "Roughness", "Emission Strength")
    out = {k: round(p.inputs[k].default_value, 4) for k in names if not p.inputs[k].is_linked}
    if any(n.type == "BSDF_VELVET" for n in mat.node_tree.nodes):
        out["velvet"] = True
    if any(n.type == "VOLUME_ABSORPTION" for n in mat.node_tree.nodes):
        out["volume_absorption"] = True
    return out


def check(glb):
    ref = json.load(open(glb[:-4] + ".reference.json"))
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=glb)
    problems = []
    objs = {ob.name: ob for ob in bpy.data.objects}
    lights = {n: o["light"] for n, o in ref["frames"][0]["objects"].items() if "light" in o}
    for name, want in lights.items():
        ob = objs.get(name)
        if ob is None or ob.type != "LIGHT":
            problems.append("light %s missing" % name)
            continue
        li = ob.data
        if li.type != want["blender_type"]:
            problems.append("light %s: type %s, want %s" % (name, li.type, want["blender_type"]))
        if abs(li.energy - want["energy"]) > 1e-3 * want["energy"]:
            problems.append("light %s: %.6g W, want %.6g W" % (name, li.energy, want["energy"]))
        if li.type == "SPOT":
            if abs(li.spot_size - want["spot_size_rad"]) > 1e-4 or \
                    abs(li.spot_blend - want["spot_blend"]) > 1e-4:
                problems.append("spot %s: size %.5f blend %.5f, want %.5f %.5f" % (
                    name, li.spot_size, li.spot_blend, want["spot_size_rad"],
                    want["spot_blend"]))
    cams = [ob for ob in bpy.data.objects if ob.type == "CAMERA"]
    want_cam = ref["frames"][0]["camera"]
    if len(cams) != 1:
        problems.append("%d cameras" % len(cams))
    elif abs(math.degrees(cams[0].data.angle_y) - want_cam["angle_y_deg"]) > 1e-3:
        problems.append("camera angle_y %.4f, want %.4f" % (math.degrees(cams[0].data.angle_y),
                                                            want_cam["angle_y_deg"]))
    animated = sorted({c["node"] for a in ref["gltf"]["animations"] for c in a["channels"]})
    actions = sorted(a.name for a in bpy.data.actions)
    for node in animated:
        ob = objs.get(node)
        owner = ob if ob is not None else next(
            (o for o in bpy.data.objects if o.type == "ARMATURE" and node in o.pose.bones), None)
        if owner is None and not any(k.user.name == node for k in bpy.data.shape_keys):
            problems.append("animated node %s missing" % node)
    skins = [o for o in bpy.data.objects if o.type == "ARMATURE"]
    for s in ref["gltf"]["skins"]:
        if not any(sorted(b.name for b in a.data.bones) == sorted(s["joints"]) for a in skins):
            problems.append("skin %s: no armature with bones %s" % (s["name"], s["joints"]))
    for m in ref["gltf"]["morph_meshes"]:
        keys = [k for k in bpy.data.shape_keys if k.user.name == m["name"]]
        got = [b.name for b in keys[0].key_blocks[1:]] if keys else []
        if got != m["target_names"]:
            problems.append("mesh %s: shape keys %s, want %s" % (m["name"], got,
                                                                   m["target_names"]))
    mats = {m.name: principled_inputs(m) for m in bpy.data.materials if m.node_tree}
    interesting = {k: v for k, v in mats.items()
                   if v.get("Transmission", 0) > 0 or v.get("Clearcoat", 0) > 0 or
                   v.get("velvet") or v.get("volume_absorption") or
                   v.get("Emission Strength", 1) > 1}
    print("check_import: %s: %d objects, %d lights, %d cameras, actions %s, armatures %s, "
          "materials %s" % (os.path.basename(glb), len(objs), len(lights), len(cams), actions,
                            [a.name for a in skins], interesting))
    for p in problems:
        print("check_import: %s: %s" % (os.path.basename(glb), p))
    return not problems


def main():
    folder = sys.argv[sys.argv.index("--") + 1]
    files = sorted(glob.glob(os.path.join(folder, "*.glb")))
    bad = [f for f in files if not check(f)]
    print("check_import: %d file(s), %d with problems" % (len(files), len(bad)))
    return 1 if bad or not files else 0


try:
    code = main()
except Exception:
    import traceback
    traceback.print_exc()
    code = 1
sys.stdout.flush()
os._exit(code)
