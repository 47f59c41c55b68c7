"""Everything that talks to Blender (bpy): properties, panels, the render engine, the export.

A new Blender API is one place to change: this module. Tested with Debian 12's Blender 3.4.1.
"""

import hashlib
import math
import os
import queue
import shutil
import tempfile
import threading
import time
import traceback
import weakref

import bpy
import mathutils
import numpy as np

from . import glb_default, locate, scene_toml, schema_props

ADDON = __package__
# What the engine's progress callback asks to stop a render: the engine's own test_break (Esc).
# Tests replace it to cancel a headless render, where no key can be pressed.
break_requested = lambda engine: engine.test_break()  # noqa: E731
# The classes made from anamorph's declarations at register time, unregistered in reverse.
_classes = []
# Why the module could not be loaded at register time (shown in the panels), or "".
_load_error = ""
# The last error the engine reported (for scripts and tests: reports go to Blender's log).
last_error = ""


class Cancelled(Exception):
    """The user cancelled (Esc): raised from the progress callback, ends the render quietly."""


# ---------------------------------------------------------------------------------------------
# Properties from anamorph's declarations


def _make_prop(spec):
    """A bpy property for one declared key (schema_props.describe)."""
    kw = {"name": spec["key"], "description": spec["doc"] + (
        f" [{spec['unit']}]" if spec["unit"] else "")}
    kind, default = spec["kind"], spec["default"]
    lo, hi = spec["min"], spec["max"]
    if kind == "float":
        kw["default"] = default if isinstance(default, float) else 0.0
        for name, v in (("min", lo), ("max", hi)):
            if v is not None and math.isfinite(v) and abs(v) <= 3e38:
                kw["soft_" + name] = v
        return bpy.props.FloatProperty(precision=4, **kw)
    if kind == "int":
        kw["default"] = default if isinstance(default, int) else 0
        for name, v in (("min", lo), ("max", hi)):
            if v is not None and math.isfinite(v):
                kw[name] = int(max(-(2**31), min(2**31 - 1, v)))
        return bpy.props.IntProperty(**kw)
    if kind == "bool":
        return bpy.props.BoolProperty(default=bool(default), **kw)
    if kind == "enum":
        items = [(c, c, "") for c in spec["choices"]]
        kw["default"] = default if default in spec["choices"] else spec["choices"][0]
        return bpy.props.EnumProperty(items=items, **kw)
    if kind == "vector":
        kw["default"] = default if default is not None else [0.0] * spec["size"]
        return bpy.props.FloatVectorProperty(size=spec["size"], **kw)
    # "string" and "toml" (a list of numbers as TOML text, e.g. "[0, 1.2, 0.1]").
    return bpy.props.StringProperty(default="", **kw)


def _group(name, specs, extra=None):
    """A PropertyGroup class with one property per spec (plus `extra` annotations)."""
    annotations = dict(extra or {})
    for spec in specs:
        annotations[spec["prop"]] = _make_prop(spec)
    cls = type(name, (bpy.types.PropertyGroup,), {"__annotations__": annotations,
                                                  "specs": specs})
    bpy.utils.register_class(cls)
    _classes.append(cls)
    return cls


def set_values(group, where, parsed=False):
    """{key: value} of the properties the user set (or animated) on a generated group: a key
    left alone takes anamorph's declared default, which may depend on other keys. `where` names
    the table in messages (camera, coin '<name>', render). TOML text stays text (written as
    typed) unless `parsed`: inside an org/dir table it is written as its parsed value."""
    out = {}
    for spec in group.specs:
        if not group.is_property_set(spec["prop"]):
            continue
        v = getattr(group, spec["prop"])
        if spec["kind"] == "vector":
            v = [float(x) for x in v]
        elif spec["kind"] == "toml":
            if not v.strip():
                continue
            v = scene_toml.Raw.checked(v, f"{where}.{spec['key']}")
            if parsed:
                v = schema_props.parse_default(v)
        elif spec["kind"] == "float":
            v = float(v)
        out[spec["key"]] = v
    return out


LENS_ITEM = ("BLENDER", "Blender lens", "The camera's own lens type: perspective, "
             "orthographic, or the panoramic type as the matching preset")
FUNCTIONS_ITEM = ("FUNCTIONS", "org/dir functions", "No preset: the rays leave the origin "
                  "function's surface in the direction function's directions (docs/cameras.md)")


def _register_declared(am):
    decl = am.declarations()
    presets = schema_props.preset_specs(decl)
    extra = {}
    items = [LENS_ITEM, FUNCTIONS_ITEM] + [(n, n, doc) for n, (doc, _) in presets.items()]
    extra["preset"] = bpy.props.EnumProperty(
        name="Preset", items=items, default="BLENDER",
        description="anamorph's camera preset (docs/cameras.md)")
    for n, (doc, specs) in presets.items():
        cls = _group("ANAMORPH_PG_preset_" + n, specs)
        extra["p_" + n] = bpy.props.PointerProperty(type=cls)
    for kind, title in (("org", "Origin function"), ("dir", "Direction function")):
        functions = schema_props.function_specs(decl, kind)
        extra[kind + "_type"] = bpy.props.EnumProperty(
            name=title, items=[(n, n, doc) for n, (doc, _) in functions.items()],
            description=f"camera.{kind}'s type (with the preset 'org/dir functions')")
        for n, (doc, specs) in functions.items():
            extra[f"{kind}_{n}"] = bpy.props.PointerProperty(
                type=_group(f"ANAMORPH_PG_{kind}_{n}", specs))
    extra["image_surface"] = bpy.props.PointerProperty(
        type=bpy.types.Object, name="Image surface", poll=lambda _, ob: ob.type == "SURFACE",
        description="A NURBS surface as the image surface instead of the preset: org = its "
        "control net (row v = 0 at the image's top), dir = its normal")
    common = _group("ANAMORPH_PG_camera_common", schema_props.camera_common_specs(decl))
    extra["common"] = bpy.props.PointerProperty(type=common)
    cam = _group("ANAMORPH_PG_camera", [], extra)
    bpy.types.Camera.anamorph = bpy.props.PointerProperty(type=cam)
    coin = _group("ANAMORPH_PG_coin", schema_props.coin_specs(decl), {
        "is_coin": bpy.props.BoolProperty(
            name="Coin", default=False,
            description="This empty is a center of interest of its parent camera")})
    bpy.types.Object.anamorph_coin = bpy.props.PointerProperty(type=coin)
    render = _group("ANAMORPH_PG_render", schema_props.render_specs(decl), {
        "keep_folder": bpy.props.StringProperty(
            name="Keep scene files in", subtype="DIR_PATH", default="",
            description="Write each frame's scene (frame_NNNN.toml and .glb) here and keep it; "
            "empty: a temporary folder, removed after the frame")})
    bpy.types.Scene.anamorph = bpy.props.PointerProperty(type=render)


# ---------------------------------------------------------------------------------------------
# Scene transfer


def _export_glb(path, scene_name, frame, subframe, set_frame=True, only=None, skip=None):
    """The scene's renderable meshes and materials at `frame`, modifiers applied, by Blender's
    own glTF exporter. False when there is no mesh to export.

    The exporter is an operator reading the scene's original objects, not the render's
    depsgraph, so it runs on Blender's main thread (main_thread_call) with the scene first set
    to the frame: its objects then hold that frame's animated values, also in an animation
    rendered from Blender's window and after a script edited them since the last frame change.
    The viewport exports the scene as it is (set_frame False: setting the frame would update the
    depsgraph, and so the viewport again). `only`: the names of the objects to export (through
    the exporter's selection; the user's selection is restored), or `skip`: the names of those
    to leave out."""
    scene = bpy.data.scenes[scene_name]
    if set_frame:
        scene.frame_set(frame, subframe=subframe)

    def chosen(o):
        return (only is None or o.name in only) and (skip is None or o.name not in skip)

    if not any(o.type in _EXPORTED_TYPES and not o.hide_render and chosen(o)
               for o in scene.objects):
        return False
    selecting = only is not None or skip is not None
    override = {"scene": scene}
    window = next((w for w in bpy.context.window_manager.windows if w.scene == scene), None)
    if window is not None:  # the exporter asks for the active object: a window's context has it
        override["window"] = window
    with bpy.context.temp_override(**override):
        objects = bpy.context.view_layer.objects
        selected = {o.name for o in objects if o.select_get()} if selecting else None
        try:
            for o in objects if selecting else ():
                o.select_set(chosen(o))
            bpy.ops.export_scene.gltf(
                filepath=path, export_format="GLB", export_apply=True, export_cameras=False,
                export_lights=False, export_animations=False, export_current_frame=True,
                export_extras=False, use_renderable=True, use_selection=selecting,
                export_yup=True, check_existing=False)
        finally:
            for o in objects if selecting else ():
                o.select_set(o.name in selected)
    glb_default.patch(path)
    return True


# Calls from a render thread to Blender's main thread: (function, result box, done event).
_main_queue = queue.Queue()


def _serve_main_queue():
    """A timer on Blender's main thread (registered with the add-on): runs queued calls."""
    while True:
        try:
            fn, box, done = _main_queue.get_nowait()
        except queue.Empty:
            return 0.02
        try:
            box["value"] = fn()
        except BaseException as e:  # handed to the waiting render thread
            box["error"] = e
        finally:
            done.set()


def main_thread_call(fn, should_stop):
    """fn() on Blender's main thread: directly when called there (background renders), else
    through the add-on's timer, waiting (and honouring Esc) until it ran. A render started from
    Blender's window runs on a render thread, where operators are not safe."""
    if threading.current_thread() is threading.main_thread():
        return fn()
    box, done = {}, threading.Event()
    _main_queue.put((fn, box, done))
    waited = 0.0
    while not done.wait(0.05):
        waited += 0.05
        if should_stop():
            raise Cancelled()
        if waited > 120:
            raise RuntimeError("anamorph: the scene export waited 2 minutes for Blender's main "
                               "thread (is Render > Lock Interface on? The add-on needs it off)")
    if "error" in box:
        raise box["error"]
    return box["value"]


def _panorama(cam):
    """Blender's panoramic settings (Camera in 4.x, the Cycles add-on's in 3.x)."""
    return cam if hasattr(cam, "panorama_type") else cam.cycles


def _deg(radians):
    """Degrees of an angle Blender holds in single precision, to 4 decimals (its precision:
    90 degrees in float32 radians is 90.0000025, beyond a latitude's range)."""
    return round(math.degrees(radians), 4)


def blender_lens(cam, width, height):
    """(preset, keys) matching Blender's own lens type."""
    big = max(width, height)
    if cam.type == "PERSP":
        fit = cam.sensor_fit
        axis = {"HORIZONTAL": "horizontal", "VERTICAL": "vertical"}.get(
            fit, "horizontal" if width >= height else "vertical")
        keys = {"fov": _deg(cam.angle), "fov_axis": axis}
        if cam.shift_x or cam.shift_y:
            keys["lens_shift"] = [cam.shift_x * big / width, cam.shift_y * big / height]
        return "perspective", keys
    if cam.type == "ORTHO":
        w = cam.ortho_scale if width >= height else cam.ortho_scale * width / height
        return "orthographic", {"view_width": w}
    pano = _panorama(cam)
    kind = pano.panorama_type
    if kind == "EQUIRECTANGULAR":
        return "equirectangular", {
            "longitude_range": [_deg(pano.longitude_min), _deg(pano.longitude_max)],
            "latitude_range": [_deg(pano.latitude_min), _deg(pano.latitude_max)]}
    if kind == "FISHEYE_EQUIDISTANT":
        return "fisheye", {"fov": _deg(pano.fisheye_fov), "mapping": "equidistant"}
    if kind == "FISHEYE_EQUISOLID":
        # r = 2 f sin(theta / 2) on the sensor; the image circle spans the shorter side.
        r = cam.sensor_width / 2 * min(width, height) / big
        theta = 2 * math.asin(min(1.0, r / (2 * pano.fisheye_lens)))
        return "fisheye", {"fov": _deg(2 * theta), "mapping": "equisolid",
                           "max_angle": min(_deg(theta), _deg(pano.fisheye_fov) / 2)}
    if kind == "MIRRORBALL":
        return "mirror_ball", {}
    raise ValueError(f"camera '{cam.name}': Blender's panorama type {kind} has no matching "
                     "anamorph preset yet; choose a preset in the camera's anamorph panel")


def _blender_dof(cam_ob, common):
    """Blender's depth of field (Camera > Depth of Field) unless the anamorph section sets
    aperture_radius: Cycles' aperture radius, focal length / (2 f-stop), and the focus distance
    (to the focus object along the view axis, when there is one)."""
    dof = cam_ob.data.dof
    if not dof.use_dof or common.is_property_set("aperture_radius"):
        return {}
    distance = dof.focus_distance
    if dof.focus_object is not None:
        axis = cam_ob.matrix_world.to_3x3() @ mathutils.Vector((0.0, 0.0, -1.0))
        to = dof.focus_object.matrix_world.translation - cam_ob.matrix_world.translation
        distance = max(1e-6, to.dot(axis.normalized()))
    return {"aperture_radius": cam_ob.data.lens * 1e-3 / (2 * dof.aperture_fstop),
            "focus_distance": distance}


def _camera_table(cam_ob, width, height, src=lambda x: x):
    cam = cam_ob.data
    settings = src(cam).anamorph
    if settings.image_surface is not None:
        preset, keys = None, _image_surface(cam_ob, settings.image_surface)
    elif settings.preset == "BLENDER":
        preset, keys = blender_lens(cam, width, height)
    elif settings.preset == "FUNCTIONS":
        preset, keys = None, {kind: {"type": t, **set_values(
            getattr(settings, f"{kind}_{t}"), f"camera.{kind}", parsed=True)}
            for kind, t in (("org", settings.org_type), ("dir", settings.dir_type))}
    else:
        preset = settings.preset
        keys = set_values(getattr(settings, "p_" + preset), "camera")
    table = {**({"preset": preset} if preset else {}), **keys,
             **_blender_dof(cam_ob, settings.common), **set_values(settings.common, "camera")}
    table["matrix"] = scene_toml.rig_matrix([list(r) for r in cam_ob.matrix_world])
    return table


def _image_surface(cam_ob, surf_ob):
    """org and dir of the camera's image surface: the first spline of a NURBS surface object,
    its control points in the camera's space (the rig without scale, as rig_matrix makes it)."""
    splines = surf_ob.data.splines
    sp = splines[0] if len(splines) else None
    if sp is None or sp.type != "NURBS" or sp.use_cyclic_u or sp.use_cyclic_v or \
            sp.use_bezier_u or sp.use_bezier_v:
        raise ValueError(f"image surface '{surf_ob.name}': a NURBS surface without cyclic or "
                         "Bezier knots is needed")
    loc, rot, _ = cam_ob.matrix_world.decompose()
    camera_from_surface = mathutils.Matrix.LocRotScale(loc, rot, None).inverted() @ \
        surf_ob.matrix_world
    nu, nv = sp.point_count_u, sp.point_count_v
    rows = [[sp.points[v * nu + u].co for u in range(nu)] for v in range(nv)]
    return scene_toml.nurbs_image_surface(
        [[list(camera_from_surface @ c.xyz) for c in row] for row in rows],
        [[float(c[3]) for c in row] for row in rows],
        sp.order_u, sp.order_v, sp.use_endpoint_u, sp.use_endpoint_v)


def _coins(depsgraph, cam_ob, src=lambda x: x):
    """The camera's coins: empties parented to it with Coin on, by name."""
    out = []
    for ob in depsgraph.objects:
        if ob.type != "EMPTY" or not src(ob).anamorph_coin.is_coin:
            continue
        if ob.parent is None or ob.parent.original != cam_ob.original:
            continue
        coin = {"position": scene_toml.to_gltf(list(ob.matrix_world.translation))}
        coin.update(set_values(src(ob).anamorph_coin, f"coin '{ob.name}'"))
        out.append((ob.name, coin))
    return [c for _, c in sorted(out, key=lambda nc: nc[0])]


# A sun wider than this [radians] gets a warning: its soft shadows are lost. Blender's default
# (0.526 degrees, the real sun's) gives shadows nearly as hard as anamorph's.
SUN_ANGLE_WARNED = math.radians(1.0)


def _lights(depsgraph, warnings):
    out = []
    for ob in depsgraph.objects:
        if ob.type != "LIGHT" or ob.hide_render:
            continue
        li = ob.data
        size = (li.size, li.size if li.shape in {"SQUARE", "DISK"} else li.size_y) \
            if li.type == "AREA" else (0.0, 0.0)
        if li.type == "SUN" and li.angle > SUN_ANGLE_WARNED:
            warnings.append(f"light '{ob.name}': the sun's angle ({math.degrees(li.angle):.3g}"
                            " degrees) is not carried over: anamorph's directional light is "
                            "one direction (hard shadows)")
        if li.type == "AREA" and li.shape in {"DISK", "ELLIPSE"}:
            warnings.append(f"light '{ob.name}': a {li.shape.lower()} area light becomes a "
                            "rectangle of the same size")
        table = scene_toml.light(
            li.type, ob.name, li.energy, li.color,
            li.shadow_soft_size if li.type == "POINT" else 0.0,
            [list(r) for r in ob.matrix_world],
            spot_size=getattr(li, "spot_size", 0.0), spot_blend=getattr(li, "spot_blend", 0.0),
            size=size)
        if table is None:
            warnings.append(f"light '{ob.name}': {li.type} lights are not carried over")
        else:
            out.append(table)
    return sorted(out, key=lambda t: t["name"])


def _environment(world, warnings, folder):
    if world is None:
        return None
    if not world.use_nodes:
        return {"color": [float(c) for c in world.color]}
    out = next((n for n in world.node_tree.nodes
                if n.type == "OUTPUT_WORLD" and n.is_active_output), None)
    if out is None or not out.inputs["Surface"].is_linked:
        return None
    bg = out.inputs["Surface"].links[0].from_node
    if bg.type != "BACKGROUND":
        warnings.append(f"world '{world.name}': only a Background node is carried over")
        return None
    strength = bg.inputs["Strength"].default_value
    if bg.inputs["Strength"].is_linked:
        warnings.append(f"world '{world.name}': a texture on the strength is not carried over "
                        "(its unlinked value is used)")
    if bg.inputs["Color"].is_linked:
        env = _environment_texture(bg.inputs["Color"].links[0].from_node, strength, warnings,
                                   folder)
        if env is not None:
            return env
        warnings.append(f"world '{world.name}': only an Environment Texture (equirectangular "
                        "image, optionally through a Mapping node) on the background's colour "
                        "is carried over (its unlinked colour is used)")
    return {"color": [float(c) * strength for c in bg.inputs["Color"].default_value[:3]]}


def _environment_texture(node, strength, warnings, folder):
    """[environment] of an Environment Texture node (equirectangular image), or None."""
    if node.type != "TEX_ENVIRONMENT" or node.projection != "EQUIRECTANGULAR":
        return None
    image = node.image
    path = _image_file(image, folder) if image is not None else None
    if path is None:
        where = bpy.path.abspath(image.filepath, library=image.library) if image else ""
        warnings.append(f"environment texture '{node.name}': its image is neither a file on "
                        f"disk, packed nor generated ({where or 'no image'})")
        return None
    z_rotation = _mapping_z(node, warnings)
    return None if z_rotation is None else scene_toml.environment_image(
        os.path.abspath(path), strength, z_rotation)


# Images written for anamorph (packed or generated): {path: what was written}, so the viewport
# writes one again only when it changed.
_written_images = {}


def _image_file(image, folder):
    """A file anamorph reads holding `image`: its own file on disk; a packed image's bytes as
    they were packed (the same file, in `folder`); a generated one saved by Blender into
    `folder` (float images as EXR, 8-bit ones as PNG in their colour space, as Cycles reads
    them). None for anything else (a movie, a missing file)."""
    image = image.original
    if image.packed_file is None and image.source == "FILE":
        path = bpy.path.abspath(image.filepath, library=image.library)
        return path if os.path.isfile(path) else None
    if image.packed_file is not None:
        ext = os.path.splitext(bpy.path.basename(image.filepath))[1] or ".png"
        what = ("packed", image.packed_file.size, image.filepath)
    elif image.source == "GENERATED":
        ext = ".exr" if image.use_generated_float else ".png"
        what = ("generated", image.generated_type, tuple(image.generated_color),
                image.generated_width, image.generated_height, image.use_generated_float,
                image.is_dirty, image.colorspace_settings.name)
    else:
        return None
    path = os.path.join(folder, "environment_" + bpy.path.clean_name(image.name) + ext)
    if _written_images.get(path) == what and os.path.isfile(path):
        return path
    part = path + ".part" + ext
    if image.packed_file is not None:
        with open(part, "wb") as f:
            f.write(image.packed_file.data)
    else:
        main_thread_call(lambda: _save_generated(image, part), lambda: False)
    os.replace(part, path)
    _written_images[path] = what
    return path


def _save_generated(image, path):
    """Saves a generated image's pixels through a new image of the same kind (saving the image
    itself would turn it into a file image). A float image's pixels are scene linear, what
    Cycles renders: written as they are only from a Non-Color image (from one in Linear,
    Blender 3.4 wrote them sRGB-encoded, seen). An 8-bit one keeps its bytes and colour space."""
    w, h = image.size
    pixels = np.empty(w * h * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    out = bpy.data.images.new("anamorph_environment", w, h, alpha=True,
                              float_buffer=image.use_generated_float)
    try:
        out.colorspace_settings.name = "Non-Color" if image.use_generated_float else \
            image.colorspace_settings.name
        out.pixels.foreach_set(pixels)
        out.file_format = "OPEN_EXR" if image.use_generated_float else "PNG"
        out.filepath_raw = path
        out.save()
    finally:
        bpy.data.images.remove(out)


def _mapping_z(tex, warnings):
    """The rotation about Blender's +Z [radians] that a Mapping node on `tex`'s Vector input
    applies to the lookup direction: 0 without one; None (with a warning) for what anamorph's
    single rotation about its up axis cannot express. Rotations about X and Y are dropped with
    a warning naming them: anamorph's [environment] turns about its up axis only (the schema's
    `rotation`), so the image is used turned about Z alone."""
    if not tex.inputs["Vector"].is_linked:
        return 0.0
    m = tex.inputs["Vector"].links[0].from_node
    if not _z_only_mapping(m):
        warnings.append(f"environment texture '{tex.name}': only a Mapping node turning "
                        "Generated coordinates about Z (uniform scale, no location) is carried "
                        "over")
        return None
    rot = m.inputs["Rotation"].default_value
    if abs(rot[0]) >= 1e-6 or abs(rot[1]) >= 1e-6:
        warnings.append(f"environment texture '{tex.name}': the Mapping node's rotation about "
                        f"X ({math.degrees(rot[0]):.4g} degrees) and Y "
                        f"({math.degrees(rot[1]):.4g} degrees) is not carried over: anamorph's "
                        "environment turns about the up axis only (its rotation about Z, "
                        f"{math.degrees(rot[2]):.4g} degrees, is)")
    return -rot[2] if m.vector_type == "TEXTURE" else rot[2]


def _z_only_mapping(m):
    """Whether `m` is a Mapping node of Generated coordinates (a world's directions) whose only
    effect on an equirectangular lookup is a turn (_mapping_z warns about X and Y)."""
    if m.type != "MAPPING" or m.vector_type not in {"POINT", "VECTOR", "TEXTURE"}:
        return False
    if any(m.inputs[k].is_linked for k in ("Rotation", "Scale", "Location")):
        return False
    fed = m.inputs["Vector"].links[0].from_socket if m.inputs["Vector"].is_linked else None
    if fed is None or fed.node.type != "TEX_COORD" or fed.name != "Generated":
        return False
    scale = m.inputs["Scale"].default_value
    location = m.inputs["Location"].default_value if m.vector_type != "VECTOR" else (0, 0, 0)
    return max(map(abs, location)) < 1e-6 and \
        scale[0] > 0 and abs(scale[1] - scale[0]) < 1e-6 and abs(scale[2] - scale[0]) < 1e-6


def scene_data(depsgraph, stem, frame, should_stop=lambda: False, export=True, folder=None,
               meshes=None):
    """The scene as scene_toml.write takes it (the meshes exported to stem.glb unless `export`
    is False: the viewport exports later, outside its update) and warnings. Images anamorph
    reads from files (a packed or generated HDRI) are written into `folder` (default: stem's).

    A render reads the add-on's properties from its depsgraph's copies, which hold their
    animated values. The viewport (export False) reads them from the original data: its
    depsgraph's copies kept the values they had when the viewport began (seen: a preset and a
    coin's strength set afterwards did not reach them), and Blender writes the current frame's
    animated values into the originals anyway. `meshes`, when given, replaces the export: it
    returns the mesh files with their transforms (scene_toml.write's mesh_objects)."""
    src = (lambda x: x) if export else (lambda x: x.original)
    scene = depsgraph.scene_eval
    if scene.camera is None:
        raise ValueError(f"scene '{scene.name}' has no camera")
    r = scene.render
    width = max(1, r.resolution_x * r.resolution_percentage // 100)
    height = max(1, r.resolution_y * r.resolution_percentage // 100)
    warnings = []
    data = {
        "image": {"width": width, "height": height},
        "render": {"integrator": "path", **set_values(src(scene).anamorph, "render")},
        "camera": _camera_table(scene.camera, width, height, src),
        "coins": _coins(depsgraph, scene.camera, src),
        "environment": _environment(scene.world, warnings, folder or os.path.dirname(stem)),
        "mesh_objects": meshes() if meshes is not None else None,
        "mesh_file": None if meshes is not None else os.path.basename(stem + ".glb")
        if export and main_thread_call(
            lambda: _export_glb(stem + ".glb", scene.original.name, frame,
                                scene.frame_subframe), should_stop) else None,
        "lights": _lights(depsgraph, warnings),
    }
    return data, warnings


def write_toml(data, path):
    am = locate.import_anamorph()
    with open(path, "w", encoding="utf-8") as f:
        f.write(scene_toml.write(data, scene_toml.Formatter(am)))
    return path


# The final render's mesh_files state (the last export's digests and files, reused by the next
# frame or render as far as its meshes export the same); and the frames that exported, one entry
# per export (for scripts and tests).
_last_export = {}
render_exports = []


def build_scene(depsgraph, folder, frame, should_stop=lambda: False, glb_folder=None,
                motion=False):
    """Writes frame_NNNN.toml into `folder` and the meshes' .glb files into `glb_folder`
    (default `folder`; another one is the add-on's own, where files no longer named are
    removed); returns (toml path, warnings).

    The meshes are exported again only as far as what the export holds changed since the last
    frame (mesh_fingerprint). Nothing changed: the frame names the last files. Only placements
    of objects changed (a transform-only frame): each object that moved is exported alone, once
    (frame_NNNN_K.glb, at its placement then), the others again together without them; from then
    on, the frame names those files, each moved object's file with its `transform` from where
    it was exported to where it is now. Anything else: one export of everything
    (frame_NNNN.glb). With `motion` (the Vector and flow passes) the file also holds the
    camera, coins and objects at frames -1 and +1 of its own (Blender's frame - 1 and + 1) as
    [[animate]] keys (motion_keys); objects that move then are exported apart."""
    stem = os.path.join(folder, "frame_%04d" % frame)
    prune = glb_folder is not None
    glb_folder = os.path.normpath(os.path.abspath(glb_folder or folder))
    scene = depsgraph.scene_eval
    near = main_thread_call(lambda: _near_frames(
        scene.original.name, depsgraph.view_layer.name, frame, scene.frame_subframe),
        should_stop) if motion else None

    def export(path, only=None, skip=None):
        done = main_thread_call(lambda: _export_glb(
            path, scene.original.name, frame, scene.frame_subframe, only=only, skip=skip),
            should_stop)
        del render_exports[:-100]
        render_exports.extend([frame] if done else [])
        return done

    def meshes():
        moving = {n for n, m in near[0]["objects"].items()
                  if any(near[d]["objects"].get(n) != m for d in (-1, 1))} if near else ()
        return mesh_files(_last_export, depsgraph, glb_folder, folder, "frame_%04d" % frame,
                          export, prune, moving)

    data, warnings = scene_data(depsgraph, stem, frame, should_stop, meshes=meshes)
    if near:
        data["animate"] = motion_keys(data, near)
    return write_toml(data, stem + ".toml"), warnings


def _near_frames(scene_name, layer_name, frame, subframe):
    """For the Vector and flow passes: {d: {camera, coins, objects: {name: world matrix rows}}}
    at Blender's frame + d for d = -1, 1 and 0 (the scene set to each, the last to `frame`)."""
    scene = bpy.data.scenes[scene_name]
    out = {}
    for d in (-1, 1, 0):
        scene.frame_set(frame + d, subframe=subframe)
        dg = scene.view_layers[layer_name].depsgraph
        r = dg.scene_eval.render
        width = max(1, r.resolution_x * r.resolution_percentage // 100)
        height = max(1, r.resolution_y * r.resolution_percentage // 100)
        cam = dg.scene_eval.camera
        out[d] = {"camera": _camera_table(cam, width, height), "coins": _coins(dg, cam),
                  "objects": {i.object.name: tuple(tuple(r) for r in i.matrix_world)
                              for i in dg.object_instances if not i.is_instance
                              and i.object.type in _EXPORTED_TYPES}}
    return out


def motion_keys(data, near):
    """[[animate]] tables putting the camera, the coins and the objects apart of `data` (the
    scene at frame 0 of its file) where they are at Blender's frame - 1 and + 1 (`near`,
    _near_frames): keys at frames -1, 0, 1 for every numeric key that changes."""
    out = []

    def add(key, values):
        if values[-1] != values[0] or values[1] != values[0]:
            out.append({"key": key, "keys": [[d, values[d]] for d in (-1, 0, 1)]})

    def numeric(v):
        return isinstance(v, (int, float)) and not isinstance(v, bool) or isinstance(
            v, list) and all(isinstance(x, (int, float)) for x in v)

    cams = {d: near[d]["camera"] for d in (-1, 1)}
    cams[0] = data["camera"]
    for k, v in data["camera"].items():
        if numeric(v) and all(k in cams[d] for d in (-1, 1)):
            add("camera.transform.matrix" if k == "matrix" else "camera." + k,
                {d: cams[d][k] for d in (-1, 0, 1)})
    if all(len(near[d]["coins"]) == len(data["coins"]) for d in (-1, 1)):
        for i, coin in enumerate(data["coins"]):
            for k, v in coin.items():
                if numeric(v) and all(k in near[d]["coins"][i] for d in (-1, 1)):
                    add("camera.coin.%d.%s" % (i, k),
                        {d: near[d]["coins"][i][k] if d else v for d in (-1, 0, 1)})
    for i, (_, matrix, name) in enumerate(data["mesh_objects"] or ()):
        if name is not None and all(name in near[d]["objects"] for d in (-1, 0, 1)):
            add("object.%d.transform.matrix" % i, {d: _moved_by(
                near[d]["objects"][name], near[0]["objects"][name], matrix) if d else matrix
                for d in (-1, 0, 1)})
    return out


def mesh_files(last, depsgraph, glb_folder, folder, stem, export, prune, apart=()):
    """The .glb files holding the meshes of `depsgraph`, with the transform of each (None, or
    the `transform.matrix` taking an object from where it was exported to where it is now) and
    the object a file holds alone (or None): [(path relative to `folder`, matrix, name)].
    Exports (`export(path, only, skip)`: True when it wrote meshes) only what changed since
    `last` (this state, updated; build_scene says how) into `glb_folder` as STEM.glb and
    STEM_K.glb; the objects named in `apart` are exported alone (the Vector pass moves them).
    `prune` removes the .glb files there named neither now nor the time before."""
    digest, objects = mesh_fingerprint(depsgraph)
    apart = set(apart) & set(objects)
    if not (last.get("digest") == digest and last["names"] == set(objects)
            and all(os.path.dirname(f[0]) == glb_folder and os.path.isfile(f[0])
                    for f in last["files"])):
        last.clear()
        last.update(digest=digest, names=set(objects), static=dict(objects), files=[])
        if not apart:
            path = os.path.join(glb_folder, stem + ".glb")
            last["files"] = [(path, None, None, None)] if export(path, None, None) else []
    if last["files"] or apart:
        _split(last, objects, apart, export, os.path.join(glb_folder, stem))
    if prune:  # (the files named before too: a viewport's thread may just be loading them)
        now = {f[0] for f in last["files"]}
        keep, last["named"] = now | last.get("named", set()), now
        for name in os.listdir(glb_folder):
            if name.endswith(".glb") and os.path.join(glb_folder, name) not in keep:
                os.remove(os.path.join(glb_folder, name))
    return [(os.path.relpath(path, folder), None if name is None else
             _moved_by(objects[name][0], at_export), name)
            for path, name, at_export, _ in last["files"]]


def _split(last, objects, apart, export, stem):
    """mesh_files' exports when the digest is the last one's: objects exported with the rest
    that moved or changed (or are `apart`) go apart from now on; objects apart whose mesh
    changed are exported again (alone); those that only moved keep their file (transforms)."""
    changed = sorted(n for n, o in last["static"].items() if objects[n] != o or n in apart)
    redo = {f[1] for f in last["files"] if f[1] is not None and objects[f[1]][1] != f[3]}
    if not (changed or redo):
        return
    rest = {n: o for n, o in last["static"].items() if n not in changed}
    files = [f for f in last["files"] if f[1] is not None and f[1] not in redo]
    if not changed:
        files = [f for f in last["files"] if f[1] is None] + files
    elif export(stem + ".glb", None, set(objects) - set(rest)):
        files.insert(0, (stem + ".glb", None, None, None))
    for k, name in enumerate(changed + sorted(redo)):
        path = "%s_%d.glb" % (stem, k + 1)
        if export(path, {name}, None):
            files.append((path, name) + objects[name])
    last.update(static=rest, files=files)


def _moved_by(now, then, after=None):
    """The `transform.matrix` (16 numbers, row-major, anamorph's axes) that takes an object
    exported at Blender's world matrix `then` to `now` (rows): C now then^-1 C^-1, C the glTF
    axes (scene_toml.GLTF_FROM_BLENDER), in double precision; times `after` (such a matrix)."""
    c = np.eye(4)
    c[:3, :3] = scene_toml.GLTF_FROM_BLENDER
    m = c @ np.array(now, dtype=np.float64) @ np.linalg.inv(np.array(then, dtype=np.float64)) \
        @ c.T
    if after is not None:
        m = m @ np.array(after, dtype=np.float64).reshape(4, 4)
    return [float(v) for v in m.ravel()]


_EXPORTED_TYPES = {"MESH", "CURVE", "SURFACE", "META", "FONT"}


def mesh_fingerprint(depsgraph):
    """A digest of everything the glTF export of the render's meshes holds: each renderable
    instance's name, placement and evaluated mesh (vertices, faces, smoothing, UVs, colour
    attributes, material slots) and its materials' settings and node trees. Equal digests:
    the export would be the same file, so an animation frame where only the camera, coins,
    lights, empties or the world move reuses the last one. Image sequences and movies on a
    material change with the frame: they add the frame. Returns (the digest, {name: (world
    matrix rows, digest of its mesh and material slots)} of the objects that can be exported
    alone (no instances in the scene, no parent or children): their placements and meshes are
    not in the digest (mesh_files compares them), every other one's are."""
    h = hashlib.sha1()
    materials, matrices = {}, {}
    alone = not any(inst.is_instance for inst in depsgraph.object_instances)
    for inst in depsgraph.object_instances:
        ob = inst.object
        if ob.type not in _EXPORTED_TYPES:
            continue
        rows = tuple(tuple(r) for r in inst.matrix_world)
        single = alone and ob.parent is None and not ob.children
        h.update(repr((ob.name, inst.is_instance, None if single else rows)).encode())
        own = hashlib.sha1() if single else h
        _hash_mesh(own, ob)
        for slot in ob.material_slots:
            own.update(repr((slot.link, slot.name)).encode())
            if slot.material is not None:
                materials[slot.material.name] = slot.material
        if single:
            matrices[ob.name] = (rows, own.hexdigest())
    for name in sorted(materials):
        _hash_rna(h, materials[name], depth=0)
        tree = materials[name].node_tree
        if tree is not None and _hash_tree(h, tree):
            h.update(repr(depsgraph.scene_eval.frame_current).encode())
    return h.hexdigest(), matrices


def _hash_mesh(h, ob):
    mesh = ob.data if ob.type == "MESH" else None
    owned = mesh is None
    if owned:
        try:
            mesh = ob.to_mesh()
        except RuntimeError:
            return
    try:
        if mesh is None:
            return
        for seq, attr, width, dtype in (
                (mesh.vertices, "co", 3, np.float32), (mesh.loops, "vertex_index", 1, np.int32),
                (mesh.polygons, "loop_start", 1, np.int32),
                (mesh.polygons, "material_index", 1, np.int32),
                (mesh.polygons, "use_smooth", 1, bool), (mesh.edges, "use_edge_sharp", 1, bool)):
            a = np.empty(len(seq) * width, dtype=dtype)
            seq.foreach_get(attr, a)
            h.update(a.tobytes())
        for layer in mesh.uv_layers:
            a = np.empty(len(layer.data) * 2, dtype=np.float32)
            layer.data.foreach_get("uv", a)
            h.update(layer.name.encode() + a.tobytes())
        for attr in mesh.attributes:
            if attr.data_type in {"FLOAT_COLOR", "BYTE_COLOR"}:
                a = np.empty(len(attr.data) * 4, dtype=np.float32)
                attr.data.foreach_get("color", a)
                h.update(attr.name.encode() + a.tobytes())
        h.update(repr((mesh.use_auto_smooth, mesh.auto_smooth_angle,
                       mesh.has_custom_normals)).encode())
        if mesh.has_custom_normals:
            mesh.calc_normals_split()
            a = np.empty(len(mesh.loops) * 3, dtype=np.float32)
            mesh.loops.foreach_get("normal", a)
            h.update(a.tobytes())
    finally:
        if owned:
            ob.to_mesh_clear()


_SIMPLE = {"BOOLEAN", "INT", "FLOAT", "STRING", "ENUM"}


def _hash_rna(h, struct, depth):
    """Every plain property of `struct` (and an image's file and state)."""
    for p in struct.bl_rna.properties:
        if p.type in _SIMPLE and p.identifier != "rna_type":
            v = getattr(struct, p.identifier, None)
            h.update(repr((p.identifier, tuple(v) if hasattr(v, "__len__") and not
                           isinstance(v, str) else v)).encode())
        elif p.type == "POINTER" and depth == 0 and p.identifier != "rna_type":
            v = getattr(struct, p.identifier, None)
            if isinstance(v, bpy.types.Image):
                h.update(repr((v.name, v.filepath, v.source, v.is_dirty,
                               v.packed_file is not None)).encode())


def _hash_tree(h, tree):
    """A node tree's nodes, their inputs and links; True when it shows an image sequence or a
    movie (which change with the frame)."""
    moving = False
    for node in sorted(tree.nodes, key=lambda n: n.name):
        h.update(repr((node.name, node.bl_idname)).encode())
        _hash_rna(h, node, depth=0)
        for sock in node.inputs:
            v = getattr(sock, "default_value", None)
            h.update(repr((sock.identifier, tuple(v) if hasattr(v, "__len__") and not
                           isinstance(v, str) else v)).encode())
        image = getattr(node, "image", None)
        moving |= image is not None and image.source in {"SEQUENCE", "MOVIE"}
        if getattr(node, "node_tree", None) is not None:  # a group
            moving |= _hash_tree(h, node.node_tree)
    for link in tree.links:
        h.update(repr((link.from_node.name, link.from_socket.identifier, link.to_node.name,
                       link.to_socket.identifier, link.is_muted)).encode())
    return moving


# ---------------------------------------------------------------------------------------------
# The render engine


def _prefs_path():
    addon = bpy.context.preferences.addons.get(ADDON)
    return addon.preferences.module_path if addon else ""


# anamorph's flow layers (docs/vision.md: x right, y down, pixels; and the fraction of the
# pixel's hits that have a flow) as the passes of the view layer's Flow toggle.
FLOW_PASSES = {"flow_forward": "Flow Forward", "flow_backward": "Flow Backward"}


class AnamorphRenderEngine(bpy.types.RenderEngine):
    bl_idname = "ANAMORPH"
    bl_label = "anamorph"
    bl_use_preview = False
    bl_use_postprocess = True

    def update_render_passes(self, scene=None, renderlayer=None):
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", "COLOR")
        if renderlayer.use_pass_z:
            self.register_pass(scene, renderlayer, "Depth", 1, "Z", "VALUE")
        if renderlayer.use_pass_normal:
            self.register_pass(scene, renderlayer, "Normal", 3, "XYZ", "VECTOR")
        if renderlayer.use_pass_object_index:
            self.register_pass(scene, renderlayer, "IndexOB", 1, "X", "VALUE")
        if getattr(renderlayer, "anamorph_albedo", False):
            self.register_pass(scene, renderlayer, "Albedo", 3, "RGB", "COLOR")
        if renderlayer.use_pass_vector:
            self.register_pass(scene, renderlayer, "Vector", 4, "XYZW", "VECTOR")
        if getattr(renderlayer, "anamorph_flow", False):
            for name in FLOW_PASSES.values():
                self.register_pass(scene, renderlayer, name, 3, "XYZ", "VECTOR")

    def render(self, depsgraph):
        global last_error
        last_error = ""
        try:
            self._render(depsgraph)
        except Cancelled:
            self.report({"INFO"}, "anamorph: render cancelled")
        except Exception as e:  # every failure becomes a Blender report, never a crash
            last_error = str(e)
            self.report({"ERROR"}, last_error)
            if not isinstance(e, (ValueError, OSError, locate.NotFound)):
                traceback.print_exc()

    def _render(self, depsgraph):
        am = locate.import_anamorph(_prefs_path())
        scene = depsgraph.scene_eval
        keep = bpy.path.abspath(scene.anamorph.keep_folder) if scene.anamorph.keep_folder else ""
        folder = keep or tempfile.mkdtemp(prefix="anamorph-blender-")
        os.makedirs(folder, exist_ok=True)
        try:
            self.update_stats("anamorph", "exporting the scene")
            layer = depsgraph.view_layer_eval
            path, warnings = build_scene(
                depsgraph, folder, scene.frame_current, lambda: break_requested(self),
                None if keep else _glb_cache(),
                motion=layer.use_pass_vector or getattr(layer, "anamorph_flow", False))
            for w in warnings:
                self.report({"WARNING"}, "anamorph: " + w)
            self.update_stats("anamorph", "loading")
            loaded = am.load(path)
            self._render_loaded(loaded, depsgraph)
        finally:
            if not keep:
                shutil.rmtree(folder, ignore_errors=True)

    def _render_loaded(self, loaded, depsgraph):
        view_layer = depsgraph.view_layer_eval
        aovs = [a for a, on in (("depth", view_layer.use_pass_z),
                                ("normal", view_layer.use_pass_normal),
                                ("albedo", getattr(view_layer, "anamorph_albedo", False)),
                                ("id", view_layer.use_pass_object_index),
                                ("motion", view_layer.use_pass_vector)) if on]
        if getattr(view_layer, "anamorph_flow", False):
            aovs += list(FLOW_PASSES)
        start = time.monotonic()

        def progress(p):
            if break_requested(self):
                raise Cancelled()
            self.update_progress(p["fraction"])
            self.update_stats("anamorph", "pass %d/%d, %.1f s" % (
                p["pass"], p["passes"], time.monotonic() - start))

        img = loaded.render(aovs=aovs, progress=progress)
        if "id" in img:
            img["id"] = _pass_indices(img["id"], loaded.info()["objects"], depsgraph)
        self._write_result(img, view_layer)

    def _write_result(self, img, view_layer):
        rgba = img["rgba"]
        height, width = rgba.shape[:2]
        result = self.begin_result(0, 0, width, height, layer=view_layer.name)
        layer = result.layers[0]
        # Blender's rows go bottom to top and its colours are premultiplied.
        out = np.flipud(rgba).reshape(-1, 4).copy()
        out[:, :3] *= out[:, 3:4]
        layer.passes["Combined"].rect = out
        if "depth" in img:
            depth = np.flipud(img["depth"]).reshape(-1, 1).copy()
            depth[~np.isfinite(depth)] = 1e10  # Cycles' value where the world is seen
            layer.passes["Depth"].rect = depth
        if "normal" in img:
            n = np.flipud(img["normal"]).reshape(-1, 3)
            # anamorph's world is glTF's (+Y up): back to Blender's axes.
            layer.passes["Normal"].rect = np.stack([n[:, 0], -n[:, 2], n[:, 1]], axis=1)
        if "albedo" in img:
            layer.passes["Albedo"].rect = np.flipud(img["albedo"]).reshape(-1, 3)
        if "id" in img:
            layer.passes["IndexOB"].rect = np.flipud(img["id"]).reshape(-1, 1)
        if "motion" in img:  # Cycles' convention already (docs/vision.md), y up
            layer.passes["Vector"].rect = np.flipud(img["motion"]).reshape(-1, 4)
        for aov, name in FLOW_PASSES.items():
            if aov in img:  # no flow (NaN): 0, its valid fraction 0
                layer.passes[name].rect = np.nan_to_num(np.flipud(img[aov]).reshape(-1, 3))
        self.end_result(result)

    # The viewport (Rendered shading).

    def _preview(self):
        if getattr(self, "_anamorph_preview", None) is None:
            self._anamorph_preview = _Preview()
        return self._anamorph_preview

    def __del__(self):
        try:
            preview = getattr(self, "_anamorph_preview", None)
        except ReferenceError:  # Blender freed the engine first (seen after each F12 render)
            return
        if preview is not None:
            preview.close()

    def view_update(self, context, depsgraph):
        """The scene changed. Camera, coins, lights, world and settings are read again at once
        and the preview restarts here (not at the next draw: under Xvfb's software OpenGL a
        window's frame took 0.5 s, bench/blender/run); the meshes are exported again only when
        geometry, shading or a mesh's placement changed: by _export_after_update, which Blender
        runs just before this (an operator cannot run inside view_update: the exporter's view
        layer update would wait for it forever), or, for the first export, on the add-on's
        timer; either restarts the preview with the view last drawn."""
        preview = self._preview()
        try:
            data, _ = scene_data(depsgraph, "", 0, export=False, folder=preview.folder)
        except Exception as e:
            preview.data = preview.latest = None
            self.report({"ERROR"}, str(e))
            return
        data["mesh_objects"] = (preview.latest or {}).get("mesh_objects")
        preview.latest = data
        preview.scene_name = depsgraph.scene_eval.original.name
        preview.engine = self
        # Exported by _export_after_update (which restarts the preview) for this update, or
        # being exported there (the exporter's own update calls this again meanwhile).
        handled = _exporting or preview.exported_now
        preview.exported_now = preview.exported_now and bool(_exporting)
        if preview.exports and (handled or not _meshes_changed(depsgraph)):
            if data != preview.data:
                preview.data, preview.key = data, None
                self._restart_last_view(preview, data)
                self.tag_redraw()
            return
        preview.exports += 1
        token, scene_name = preview.exports, preview.scene_name

        def export():
            if token != preview.exports:  # a newer update superseded this one
                return
            latest = dict(preview.latest)
            latest["mesh_objects"] = preview.mesh_objects(
                bpy.context.evaluated_depsgraph_get(), scene_name)
            preview.data = preview.latest = latest
            preview.key = None
            self._restart_last_view(preview, latest)
            self.tag_redraw()

        _main_queue.put((export, {}, threading.Event()))

    def _view(self, context, scene, data):
        """(frame in region pixels, width, height, scene data as rendered) of the viewport's
        view of `data`: the anamorph camera in the camera view, drawn into the camera frame at
        its size (at most 1280 wide), else a perspective or orthographic camera of the view.
        None when the camera frame is not on screen."""
        region, rv3d = context.region, context.region_data
        if rv3d.view_perspective == "CAMERA" and scene.camera is not None:
            frame = _camera_frame(context, scene)
            if frame is None:
                return None
            aspect = data["image"]["width"] / data["image"]["height"]
            width = max(1, min(int(frame[2]), 1280))
            return frame, width, max(1, int(round(width / aspect))), data
        frame = (0, 0, region.width, region.height)
        return frame, region.width, region.height, dict(
            data, camera=_view_camera(region, rv3d), coins=[])

    def _restart_last_view(self, preview, data):
        """Restarts the preview on new scene data with the view last drawn (its size and, out
        of the camera view, its camera): view_update's region matrices still hold the old
        camera (seen: the frame measured there differed, restarting it twice)."""
        if preview.view is not None:
            width, height, camera = preview.view
            self._restart(preview, (None, width, height, data if camera is None else
                                    dict(data, camera=camera, coins=[])))

    def _restart(self, preview, view):
        """Starts the preview of `view` (_view's answer) unless it shows that already."""
        if view is None:
            return
        _, width, height, data = view
        camera = data["camera"]
        key = (width, height, tuple(camera["matrix"]), tuple(sorted(
            (k, str(v)) for k, v in camera.items() if k != "matrix")))
        if key != preview.key:
            preview.key = key
            preview.view = (width, height, camera if data is not preview.data else None)
            preview.start(self, data, width, height)

    def view_draw(self, context, depsgraph):
        preview = self._preview()
        if preview.data is None:
            return
        scene = depsgraph.scene_eval
        view = self._view(context, scene, preview.data)
        if view is None:
            return
        self._restart(preview, view)
        preview.wait_first_image()
        self._draw_image(preview, scene, view[0])

    def _draw_image(self, preview, scene, frame):
        """Draws the preview's newest image into `frame`. Its pixels were made ready for the
        texture on the preview's thread (_texture_pixels) and its texture is made once, at its
        first draw: Blender draws the viewport again for every redraw of the window."""
        import gpu
        from gpu_extras.presets import draw_texture_2d

        t0 = time.monotonic()
        with preview.lock:
            pixels, log = preview.pixels, preview.image_log
        if pixels is None:
            return
        if preview.texture is None or preview.texture[0] is not pixels:
            h, w = pixels.shape[:2]
            preview.texture = (pixels, gpu.types.GPUTexture((w, h), format="RGBA16F", data=(
                gpu.types.Buffer("FLOAT", pixels.shape, pixels))))
        gpu.state.blend_set("ALPHA_PREMULT")
        self.bind_display_space_shader(scene)
        draw_texture_2d(preview.texture[1], (frame[0], frame[1]), frame[2], frame[3])
        self.unbind_display_space_shader()
        gpu.state.blend_set("NONE")
        if log.get("first_drawn") is None:
            log["first_drawn"] = time.monotonic()
            log["first_draw_ms"] = 1e3 * (log["first_drawn"] - t0)


def _texture_pixels(img):
    """An image's pixels as the viewport's texture takes them (rows from the bottom,
    premultiplied, as Blender draws): made on the preview's thread, not in view_draw, which
    runs on Blender's main thread (20 ms for a 908 x 511 image)."""
    rgba = np.flipud(img).copy()
    rgba[..., :3] *= rgba[..., 3:4]
    return rgba


_glb_cache_folder = []


def _glb_cache():
    """The add-on's folder for the final render's last .glb when no scene folder is kept (a
    frame's own folder is removed after it): removed when the add-on is disabled."""
    if not _glb_cache_folder or not os.path.isdir(_glb_cache_folder[0]):
        _glb_cache_folder[:] = [tempfile.mkdtemp(prefix="anamorph-blender-meshes-")]
    return _glb_cache_folder[0]


def _pass_indices(ids, names, depsgraph):
    """The IndexOB pass of anamorph's `id` layer (H, W, 1): each pixel's object id becomes the
    Pass Index of the Blender object it came from (the exported glTF node carries the object's
    name; `names` are the scene's objects by id), 0 where nothing is hit, as Cycles."""
    index = {ob.name: ob.pass_index for ob in depsgraph.objects}
    prefix = scene_toml.MESH_OBJECT + "/"

    def pass_index(name):
        name = name[len(prefix):] if name.startswith(prefix) else name
        ob = bpy.data.objects.get(name)  # an instanced object's own (not in depsgraph.objects)
        return float(index.get(name, ob.pass_index if ob is not None else 0))

    table = np.array([0.0] + [pass_index(n) for n in names], dtype=np.float32)
    ids = np.asarray(ids)
    return table[np.where(ids >= 0, ids + 1, 0).astype(np.int64)]


# ---------------------------------------------------------------------------------------------
# The viewport: Rendered shading, progressive


# What the viewport renders after each restart: (fraction of the size, samples per pixel).
VIEWPORT_PASSES = ((0.25, 1), (1.0, 1), (1.0, 4), (1.0, 16), (1.0, 64))
# How long the first view_draw after a restart waits for the restarted preview's first image
# [s] (_Preview.wait_first_image): 0 draws the last image at once.
FIRST_IMAGE_WAIT = 0.1
# The last viewport restarts, for scripts and tests: [{started, first_image, first_drawn,
# passes}] (seconds of time.monotonic(); first_drawn: when view_draw first drew one of its
# images), newest last; and the times of the viewport's exports.
viewport_log = []
viewport_exports = []


# The open viewports' previews (for _export_after_update).
_live_previews = weakref.WeakSet()
_exporting = []


@bpy.app.handlers.persistent
def _export_after_update(scene, depsgraph):
    """Exports the meshes of each open preview of `scene` when this depsgraph update changed
    them, right after the update and before the engine's view_update (which then restarts the
    preview with the file): not through the add-on's timer, which Blender runs only after it
    has drawn the window (0.2-0.7 s under Xvfb, bench/blender/run). Blender runs these handlers
    after evaluating the depsgraph and before telling the editors, and evaluates once more when
    a handler changed something; an operator inside view_update itself deadlocked (seen)."""
    previews = [p for p in list(_live_previews) if p.exports and p.scene_name == scene.name
                and p.latest is not None and p.engine is not None]
    if not previews or _exporting or not _meshes_changed(depsgraph):
        return
    _exporting.append(True)
    try:
        for p in previews:
            p.exports += 1
            p.latest = dict(p.latest, mesh_objects=p.mesh_objects(depsgraph, scene.name))
            p.exported_now = True
            if p.latest == p.data:  # nothing the preview shows changed (e.g. a selection)
                continue
            p.data, p.key = p.latest, None
            try:
                p.engine._restart_last_view(p, p.data)
                p.engine.tag_redraw()
            except ReferenceError:  # the engine was freed (the viewport closed)
                pass
    finally:
        _exporting.clear()


class _Preview:
    """One viewport's progressive preview: a thread renders VIEWPORT_PASSES of a scene file,
    the newest image is drawn; a restart cancels the thread at its next progress report."""

    def __init__(self):
        self.folder = tempfile.mkdtemp(prefix="anamorph-viewport-")
        self.data = None  # scene_data of the last view_update
        self.key = None  # the view the running preview shows
        self.image = None  # (H, W, 4) float32, rows from the top, straight alpha
        self.pixels = None  # the image as the texture takes it (_texture_pixels)
        self.texture = None  # (pixels, its GPUTexture): made by view_draw at the first draw
        self.image_log = None  # the viewport_log entry of the preview that rendered it
        self.lock = threading.Lock()
        self.cancel = threading.Event()
        self.first_image = None  # set by its first image: the restart view_draw waits for
        self.threads = []  # the running preview's thread last, cancelled ones before it
        self.count = 0
        self.exports = 0
        self.latest = None  # the newest scene_data, its mesh_objects the last export's
        self.view = None  # (width, height, camera or None: data's own) of the running preview
        self.scene_name = None  # the scene it shows
        self.meshes = {}  # mesh_files' state
        self.glbs = 0
        # Whether _export_after_update exported for the view_update that follows it.
        self.exported_now = False
        self.engine = None  # the engine of the last view_update
        # Loaded scenes: [_scene_key, anamorph Scene, rendering now, scene file], for
        # view-only restarts (_loaded).
        self.scenes = []
        _live_previews.add(self)

    def mesh_objects(self, depsgraph, scene_name):
        """The meshes' files (mesh_files) for `depsgraph`, exported as far as they changed:
        a moved object is exported alone once, then placed by a transform."""
        def export(path, only, skip):
            done = _export_glb(path, scene_name, 0, 0.0, set_frame=False, only=only, skip=skip)
            del viewport_exports[:-20]
            viewport_exports.extend([time.monotonic()] if done else [])
            return done

        self.glbs += 1
        return mesh_files(self.meshes, depsgraph, self.folder, self.folder,
                          "view_glb_%d" % self.glbs, export, True)

    def wait_first_image(self):
        """Waits, once per restart and at most FIRST_IMAGE_WAIT, for the restarted preview's
        first image, so that the window's frame being drawn shows it: Blender drew the window
        right after the edit with the last image, and the new one, ready meanwhile, waited for
        the next frame (under Xvfb's software OpenGL 25 ms per frame at a load of 3-6 and
        130-160 ms at 8-10, bench/blender/run)."""
        first, self.first_image = self.first_image, None
        if first is not None:
            first.wait(FIRST_IMAGE_WAIT)

    def stop(self):
        """Cancels the running preview and waits for its thread (before its files go)."""
        self.cancel.set()
        for thread in self.threads:
            thread.join()
        self.threads = []

    def start(self, engine, data, width, height):
        """Renders `data` at width x height in a new thread. The running one is cancelled, not
        waited for: it stops at its next progress report (every 50 ms), meanwhile rendering
        beside the new one (waiting for it took up to 60 ms of an edit's first image). When
        only the view changed (camera, coins, image, render settings) a scene loaded before
        and not rendering is rendered again with the new view (Scene.render's set: the meshes
        are neither read nor their acceleration structure built again); else the scene file is
        written and loaded."""
        self.cancel.set()
        self.count += 1
        key = _scene_key(data)
        with self.lock:
            entry = next((e for e in self.scenes if e[0] == key and not e[2]), None)
            if entry is not None:
                entry[2] = True
        path = None if entry is not None else write_toml(
            dict(data, image={"width": width, "height": height}),
            os.path.join(self.folder, "view_%d.toml" % self.count))
        log = {"started": time.monotonic(), "first_image": None, "passes": 0,
               "reused": entry is not None}
        del viewport_log[:-20]
        viewport_log.append(log)
        self.cancel = threading.Event()
        self.first_image = threading.Event()
        self.threads = [t for t in self.threads if t.is_alive()]
        self.threads.append(threading.Thread(target=self._run, daemon=True, args=(
            engine, path or entry, view_set(data, width, height), width, height, self.cancel,
            log, key, self.first_image)))
        self.threads[-1].start()

    def _loaded(self, source, key):
        """The pool entry [key, Scene, busy, its file] to render: `source` itself, or a new one
        loaded from the scene file `source` (the pool keeps two idle ones of the newest key;
        a view is read from the file again, so the file stays while its entry does)."""
        if not isinstance(source, str):
            return source
        entry = [key, locate.import_anamorph().load(source), True, source]
        with self.lock:
            keep = [e for e in self.scenes if e[0] == key and not e[2]][-1:]
            gone = [e for e in self.scenes if not e[2] and e not in keep]
            self.scenes = [e for e in self.scenes if e[2]] + keep + [entry]
        for e in gone:
            try:
                os.remove(e[3])
            except OSError:
                pass
        return entry

    def _run(self, engine, source, view, width, height, cancel, log, key, first):
        def progress(p):
            if cancel.is_set():
                raise Cancelled()

        entry = None
        try:
            entry = self._loaded(source, key)
            for fraction, spp in VIEWPORT_PASSES:
                img = entry[1].render(width=max(1, int(width * fraction)),
                                      height=max(1, int(height * fraction)), spp=spp,
                                      progress=progress, set=view)["rgba"]
                pixels = _texture_pixels(img)
                with self.lock:
                    if cancel.is_set():  # a newer preview started: its images only
                        break
                    self.image, self.pixels, self.image_log = img, pixels, log
                log["passes"] += 1
                log["first_image"] = log["first_image"] or time.monotonic()
                first.set()
                _redraw(engine)
        except Cancelled:
            pass
        except Exception as e:  # shown in the status of the next draw
            log["error"] = str(e)
            _redraw(engine)
        finally:
            first.set()
            if entry is not None:
                entry[2] = False

    def close(self):
        _live_previews.discard(self)
        self.engine = None
        self.stop()
        self.scenes = []
        shutil.rmtree(self.folder, ignore_errors=True)


def _scene_key(data):
    """What a preview's loaded scene holds beyond its view: equal keys, one loaded scene. The
    mesh files' transforms are not in it: a render's set moves those objects (view_set)."""
    key = {k: v for k, v in data.items() if k not in _VIEW_DATA}
    key["mesh_objects"] = [(f[0], f[1] is None) + tuple(f[2:])
                           for f in key.get("mesh_objects") or ()]
    return repr(key)


_VIEW_DATA = ("image", "render", "camera", "coins")


def view_set(data, width, height):
    """Scene.render's `set` giving `data`'s view (camera with its coins, render settings) at
    width x height, and the place of each mesh file placed by a transform (`object.N.transform`:
    the object moves without a load; scene_toml.write writes them as the first [[object]]
    tables): whole tables, so a key no longer set takes its default."""
    camera = {k: _plain(v) for k, v in data["camera"].items() if k != "matrix"}
    camera["transform"] = {"matrix": data["camera"]["matrix"]}
    if data["coins"]:
        camera["coin"] = [{k: _plain(v) for k, v in c.items()} for c in data["coins"]]
    view = {"camera": camera, "image": {"width": width, "height": height},
            "render": {k: _plain(v) for k, v in data["render"].items()}}
    for n, (_, matrix, *_) in enumerate(data.get("mesh_objects") or ()):
        if matrix is not None:
            view["object.%d.transform" % n] = {"matrix": matrix}
    return view


def _plain(v):
    """A value as Python data (TOML text the user typed, scene_toml.Raw, parsed)."""
    if isinstance(v, scene_toml.Raw):
        import tomllib

        return tomllib.loads("v = " + v)["v"]
    return v


def _redraw(engine):
    """Asks Blender to draw the viewport again, from the preview's thread: the engine's
    tag_redraw only sets a flag the window manager's loop looks at (Cycles calls it from its
    session thread too). Through the add-on's timer instead, the image waited 300-500 ms for
    the timer's next call in a window under Xvfb (bench/blender/run)."""
    try:
        engine.tag_redraw()
    except ReferenceError:  # the engine was freed (the viewport closed)
        pass


_MESH_DATA = (bpy.types.Mesh, bpy.types.Material, bpy.types.Image, bpy.types.Curve,
              bpy.types.NodeTree, bpy.types.Collection)


# Data the export leaves out: read again by view_update without exporting. A camera's own
# edit (its fov) comes as an update of its Camera and its Object with is_updated_geometry set
# (seen in Blender 3.4): without this it exported the meshes again (a 50-150 ms export).
_NOT_EXPORTED = (bpy.types.Camera, bpy.types.Light, bpy.types.World, bpy.types.Scene)


def _meshes_changed(depsgraph):
    """Whether an update can change what the glTF export holds."""
    for u in depsgraph.updates:
        if isinstance(u.id, _NOT_EXPORTED):
            continue
        if isinstance(u.id, bpy.types.Object):
            if u.id.type not in {"CAMERA", "EMPTY", "LIGHT"}:
                return True
            continue
        if u.is_updated_geometry or u.is_updated_shading or isinstance(u.id, _MESH_DATA):
            return True
    return False


def _view_camera(region, rv3d):
    """The camera table of the viewport's own view (outside the camera view): perspective or
    orthographic, from Blender's view and projection matrices."""
    p = rv3d.window_matrix
    world_from_view = rv3d.view_matrix.inverted()
    rows = [list(r) for r in world_from_view]
    if rv3d.is_perspective:
        fov = math.degrees(2 * math.atan(1 / p[0][0]))
        table = {"preset": "perspective", "fov": min(179.0, fov), "fov_axis": "horizontal"}
    else:
        table = {"preset": "orthographic", "view_width": 2 / p[0][0]}
    table["matrix"] = scene_toml.rig_matrix(rows)
    return table


def _camera_frame(context, scene):
    """The camera view's frame in region pixels: (x, y, width, height)."""
    from bpy_extras.view3d_utils import location_3d_to_region_2d

    cam = scene.camera
    corners = [cam.matrix_world @ c for c in cam.data.view_frame(scene=scene)]
    pts = [location_3d_to_region_2d(context.region, context.region_data, c) for c in corners]
    if any(p is None for p in pts):
        return None
    xs, ys = [p.x for p in pts], [p.y for p in pts]
    return min(xs), min(ys), max(xs) - min(xs), max(ys) - min(ys)


# ---------------------------------------------------------------------------------------------
# UI


class AnamorphPreferences(bpy.types.AddonPreferences):
    bl_idname = ADDON
    module_path: bpy.props.StringProperty(
        name="anamorph module folder", subtype="DIR_PATH", default="",
        description="A folder holding the anamorph package (e.g. <repo>/build/python); empty: "
        "the one recorded when the add-on was packaged, then an installed module")

    def draw(self, context):
        self.layout.prop(self, "module_path")
        if _load_error:
            for line in _load_error.splitlines():
                self.layout.label(text=line, icon="ERROR")


def _draw_group(layout, group):
    layout.use_property_split = True
    for spec in group.specs:
        layout.prop(group, spec["prop"])


class ANAMORPH_PT_camera(bpy.types.Panel):
    bl_label = "anamorph"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "data"
    COMPAT_ENGINES = {"ANAMORPH"}

    @classmethod
    def poll(cls, context):
        return context.camera is not None and context.engine == "ANAMORPH"

    def draw(self, context):
        layout = self.layout
        if _load_error:
            layout.label(text=_load_error.splitlines()[0], icon="ERROR")
            return
        settings = context.camera.anamorph
        layout.prop(settings, "image_surface")
        if settings.image_surface is None:
            layout.prop(settings, "preset")
        if settings.image_surface is None and settings.preset == "FUNCTIONS":
            for kind in ("org", "dir"):
                layout.prop(settings, kind + "_type")
                _draw_group(layout.column(), getattr(
                    settings, f"{kind}_{getattr(settings, kind + '_type')}"))
        elif settings.image_surface is None and settings.preset != "BLENDER":
            _draw_group(layout.column(), getattr(settings, "p_" + settings.preset))
        _draw_group(layout.column(), settings.common)
        layout.operator(ANAMORPH_OT_add_coin.bl_idname, icon="EMPTY_AXIS")


class ANAMORPH_PT_coin(bpy.types.Panel):
    bl_label = "anamorph coin"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "object"

    @classmethod
    def poll(cls, context):
        ob = context.object
        return (not _load_error and ob is not None and ob.type == "EMPTY"
                and context.engine == "ANAMORPH")

    def draw(self, context):
        coin = context.object.anamorph_coin
        self.layout.prop(coin, "is_coin")
        if coin.is_coin:
            _draw_group(self.layout.column(), coin)


class ANAMORPH_PT_render(bpy.types.Panel):
    bl_label = "anamorph"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"

    @classmethod
    def poll(cls, context):
        return context.engine == "ANAMORPH"

    def draw(self, context):
        if _load_error:
            for line in _load_error.splitlines():
                self.layout.label(text=line, icon="ERROR")
            return
        self.layout.prop(context.scene.anamorph, "keep_folder")
        _draw_group(self.layout.column(), context.scene.anamorph)


class ANAMORPH_PT_passes(bpy.types.Panel):
    """The passes anamorph writes into the render result (View Layer Properties > Passes)."""

    bl_label = "anamorph"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "view_layer"
    bl_parent_id = "VIEWLAYER_PT_layer_passes"

    @classmethod
    def poll(cls, context):
        return context.engine == "ANAMORPH"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        vl = context.view_layer
        col = layout.column()
        col.prop(vl, "use_pass_z", text="Depth (distance)")
        col.prop(vl, "use_pass_normal")
        col.prop(vl, "anamorph_albedo")
        col.prop(vl, "use_pass_object_index")
        col.prop(vl, "use_pass_vector")
        col.prop(vl, "anamorph_flow")


def _passes_changed(view_layer, _context):
    view_layer.update_render_passes()  # the compositor's Render Layers node gets its sockets


class ANAMORPH_OT_add_coin(bpy.types.Operator):
    """Add an empty as a center of interest of this camera (at the camera's view axis, 2 m out)"""

    bl_idname = "anamorph.add_coin"
    bl_label = "Add coin"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        cam_ob = context.object if context.object and context.object.type == "CAMERA" \
            else context.scene.camera
        if cam_ob is None:
            self.report({"ERROR"}, "anamorph: no camera to add a coin to")
            return {"CANCELLED"}
        ob = add_coin(cam_ob, (0.0, 0.0, -2.0))
        self.report({"INFO"}, f"anamorph: coin '{ob.name}' added to '{cam_ob.name}'")
        return {"FINISHED"}


def add_coin(cam_ob, local_position, name="coin"):
    """An empty parented to the camera at `local_position` (camera space), marked as a coin."""
    ob = bpy.data.objects.new(name, None)
    ob.empty_display_type = "SPHERE"
    ob.empty_display_size = 0.1
    for coll in cam_ob.users_collection[:1] or [bpy.context.scene.collection]:
        coll.objects.link(ob)
    ob.parent = cam_ob
    ob.location = local_position
    ob.anamorph_coin.is_coin = True
    return ob


_STATIC = [AnamorphPreferences, AnamorphRenderEngine, ANAMORPH_PT_camera, ANAMORPH_PT_coin,
           ANAMORPH_PT_render, ANAMORPH_PT_passes, ANAMORPH_OT_add_coin]


def _panels_for_engine(add):
    """Lets Blender's own panels that suit any engine (dimensions, output, ...) show."""
    for name in ("RENDER_PT_format", "RENDER_PT_frame_range", "RENDER_PT_output",
                 "RENDER_PT_color_management", "DATA_PT_camera", "DATA_PT_lens",
                 "DATA_PT_camera_display", "DATA_PT_context_camera", "VIEWLAYER_PT_layer_passes",
                 "DATA_PT_light", "DATA_PT_context_light", "DATA_PT_EEVEE_light",
                 "DATA_PT_camera_dof", "DATA_PT_camera_dof_aperture"):
        panel = getattr(bpy.types, name, None)
        if panel is None or not hasattr(panel, "COMPAT_ENGINES"):
            continue
        (panel.COMPAT_ENGINES.add if add else panel.COMPAT_ENGINES.discard)("ANAMORPH")


def register():
    global _load_error
    _load_error = ""
    for cls in _STATIC:
        bpy.utils.register_class(cls)
    _panels_for_engine(True)
    bpy.types.ViewLayer.anamorph_albedo = bpy.props.BoolProperty(
        name="Albedo", default=False, update=_passes_changed,
        description="anamorph's albedo layer as the pass 'Albedo': the base colour of the first "
        "surface hit (mean over the pixel's samples that hit one), 0 where nothing is hit")
    bpy.types.ViewLayer.anamorph_flow = bpy.props.BoolProperty(
        name="Flow", default=False, update=_passes_changed,
        description="anamorph's optical flow to the next and previous frame as the passes "
        "'Flow Forward' and 'Flow Backward': X right, Y down in pixels, Z the fraction of the "
        "pixel's hits whose point is seen in that frame (0 and 0 where none is)")
    if _export_after_update not in bpy.app.handlers.depsgraph_update_post:
        bpy.app.handlers.depsgraph_update_post.append(_export_after_update)
    if not bpy.app.timers.is_registered(_serve_main_queue):
        bpy.app.timers.register(_serve_main_queue, first_interval=0.02, persistent=True)
    try:
        am = locate.import_anamorph(_prefs_path())
        _register_declared(am)
    except (locate.NotFound, ImportError) as e:
        _load_error = str(e)
        print(_load_error)


def unregister():
    if _export_after_update in bpy.app.handlers.depsgraph_update_post:
        bpy.app.handlers.depsgraph_update_post.remove(_export_after_update)
    for folder in _glb_cache_folder:
        shutil.rmtree(folder, ignore_errors=True)
    _glb_cache_folder.clear()
    _last_export.clear()
    if bpy.app.timers.is_registered(_serve_main_queue):
        bpy.app.timers.unregister(_serve_main_queue)
    _panels_for_engine(False)
    for attr, owner in (("anamorph", bpy.types.Camera), ("anamorph_coin", bpy.types.Object),
                        ("anamorph", bpy.types.Scene), ("anamorph_albedo", bpy.types.ViewLayer),
                        ("anamorph_flow", bpy.types.ViewLayer)):
        if hasattr(owner, attr):
            delattr(owner, attr)
    while _classes:
        bpy.utils.unregister_class(_classes.pop())
    for cls in reversed(_STATIC):
        bpy.utils.unregister_class(cls)
