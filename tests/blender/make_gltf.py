"""Builds the test scenes of scenes.py, exports each with Blender's own glTF exporter and renders
Cycles references of it, with statistics and Blender's projections of every object.

  blender -b --factory-startup --python tests/blender/make_gltf.py -- OUTDIR \
      [--only NAME[,NAME...]] [--spp N] [--threads N]

Writes OUTDIR/NAME.glb, OUTDIR/NAME.reference.json, OUTDIR/textures/checker.png, the EXRs in
OUTDIR/cycles/ (not committed) and, for vector_motion, OUTDIR/vector_motion_fFFFF.passes.exr
(Cycles' Vector and Depth passes only). Blender 3.4 (Debian 12), Python 3.11. Exit code 1 when
an export does not reproduce Blender's own evaluation of the scene (positions, light and camera
directions, morph weights, camera field of view) at every whole and half frame.
"""
import argparse
import json
import math
import os
import sys
import time

import bpy
import numpy as np
from bpy_extras.object_utils import world_to_camera_view
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import exr_io  # noqa: E402
import gltf_inspect  # noqa: E402
import scenes  # noqa: E402

# The exporter's options, all written out (3.4 defaults except: cameras and lights on, a
# copyright string). Scenes may override some (scenes.py: "export").
EXPORT_OPTIONS = {
    "export_format": "GLB", "export_copyright": "anamorph test data, CC0-1.0",
    "export_image_format": "AUTO", "export_texcoords": True, "export_normals": True,
    "export_tangents": False, "export_materials": "EXPORT", "export_original_specular": False,
    "export_colors": True, "export_attributes": False, "use_mesh_edges": False,
    "use_mesh_vertices": False, "export_cameras": True, "export_lights": True,
    "convert_lighting_mode": "SPEC", "use_selection": False, "use_visible": False,
    "use_renderable": False, "use_active_collection": False, "use_active_scene": False,
    "export_extras": False, "export_yup": True, "export_apply": False,
    "export_animations": True, "export_frame_range": True, "export_frame_step": 1,
    "export_force_sampling": True, "export_nla_strips": True, "export_def_bones": False,
    "export_optimize_animation_size": False, "export_anim_single_armature": True,
    "export_reset_pose_bones": True, "export_current_frame": False, "export_skins": True,
    "export_all_influences": False, "export_morph": True, "export_morph_normal": True,
    "export_morph_tangent": False, "export_draco_mesh_compression_enable": False,
    "will_save_settings": False,
}

WIDTH, HEIGHT = 160, 120
FISHEYE_SIZE = 120  # Cycles stretches its fisheye circle over the whole frame: render square
BLOCK = 8
SEEDS = (1, 2)
BOUNCES = 8
DEFAULT_SPP = 512
EXPORT_TOLERANCE = 1e-4  # metres, radians-ish (unit vectors), weights

CONVENTIONS = {
    "axes": "Blender: right-handed, +Z up, metres. glTF (the exporter, export_yup): "
            "(x, y, z)_gltf = (x, z, -y)_blender.",
    "time": "glTF time t = frame / fps: Blender 3.4's exporter writes keyframe times as "
            "frame / fps, so frame 1 is t = 1/24 s (not 0); each frame lists gltf_time_s.",
    "pixel": "Continuous pixel coordinates: x to the right, y down, (0, 0) the top-left "
             "corner of the image; the centre of pixel column i, row j (from the top) is "
             "(i + 0.5, j + 0.5). Perspective: Blender's "
             "bpy_extras.object_utils.world_to_camera_view (u, v) -> (u * width, (1 - v) * "
             "height); depth is its z (distance along the view axis). Fisheye: the "
             "equidistant formula of Cycles (see the variant's projection note).",
    "image_stats": "Linear scene-referred RGB (the EXR's R, G, B). The reference image is "
                   "the average of the renders with the two seeds.",
    "blocks": "8 x 8 pixel blocks, rows from the top then columns from the left: "
              "mean[r][c] = [R, G, B] over rows 8r..8r+7, columns 8c..8c+7 of the reference.",
    "stderr": "Standard error of the stored value (the mean of the two seeds' renders), "
              "estimated from the per-pixel differences d = a - b of the two renders: "
              "sqrt(sum d^2) / (2 n) over the n pixels of the block or image (64 degrees of "
              "freedom per block; pixels independent). One render alone has sqrt(2) times it.",
}


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="make_gltf.py")
    p.add_argument("outdir")
    p.add_argument("--only", action="append", default=[],
                   help="scene name(s), comma-separated; repeatable (default: all)")
    p.add_argument("--spp", type=int, default=DEFAULT_SPP)
    p.add_argument("--threads", type=int, default=2)
    a = p.parse_args(argv)
    names = [n for arg in a.only for n in arg.split(",") if n]
    unknown = [n for n in names if n not in scenes.SCENES]
    if unknown:
        p.error("unknown scene(s) %s; valid: %s" % (", ".join(unknown),
                                                     ", ".join(scenes.SCENES)))
    a.names = names or list(scenes.SCENES)
    return a


# ---------------------------------------------------------------------------------------------
# Export and its check


def export(path, options):
    tmp = path[:-4] + ".partial.glb"
    bpy.ops.export_scene.gltf(filepath=tmp, **options)
    os.replace(tmp, path)


def to_gltf(v):
    return [v[0], v[2], -v[1]]


def blender_state(sc):
    """At the current frame: {node name: (position, -Z axis or None)} in glTF axes, and
    {mesh name: {shape key: value}}."""
    state, weights = {}, {}
    for ob in sc.objects:
        mw = ob.matrix_world
        axis = None
        if ob.type in ("LIGHT", "CAMERA"):
            axis = to_gltf((mw.to_3x3() @ Vector((0, 0, -1))).normalized())
        state[ob.name] = (to_gltf(mw.translation), axis)
        if ob.type == "ARMATURE":
            for pb in ob.pose.bones:
                state[pb.name] = (to_gltf(mw @ pb.head), None)
        keys = ob.data.shape_keys if ob.type == "MESH" else None
        if keys is not None:
            weights[ob.data.name] = {k.name: k.value for k in keys.key_blocks[1:]}
    return state, weights


def check_export(doc, binary, sc):
    """Compares the glTF evaluated at t = frame / fps with Blender at every frame and half
    frame of the scene's range. Returns the largest differences."""
    worst = {"position_m": 0.0, "direction": 0.0, "morph_weight": 0.0, "nodes_compared": 0}
    names = {i: n.get("name") for i, n in enumerate(doc["nodes"])}
    times = [(f, sub) for f in range(sc.frame_start, sc.frame_end + 1) for sub in (0.0, 0.5)]
    for frame, sub in times[:-1]:
        sc.frame_set(frame, subframe=sub)
        state, weights = blender_state(sc)
        world = gltf_inspect.evaluate(doc, binary, (frame + sub) / sc.render.fps)
        compared = 0
        for i, (m, w) in world.items():
            if names[i] not in state:
                continue
            pos, axis = state[names[i]]
            gpos = [m[r][3] for r in range(3)]
            worst["position_m"] = max(worst["position_m"],
                                      max(abs(a - b) for a, b in zip(pos, gpos)))
            if axis is not None:
                gaxis = [-m[r][2] for r in range(3)]
                n = math.sqrt(sum(x * x for x in gaxis))
                worst["direction"] = max(worst["direction"],
                                         max(abs(a - b / n) for a, b in zip(axis, gaxis)))
            mesh = doc["meshes"][doc["nodes"][i]["mesh"]] if "mesh" in doc["nodes"][i] else None
            if w is not None and mesh is not None and mesh.get("name") in weights:
                ref = list(weights[mesh["name"]].values())
                worst["morph_weight"] = max(worst["morph_weight"],
                                            max(abs(a - b) for a, b in zip(ref, w)))
            compared += 1
        worst["nodes_compared"] = max(worst["nodes_compared"], compared)
    sc.frame_set(sc.frame_start)
    worst["frames"] = "%d..%d, whole and half frames" % (sc.frame_start, sc.frame_end)
    # The camera's projection: glTF yfov and aspectRatio against Blender's frame.
    worst["camera_yfov"] = 0.0
    for n in doc["nodes"]:
        if "camera" in n and n.get("name") in sc.objects:
            persp = doc["cameras"][n["camera"]]["perspective"]
            rec = camera_record(sc, sc.objects[n["name"]])
            worst["camera_yfov"] = max(worst["camera_yfov"],
                                       abs(persp["yfov"] - math.radians(rec["angle_y_deg"])),
                                       abs(persp["aspectRatio"] - sc.render.resolution_x /
                                           sc.render.resolution_y))
    worst["ok"] = (worst["camera_yfov"] < EXPORT_TOLERANCE and
                   worst["position_m"] < EXPORT_TOLERANCE and
                   worst["direction"] < EXPORT_TOLERANCE and
                   worst["morph_weight"] < EXPORT_TOLERANCE)
    return worst


# ---------------------------------------------------------------------------------------------
# Cycles


def configure_cycles(sc, spp, threads, width, height):
    sc.render.engine = "CYCLES"
    cy = sc.cycles
    cy.device = "CPU"
    cy.feature_set = "SUPPORTED"
    cy.samples = spp
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.use_animated_seed = False
    cy.max_bounces = BOUNCES
    cy.diffuse_bounces = BOUNCES
    cy.glossy_bounces = BOUNCES
    cy.transmission_bounces = BOUNCES
    cy.volume_bounces = BOUNCES
    cy.transparent_max_bounces = BOUNCES
    cy.min_light_bounces = 0
    cy.min_transparent_bounces = 0
    cy.caustics_reflective = True
    cy.caustics_refractive = True
    cy.blur_glossy = 0.0
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.light_sampling_threshold = 0.0
    cy.pixel_filter_type = "BOX"
    cy.filter_width = 1.0
    cy.film_exposure = 1.0
    sc.render.film_transparent = False
    sc.render.use_motion_blur = False
    sc.render.threads_mode = "FIXED"
    sc.render.threads = threads
    sc.render.resolution_x = width
    sc.render.resolution_y = height
    sc.render.resolution_percentage = 100
    sc.render.pixel_aspect_x = sc.render.pixel_aspect_y = 1.0
    sc.view_settings.view_transform = "Standard"
    sc.view_settings.look = "None"
    sc.view_settings.exposure = 0.0
    sc.view_settings.gamma = 1.0
    sc.display_settings.display_device = "sRGB"
    im = sc.render.image_settings
    im.file_format = "OPEN_EXR"
    im.color_depth = "32"
    im.color_mode = "RGBA"
    im.exr_codec = "ZIP"


def render_settings(sc):
    cy = sc.cycles
    return {"engine": "CYCLES", "device": "CPU", "width": sc.render.resolution_x,
            "height": sc.render.resolution_y, "spp": cy.samples, "seeds": list(SEEDS),
            "sampling_pattern": cy.sampling_pattern, "adaptive_sampling": False,
            "denoising": False, "pixel_filter": "BOX", "filter_width_px": cy.filter_width,
            "bounces": {"max": cy.max_bounces, "diffuse": cy.diffuse_bounces,
                        "glossy": cy.glossy_bounces, "transmission": cy.transmission_bounces,
                        "volume": cy.volume_bounces, "transparent": cy.transparent_max_bounces,
                        "anamorph_max_depth": cy.max_bounces + 1,
                        "note": "Cycles' max_bounces N allows N + 1 scattering events, "
                                "anamorph's max_depth N + 1 (docs/performance.md)"},
            "caustics_reflective": True, "caustics_refractive": True, "clamp": 0,
            "filter_glossy": 0, "light_sampling_threshold": 0,
            "motion_blur": ({"shutter_frames": sc.render.motion_blur_shutter,
                             "position": cy.motion_blur_position}
                            if sc.render.use_motion_blur else False),
            "view_transform": "Standard (not applied: the EXRs are linear)",
            "film_exposure": 1.0, "threads": sc.render.threads,
            "output": "EXR RGBA float32, linear"}


def read_exr_rgb(path):
    ch = exr_io.read_exr(path)
    return np.stack([ch[c] for c in "RGB"], axis=2).astype(np.float64)  # rows from the top


def render_to(sc, path):
    t0 = time.perf_counter()
    bpy.ops.render.render(write_still=False)
    seconds = time.perf_counter() - t0
    tmp = path[:-4] + ".partial.exr"
    bpy.data.images["Render Result"].save_render(tmp)
    os.replace(tmp, path)
    rgb = read_exr_rgb(path)
    if not np.isfinite(rgb).all():
        raise SystemExit(f"make_gltf.py: {path}: non-finite pixels")
    return rgb, seconds


def dump_json(o, indent=0):
    """JSON with one key per line, but lists of numbers (and lists of such lists, as a block
    row) on one line: a readable file about a third of json.dump(indent=1)'s size."""
    def flat(v, depth):
        if isinstance(v, list):
            return depth > 0 and all(flat(x, depth - 1) for x in v)
        return not isinstance(v, dict)
    pad = " " * (indent + 1)
    if isinstance(o, dict) and o:
        items = [pad + json.dumps(k) + ": " + dump_json(v, indent + 1) for k, v in o.items()]
        return "{\n" + ",\n".join(items) + "\n" + " " * indent + "}"
    if isinstance(o, list) and o and not flat(o, 2):
        return "[\n" + ",\n".join(pad + dump_json(v, indent + 1) for v in o) + "\n" + \
            " " * indent + "]"
    return json.dumps(o, separators=(",", ":"))


def r6(x):
    """Rounds (nested) floats to 6 significant digits for the JSON."""
    if isinstance(x, (list, tuple)):
        return [r6(v) for v in x]
    return float("%.6g" % x)


def image_stats(a, b):
    ref, d2 = (a + b) / 2, (a - b) ** 2
    h, w, _ = ref.shape
    bh, bw = h // BLOCK, w // BLOCK
    blocks = ref.reshape(bh, BLOCK, bw, BLOCK, 3).mean(axis=(1, 3))
    block_se = np.sqrt(d2.reshape(bh, BLOCK, bw, BLOCK, 3).sum(axis=(1, 3))) / (2 * BLOCK ** 2)
    return {"image_mean": r6(ref.mean(axis=(0, 1)).tolist()),
            "image_mean_stderr": r6((np.sqrt(d2.sum(axis=(0, 1))) / (2 * h * w)).tolist()),
            "image_mean_per_seed": [r6(a.mean(axis=(0, 1)).tolist()),
                                    r6(b.mean(axis=(0, 1)).tolist())],
            "blocks": {"size": BLOCK, "rows": bh, "cols": bw, "mean": r6(blocks.tolist()),
                       "stderr": r6(block_se.tolist())}}


# ---------------------------------------------------------------------------------------------
# Projections


def fisheye_pixel(cam, co, width, height):
    """Cycles' equidistant fisheye (fisheye_fov = pi): theta from the view axis (-Z) maps
    linearly to the radius, theta = 90 degrees at the edge of the circle inscribed in the image;
    image up is the camera's +Y, image right its +X."""
    p = cam.matrix_world.inverted() @ co
    theta = math.atan2(math.hypot(p.x, p.y), -p.z)
    phi = math.atan2(p.y, p.x)
    r = theta / (cam.data.cycles.fisheye_fov / 2)
    return [width / 2 * (1 + r * math.cos(phi)), height / 2 * (1 - r * math.sin(phi))], r <= 1


def projections(sc, fisheye=False):
    cam = sc.camera
    w, h = sc.render.resolution_x, sc.render.resolution_y
    out = {}
    points = []
    for ob in sc.objects:
        if ob.type in ("MESH", "LIGHT"):
            points.append((ob.name, ob.type, ob.matrix_world.translation.copy(), ob))
        if ob.type == "ARMATURE":
            for pb in ob.pose.bones:
                points.append((pb.name, "BONE_HEAD", ob.matrix_world @ pb.head, None))
    for name, kind, co, ob in points:
        rec = {"type": kind, "world_blender": r6(list(co)), "world_gltf": r6(to_gltf(co))}
        if fisheye:
            px, inside = fisheye_pixel(cam, co, w, h)
            rec.update(pixel=r6(px), in_image=inside)
        else:
            v = world_to_camera_view(sc, cam, co)
            rec.update(pixel=r6([v.x * w, (1 - v.y) * h]), depth=r6(v.z),
                       in_image=bool(0 <= v.x <= 1 and 0 <= v.y <= 1 and v.z > 0))
        if ob is not None and ob.type == "LIGHT":
            rec["light"] = light_record(ob)
        out[name] = rec
    return out


def light_record(ob):
    """The light's Blender settings and what the glTF should say (KHR_lights_punctual)."""
    li = ob.data
    d = (ob.matrix_world.to_3x3() @ Vector((0, 0, -1))).normalized()
    rec = {"blender_type": li.type, "energy": li.energy, "color": r6(list(li.color)),
           "direction_gltf": r6(to_gltf(d))}
    if li.type == "SUN":
        rec["expected_gltf"] = {"type": "directional", "intensity_lux": r6(li.energy * 683)}
    else:
        rec["expected_gltf"] = {"type": li.type.lower(),
                                "intensity_cd": r6(li.energy / (4 * math.pi) * 683)}
    if li.type == "SPOT":
        half = li.spot_size / 2
        rec["spot_size_rad"], rec["spot_blend"] = r6(li.spot_size), r6(li.spot_blend)
        rec["expected_gltf"].update(outerConeAngle=r6(half),
                                    innerConeAngle=r6(half - half * li.spot_blend))
        rec["cycles_cone"] = {"cos_half": r6(math.cos(half)),
                              "smooth": r6((1 - math.cos(half)) * li.spot_blend)}
    return rec


def camera_record(sc, cam=None):
    cam = cam or sc.camera
    mw = cam.matrix_world
    rec = {"name": cam.name, "position_gltf": r6(to_gltf(mw.translation)),
           "forward_gltf": r6(to_gltf((mw.to_3x3() @ Vector((0, 0, -1))).normalized())),
           "up_gltf": r6(to_gltf((mw.to_3x3() @ Vector((0, 1, 0))).normalized())),
           "type": cam.data.type}
    if cam.data.type == "PERSP":
        rec.update(angle_x_deg=r6(math.degrees(cam.data.angle_x)),
                   angle_y_deg=r6(math.degrees(2 * math.atan(
                       math.tan(cam.data.angle_x / 2) * sc.render.resolution_y /
                       sc.render.resolution_x))), sensor_fit=cam.data.sensor_fit)
    else:
        rec.update(panorama_type=cam.data.cycles.panorama_type,
                   fisheye_fov_deg=r6(math.degrees(cam.data.cycles.fisheye_fov)))
    return rec


def morph_weights(sc):
    return {ob.name: {k.name: r6(k.value) for k in ob.data.shape_keys.key_blocks[1:]}
            for ob in sc.objects if ob.type == "MESH" and ob.data.shape_keys}


# ---------------------------------------------------------------------------------------------
# Rendering a scene's frames


def render_frames(sc, name, tag, frames, cycles_dir, fisheye=False):
    out = []
    for frame in frames:
        sc.frame_set(frame)
        imgs, seconds, files = [], [], []
        for seed in SEEDS:
            sc.cycles.seed = seed
            fname = "%s%s_f%04d_s%d.exr" % (name, tag, frame, seed)
            rgb, s = render_to(sc, os.path.join(cycles_dir, fname))
            imgs.append(rgb)
            seconds.append(round(s, 3))
            files.append(fname)
        rec = {"frame": frame, "gltf_time_s": r6(frame / sc.render.fps),
               **image_stats(*imgs), "exr": ["cycles/" + f for f in files],
               "render_seconds": seconds, "camera": camera_record(sc),
               "objects": projections(sc, fisheye)}
        weights = morph_weights(sc)
        if weights:
            rec["morph_weights"] = weights
        out.append(rec)
        print("make_gltf: %s%s frame %d mean %s (%.1f s)" % (name, tag, frame,
                                                             rec["image_mean"], sum(seconds)))
    return out


def fisheye_variant(sc, name, frames, cycles_dir, spp, threads):
    cam = sc.camera.data
    cam.type = "PANO"
    cam.cycles.panorama_type = "FISHEYE_EQUIDISTANT"
    cam.cycles.fisheye_fov = math.pi
    configure_cycles(sc, spp, threads, FISHEYE_SIZE, FISHEYE_SIZE)
    rec = {"description": "The scene's animated camera as a 180-degree equidistant fisheye "
                          "(Cycles panoramic camera, FISHEYE_EQUIDISTANT, fisheye_fov = pi), "
                          "switched after the export (the .glb keeps the perspective camera).",
           "projection": "r = theta / (pi / 2) with theta the angle from the camera's -Z axis; "
                         "pixel = (W/2 (1 + r cos phi), H/2 (1 - r sin phi)), phi = atan2(y, x) "
                         "in camera space (x right, y up). The circle of radius W/2 = H/2 is "
                         "inscribed in the square image; Cycles stretches it to an ellipse on a "
                         "non-square image, hence the square size. Checked: an emissive "
                         "sphere's image centroid was within 0.02 px of this formula.",
           "render": render_settings(sc),
           "frames": render_frames(sc, name, "_fisheye180", frames, cycles_dir, fisheye=True)}
    return rec


def pixel_ray(sc, px, py):
    """World ray (origin, direction) through continuous pixel (px, py) of the perspective
    camera."""
    cam = sc.camera
    w, h = sc.render.resolution_x, sc.render.resolution_y
    tr, br, bl, tl = cam.data.view_frame(scene=sc)  # camera space, z < 0
    u, v = px / w, 1 - py / h
    p = bl + (br - bl) * u + (tl - bl) * v
    mw = cam.matrix_world
    return mw.translation.copy(), (mw.to_3x3() @ p).normalized()


def vector_probe(sc, px, py, frame):
    """What Cycles' Vector pass should hold at a pixel: the surface point seen through the
    pixel centre at `frame`, carried with its object to frame - 1 and frame + 1 and projected
    by Blender (pixels, y down), minus its own position; and its planar depth and distance."""
    sc.frame_set(frame)
    dg = bpy.context.evaluated_depsgraph_get()
    origin, d = pixel_ray(sc, px, py)
    hit, loc, _, _, ob, _ = sc.ray_cast(dg, origin, d)
    if not hit:
        return None
    local = ob.matrix_world.inverted() @ loc
    cam = sc.camera
    fwd = (cam.matrix_world.to_3x3() @ Vector((0, 0, -1))).normalized()
    rec = {"pixel": [px, py], "object": ob.name, "hit_world_blender": r6(list(loc)),
           "depth_planar": r6((loc - origin).dot(fwd)), "distance": r6((loc - origin).length)}
    w, h = sc.render.resolution_x, sc.render.resolution_y
    for other, key in ((frame - 1, "to_previous_px"), (frame + 1, "to_next_px")):
        sc.frame_set(other)
        co = bpy.data.objects[ob.name].matrix_world @ local
        v = world_to_camera_view(sc, cam, co)
        rec[key] = r6([v.x * w - px, (1 - v.y) * h - py])
    sc.frame_set(frame)
    return rec


VECTOR_SPP = 64
VECTOR_CONVENTION = (
    "Cycles 3.4's Vector pass, measured on the probes below: (X, Y) = the point's position in "
    "the previous frame minus its position in this frame, (Z, W) = its position in this frame "
    "minus its position in the next frame; pixels, x to the right, y UP (Blender's raster, "
    "the opposite of this file's pixel convention). So with y down: to_previous = (X, -Y) and "
    "to_next = (-Z, W). Depth.Z is the planar depth along the camera's view axis (not the "
    "distance). Pixels that see the world hold Depth 1e10 and Vector 0. Both passes are "
    "averages over the pixel's samples, so edge pixels mix the two sides.")


def vector_passes(sc, name, frames, outdir, cycles_dir):
    """Per frame: one more render (seed 1, VECTOR_SPP samples) with the Vector and Depth passes,
    saved whole to cycles/ and as OUTDIR/NAME_fFFFF.passes.exr with only those passes; probes
    tie their sign and units to Blender's own projection."""
    vl = sc.view_layers[0]
    vl.use_pass_z = vl.use_pass_vector = True
    spp = sc.cycles.samples
    sc.cycles.samples, sc.cycles.seed = VECTOR_SPP, SEEDS[0]
    sc.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    w, h = sc.render.resolution_x, sc.render.resolution_y
    out = {"convention": VECTOR_CONVENTION, "spp": VECTOR_SPP, "seed": SEEDS[0], "frames": []}
    for frame in frames:
        sc.frame_set(frame)
        ball = bpy.data.objects["moving_sphere"]
        v = world_to_camera_view(sc, sc.camera, ball.matrix_world.translation)
        cx, cy = math.floor(v.x * w) + 0.5, math.floor((1 - v.y) * h) + 0.5
        probes = [(cx + dx, cy + dy) for dx in (-4, 0, 4) for dy in (-4, 0, 4)]
        probes += [(20.5, 100.5), (140.5, 110.5), (80.5, 40.5)]
        full = os.path.join(cycles_dir, "%s_f%04d_passes.exr" % (name, frame))
        bpy.ops.render.render(write_still=False)
        bpy.data.images["Render Result"].save_render(full)
        ch = exr_io.read_exr(full)
        keep = {k: a for k, a in ch.items() if ".Vector." in k or ".Depth." in k}
        committed = "%s_f%04d.passes.exr" % (name, frame)
        exr_io.write_exr(os.path.join(outdir, committed), keep)
        vec = np.stack([ch["ViewLayer.Vector." + c] for c in "XYZW"], axis=2)
        depth = ch["ViewLayer.Depth.Z"]
        rec = {"frame": frame, "file": committed, "channels": sorted(keep), "probes": []}
        worst = 0.0
        for px, py in probes:
            probe = vector_probe(sc, px, py, frame)
            if probe is None:
                continue
            x, y, z, w_ = vec[int(py), int(px)].tolist()
            probe["cycles_vector_xyzw"] = r6([x, y, z, w_])
            probe["cycles_depth"] = r6(float(depth[int(py), int(px)]))
            expect = probe["to_previous_px"] + [-probe["to_next_px"][0], probe["to_next_px"][1]]
            got = [x, -y, z, w_]
            worst = max(worst, max(abs(a - b) for a, b in zip(expect, got)),
                        abs(probe["cycles_depth"] - probe["depth_planar"]))
            rec["probes"].append(probe)
        rec["convention_max_error"] = r6(worst)
        rec["vector_abs_max"] = r6(np.abs(vec).max(axis=(0, 1)).tolist())
        rec["moving_pixels"] = int((np.abs(vec).max(axis=2) > 1e-6).sum())
        out["frames"].append(rec)
        print("make_gltf: %s passes frame %d: convention error %.3g px" % (name, frame, worst))
    vl.use_pass_z = vl.use_pass_vector = False
    sc.cycles.samples = spp
    sc.render.image_settings.file_format = "OPEN_EXR"
    return out


# ---------------------------------------------------------------------------------------------


def run_scene(name, a):
    t0 = time.perf_counter()
    outdir = os.path.abspath(a.outdir)
    cycles_dir = os.path.join(outdir, "cycles")
    os.makedirs(cycles_dir, exist_ok=True)
    info = scenes.SCENES[name](os.path.join(outdir, "textures"))
    sc = bpy.context.scene
    options = dict(EXPORT_OPTIONS, **info.get("export", {}))
    glb = os.path.join(outdir, name + ".glb")
    export(glb, options)
    doc, binary = gltf_inspect.read_glb(glb)
    gltf = gltf_inspect.summary(doc, binary)
    gltf["file_bytes"] = os.path.getsize(glb)
    gltf["check_against_blender"] = check_export(doc, binary, sc)
    if not gltf["check_against_blender"]["ok"]:
        print("make_gltf: %s: the export differs from Blender: %s" %
              (name, gltf["check_against_blender"]), file=sys.stderr)
    import io_scene_gltf2
    ref = {"scene": name, "notes": info["notes"],
           "generated_by": "tests/blender/make_gltf.py (scenes.py: %s)" % name,
           "licence": "CC0-1.0", "blender": bpy.app.version_string,
           "exporter": "io_scene_gltf2 %s" % ".".join(map(str, io_scene_gltf2.bl_info["version"])),
           "export_options": options, "fps": sc.render.fps,
           "frame_range": [sc.frame_start, sc.frame_end], "conventions": CONVENTIONS,
           "gltf": gltf}
    configure_cycles(sc, a.spp, a.threads, WIDTH, HEIGHT)
    if info.get("motion_blur"):
        # Blender's shutter: a fraction of a frame centred on the frame.
        sc.render.use_motion_blur = True
        sc.render.motion_blur_shutter = info["motion_blur"]
        sc.cycles.motion_blur_position = "CENTER"
    ref["render"] = render_settings(sc)
    ref["frames"] = render_frames(sc, name, "", info["frames"], cycles_dir)
    if info.get("vector"):
        ref["vector_pass"] = vector_passes(sc, name, info["frames"], outdir, cycles_dir)
    if info.get("fisheye"):
        ref["variants"] = {"fisheye180": fisheye_variant(sc, name, info["frames"], cycles_dir,
                                                         a.spp, a.threads)}
    if info.get("motion_blur"):
        # The same frames without motion blur: what the blur changes, per block, with the two
        # renderers' shading differences cancelled.
        sc.render.use_motion_blur = False
        ref["variants"] = {"still": {
            "description": "The same frames with Cycles' motion blur off.",
            "render": render_settings(sc),
            "frames": render_frames(sc, name, "_still", info["frames"], cycles_dir)}}
    ref["generation_seconds"] = round(time.perf_counter() - t0, 1)
    path = os.path.join(outdir, name + ".reference.json")
    with open(path + ".partial", "w") as f:
        f.write(dump_json(ref) + "\n")
    os.replace(path + ".partial", path)
    print("make_gltf: %s done in %.1f s" % (name, ref["generation_seconds"]))
    return gltf["check_against_blender"]["ok"]


def main():
    a = parse_args()
    t0 = time.perf_counter()
    failed = [name for name in a.names if not run_scene(name, a)]
    print("make_gltf: %d scene(s) in %.1f s" % (len(a.names), time.perf_counter() - t0))
    if failed:
        print("make_gltf: exports that differ from Blender: %s" % ", ".join(failed),
              file=sys.stderr)
        sys.exit(1)


try:
    main()
except SystemExit as e:
    # Blender keeps running after a script's SystemExit; leave with its code.
    sys.stdout.flush()
    os._exit(e.code if isinstance(e.code, int) else 2)
except Exception:
    import traceback
    traceback.print_exc()
    sys.stdout.flush()
    os._exit(1)
os._exit(0)
