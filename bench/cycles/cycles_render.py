# Renders an anamorph scene TOML of bench/cycles with Blender Cycles, as equal as the two
# renderers allow: same meshes (Blender imports the same OBJ / glTF files), pure Lambertian
# materials with the same albedo, the OBJ's `Ka > 1` light as an emission of the same radiance,
# `sphere` and `box` objects as Blender primitives (a sphere as a smooth 96 x 48 UV sphere),
# the same camera, image size, samples, bounces, box pixel filter, no denoising, no clamping.
#
#   blender -b --factory-startup --python cycles_render.py -- scene.toml out.exr \
#       --spp N --bounces B --threads 2 [--adaptive THRESHOLD --min-spp N] [--time-limit S]
#
# Prints `CYCLES_RENDER_SECONDS <s>` (the bpy.ops.render.render call only: scene sync, BVH
# build and rendering; not Blender's start-up, the imports or writing the EXR).
# Blender 3.4 (Debian 12); Python 3.11 for tomllib.
import argparse
import math
import os
import sys
import time
import tomllib

import bpy
from mathutils import Matrix, Vector


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="cycles_render.py")
    p.add_argument("scene")
    p.add_argument("output")
    p.add_argument("--spp", type=int, default=16)
    p.add_argument("--bounces", type=int, default=None,
                   help="Cycles max bounces (default: the scene's render.max_depth - 1, which "
                        "gives paths with the same number of scattering events)")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--width", type=int)
    p.add_argument("--height", type=int)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--adaptive", type=float, default=None, help="adaptive_threshold (enables it)")
    p.add_argument("--min-spp", type=int, default=0, help="adaptive_min_samples (0: automatic)")
    p.add_argument("--time-limit", type=float, default=0.0)
    p.add_argument("--spp-out", help="also write Cycles' sample-count pass (samples per pixel) "
                   "to this EXR (through the compositor; adds its time to the render call)")
    return p.parse_args(argv)


def load_toml(path):
    """The scene with its includes merged as anamorph merges them (tables key by key, arrays of
    tables concatenated with the included entries first, other values of the including file win).
    File paths are made absolute relative to the file that names them."""
    with open(path, "rb") as f:
        doc = tomllib.load(f)
    base = os.path.dirname(os.path.abspath(path))
    for obj in doc.get("object", []):
        if "file" in obj:
            obj["file"] = os.path.join(base, obj["file"])
    for mat in doc.get("material", []):
        for v in mat.values():
            if isinstance(v, dict) and "file" in v:
                v["file"] = os.path.join(base, v["file"])
    inc = doc.pop("include", [])
    for name in [inc] if isinstance(inc, str) else inc:
        doc = merge(load_toml(os.path.join(base, name)), doc)
    return doc


def merge(a, b):
    out = dict(a)
    for k, v in b.items():
        if isinstance(v, dict) and isinstance(out.get(k), dict):
            out[k] = merge(out[k], v)
        elif isinstance(v, list) and v and isinstance(v[0], dict) and isinstance(out.get(k), list):
            out[k] = out[k] + v
        else:
            out[k] = v
    return out


def color3(v, default):
    if v is None:
        v = default
    if isinstance(v, (int, float)):
        return (float(v),) * 3
    return tuple(float(x) for x in v)


def read_mtl(obj_path):
    """name -> (Kd, emission) as anamorph's OBJ loader reads them (Ke, else Ka when > 1)."""
    mats = {}
    mtllibs = []
    with open(obj_path) as f:
        for line in f:
            t = line.split()
            if t and t[0] == "mtllib":
                mtllibs.append(os.path.join(os.path.dirname(obj_path), " ".join(t[1:])))
    for lib in mtllibs:
        cur = None
        with open(lib) as f:
            for line in f:
                t = line.split()
                if not t:
                    continue
                if t[0] == "newmtl":
                    cur = mats.setdefault(t[1], {"Kd": (0.8,) * 3, "Ka": (0,) * 3, "Ke": (0,) * 3})
                elif cur is not None and t[0] in ("Kd", "Ka", "Ke"):
                    cur[t[0]] = tuple(float(x) for x in t[1:4])
    out = {}
    for name, m in mats.items():
        e = m["Ke"] if max(m["Ke"]) > 0 else (m["Ka"] if max(m["Ka"]) > 1 else (0, 0, 0))
        out[name] = (m["Kd"], e)
    return out


def lambert_material(name, albedo, emission=(0, 0, 0)):
    """Diffuse BSDF (Lambertian: roughness 0) plus, for lights, an Emission of radiance
    `emission` (strength 1, so the colour is the radiance)."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    diff = nt.nodes.new("ShaderNodeBsdfDiffuse")
    diff.inputs["Color"].default_value = (*albedo, 1.0)
    diff.inputs["Roughness"].default_value = 0.0
    shader = diff.outputs["BSDF"]
    if max(emission) > 0:
        em = nt.nodes.new("ShaderNodeEmission")
        em.inputs["Color"].default_value = (*emission, 1.0)
        em.inputs["Strength"].default_value = 1.0
        add = nt.nodes.new("ShaderNodeAddShader")
        nt.links.new(diff.outputs["BSDF"], add.inputs[0])
        nt.links.new(em.outputs["Emission"], add.inputs[1])
        shader = add.outputs["Shader"]
    nt.links.new(shader, out.inputs["Surface"])
    return mat, nt, diff


def glass_material(m):
    """A whitted material with transmission 1 (anamorph's smooth dielectric: Fresnel reflection
    and refraction, no diffuse part) as a sharp Glass BSDF of the same IOR, white."""
    if float(m.get("diffuse", 1.0)) != 0 or float(m.get("reflectivity", 0)) != 0:
        raise SystemExit("cycles_render.py: glass needs diffuse = 0 and reflectivity = 0")
    mat = bpy.data.materials.new(m["name"] + "_glass")
    mat.use_nodes = True
    nt = mat.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    g = nt.nodes.new("ShaderNodeBsdfGlass")
    g.distribution = "SHARP"
    g.inputs["Color"].default_value = (*color3(m.get("color"), 1.0), 1.0)
    g.inputs["IOR"].default_value = float(m.get("ior", 1.5))
    nt.links.new(g.outputs["BSDF"], out.inputs["Surface"])
    return mat


def diffuse_from_gltf(mat):
    """Replace the importer's Principled BSDF by a Diffuse BSDF fed by the same base colour
    (texture chain or constant)."""
    nt = mat.node_tree
    pr = next(n for n in nt.nodes if n.type == "BSDF_PRINCIPLED")
    out = next(n for n in nt.nodes if n.type == "OUTPUT_MATERIAL")
    diff = nt.nodes.new("ShaderNodeBsdfDiffuse")
    diff.inputs["Roughness"].default_value = 0.0
    base = pr.inputs["Base Color"]
    if base.is_linked:
        nt.links.new(base.links[0].from_socket, diff.inputs["Color"])
    else:
        diff.inputs["Color"].default_value = base.default_value
    nt.nodes.remove(pr)
    nt.links.new(diff.outputs["BSDF"], out.inputs["Surface"])


# anamorph's scenes are y-up; both of Blender's importers (OBJ with forward -Z / up Y, glTF)
# map (x, y, z) to (x, -z, y), a rotation of +90 degrees about x.
TO_BLENDER = Matrix.Rotation(math.radians(90), 4, "X")


def add_primitive(obj, toml_mats):
    """A `sphere` (center, radius) or `box` (min, max) object with its whitted material's albedo
    and emission x emission_strength (radiance)."""
    m = toml_mats[obj["material"]]
    if m.get("type", "whitted") != "whitted":
        raise SystemExit("cycles_render.py: only whitted (diffuse) materials on primitives")
    if float(m.get("transmission", 0)) == 1.0:
        mat = glass_material(m)
    else:
        k = float(m.get("emission_strength", 1.0))
        mat, _, _ = lambert_material(m["name"] + "_lambert", color3(m.get("color"), 0.8),
                                     tuple(k * c for c in color3(m.get("emission"), 0)))
    if obj["type"] == "sphere":
        bpy.ops.mesh.primitive_uv_sphere_add(segments=96, ring_count=48, radius=obj["radius"],
                                             location=TO_BLENDER @ Vector(obj["center"]))
        bpy.ops.object.shade_smooth()
    else:
        lo, hi = Vector(obj["min"]), Vector(obj["max"])
        d = hi - lo
        bpy.ops.mesh.primitive_cube_add(size=1.0, location=TO_BLENDER @ ((lo + hi) / 2))
        bpy.context.active_object.scale = (d.x, d.z, d.y)  # (x, y, z) -> Blender (x, -z, y)
    bpy.context.active_object.data.materials.append(mat)


def look_at_matrix(eye, at, up):
    """anamorph's rig: f = normalize(at - eye), r = normalize(f x up), u = r x f; camera space
    x = r, y = u, -z = f. Blender's camera has the same local axes."""
    eye, at, up = Vector(eye), Vector(at), Vector(up)
    f = (at - eye).normalized()
    r = f.cross(up).normalized()
    u = r.cross(f)
    m = Matrix.Identity(4)
    for i in range(3):
        m[i][0], m[i][1], m[i][2], m[i][3] = r[i], u[i], -f[i], eye[i]
    return m


def sample_count_output(sc, path):
    """A compositor File Output node writes the Debug Sample Count pass; the Composite node keeps
    the combined image as the render result."""
    sc.view_layers[0].cycles.pass_debug_sample_count = True
    sc.use_nodes = True
    sc.render.use_compositing = True
    tree = sc.node_tree
    for n in list(tree.nodes):
        tree.nodes.remove(n)
    rl = tree.nodes.new("CompositorNodeRLayers")
    comp = tree.nodes.new("CompositorNodeComposite")
    tree.links.new(rl.outputs["Image"], comp.inputs["Image"])
    fo = tree.nodes.new("CompositorNodeOutputFile")
    fo.base_path = os.path.dirname(os.path.abspath(path))
    fo.file_slots[0].path = os.path.basename(path) + "_"  # Blender appends the frame number
    fo.format.file_format = "OPEN_EXR"
    fo.format.color_depth = "32"
    tree.links.new(rl.outputs["Debug Sample Count"], fo.inputs[0])


def main():
    a = parse_args()
    scene_doc = load_toml(a.scene)
    img = scene_doc.get("image", {})
    width = a.width or img.get("width", 640)
    height = a.height or img.get("height", 480)
    render = scene_doc.get("render", {})
    max_depth = render.get("max_depth", 5)
    bounces = a.bounces if a.bounces is not None else max(0, max_depth - 1)

    # An empty scene.
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    sc = bpy.context.scene

    toml_mats = {m["name"]: m for m in scene_doc.get("material", [])}
    for obj in scene_doc.get("object", []):
        if obj.get("type") in ("sphere", "box"):
            add_primitive(obj, toml_mats)
            continue
        if obj.get("type") != "mesh":
            raise SystemExit(f"cycles_render.py: object type {obj.get('type')} not supported")
        path = obj["file"]
        before = set(bpy.data.objects)
        ext = os.path.splitext(path)[1].lower()
        if ext == ".obj":
            bpy.ops.wm.obj_import(filepath=path, forward_axis="NEGATIVE_Z", up_axis="Y")
        elif ext in (".gltf", ".glb"):
            # Debian 12's Blender 3.4 glTF importer uses np.bool, which numpy 1.24 removed.
            import numpy
            if "bool" not in numpy.__dict__:
                numpy.bool = bool
            bpy.ops.import_scene.gltf(filepath=path)
        else:
            raise SystemExit(f"cycles_render.py: {path}: only OBJ and glTF are supported")
        new = [o for o in bpy.data.objects if o not in before and o.type == "MESH"]
        override = toml_mats.get(obj.get("material")) if obj.get("material") else None
        mtl = read_mtl(path) if ext == ".obj" else {}
        for ob in new:
            for slot in ob.material_slots:
                m = slot.material
                if override is not None:
                    if override.get("type", "whitted") != "whitted":
                        raise SystemExit("cycles_render.py: only whitted (diffuse) overrides")
                    col = override.get("color", 0.8)
                    if isinstance(col, dict):  # an image: keep the importer's texture chain
                        diffuse_from_gltf(m)
                    else:
                        slot.material, _, _ = lambert_material(
                            override["name"], color3(col, 0.8),
                            color3(override.get("emission"), 0))
                elif ext == ".obj":
                    kd, e = mtl[m.name.split(".")[0]]
                    slot.material, _, _ = lambert_material(m.name + "_lambert", kd, e)
                else:
                    diffuse_from_gltf(m)

    # Camera.
    cam_doc = scene_doc.get("camera", {})
    preset = cam_doc.get("preset", "perspective")
    cam_data = bpy.data.cameras.new("cam")
    cam = bpy.data.objects.new("cam", cam_data)
    sc.collection.objects.link(cam)
    sc.camera = cam
    cam.matrix_world = TO_BLENDER @ look_at_matrix(
        cam_doc.get("look_from", [0, 0, 0]), cam_doc.get("look_at", [0, 0, -1]),
        cam_doc.get("up", [0, 1, 0]))
    cam_data.clip_start = 1e-3
    cam_data.clip_end = 1e7
    if preset == "perspective":
        cam_data.type = "PERSP"
        axis = cam_doc.get("fov_axis", "horizontal")
        fov = math.radians(cam_doc.get("fov", 60))
        if axis == "vertical":
            cam_data.sensor_fit = "VERTICAL"
            cam_data.angle_y = fov
        elif axis == "horizontal":
            cam_data.sensor_fit = "HORIZONTAL"
            cam_data.angle_x = fov
        else:
            raise SystemExit("cycles_render.py: fov_axis diagonal not supported")
    elif preset == "equirectangular":
        cam_data.type = "PANO"
        cc = cam_data.cycles
        cc.panorama_type = "EQUIRECTANGULAR"
        lon = cam_doc.get("longitude_range", [-180, 180])
        lat = cam_doc.get("latitude_range", [-90, 90])
        # anamorph: longitude grows to the right of look_at; Cycles' longitude grows to the left.
        cc.longitude_min, cc.longitude_max = math.radians(-lon[1]), math.radians(-lon[0])
        cc.latitude_min, cc.latitude_max = math.radians(lat[0]), math.radians(lat[1])
    elif preset == "dome":
        # anamorph's domemaster (untilted, eye at the centre): an equidistant fisheye whose centre
        # is the rig's up, image up towards the back (-forward), right = right. Blender's camera
        # looks along its -z with image up its +y: the same rig aimed at up with -forward as up.
        if cam_doc.get("tilt", 0) or cam_doc.get("eye_offset"):
            raise SystemExit("cycles_render.py: dome tilt / eye_offset not supported")
        eye = Vector(cam_doc.get("look_from", [0, 0, 0]))
        f = (Vector(cam_doc.get("look_at", [0, 0, -1])) - eye).normalized()
        r = f.cross(Vector(cam_doc.get("up", [0, 1, 0]))).normalized()
        u = r.cross(f)
        cam.matrix_world = TO_BLENDER @ look_at_matrix(eye, eye + u, -f)
        cam_data.type = "PANO"
        cam_data.cycles.panorama_type = "FISHEYE_EQUIDISTANT"
        cam_data.cycles.fisheye_fov = math.radians(cam_doc.get("fov", 180))
    else:
        raise SystemExit(f"cycles_render.py: camera preset {preset} not supported")

    # World: anamorph's constant environment.
    env = scene_doc.get("environment", {})
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (*color3(env.get("color"), 0), 1.0)
    if "file" in env:
        # anamorph: longitude 0 (the image centre) is -z, u grows towards +x, top row +y. Cycles'
        # centre is Blender's +x, u growing towards -y; TO_BLENDER takes -z to +y and +x to +x,
        # so the lookup direction is turned by -90 degrees (less anamorph's `rotation` about +y,
        # Blender's +z) about z. Closest: the texels unfiltered (ours is bilinear, which blurs the
        # sun by half a texel; the image means agree within 0.3 %).
        nt = world.node_tree
        tex = nt.nodes.new("ShaderNodeTexEnvironment")
        tex.image = bpy.data.images.load(os.path.join(os.path.dirname(os.path.abspath(a.scene)),
                                                      env["file"]))
        tex.interpolation = "Closest"
        mp = nt.nodes.new("ShaderNodeMapping")
        mp.inputs["Rotation"].default_value = (0, 0, math.radians(-90 - env.get("rotation", 0)))
        tc = nt.nodes.new("ShaderNodeTexCoord")
        nt.links.new(tc.outputs["Generated"], mp.inputs["Vector"])
        nt.links.new(mp.outputs["Vector"], tex.inputs["Vector"])
        nt.links.new(tex.outputs["Color"], bg.inputs["Color"])
        # The importance map at the image's own resolution. Automatic picks 4096 x 2048 here (the
        # Mapping node hides the image from its rule): evaluating the world 8 M times took 9 of
        # the 10 s of a 4-spp 120 x 90 render (2 threads), for no better sampling of 256 x 128
        # texels than a map of their size (ours is that: render/lights.h).
        world.cycles.sampling_method = "MANUAL"
        world.cycles.sample_map_resolution = tex.image.size[0]
    bg.inputs["Strength"].default_value = float(env.get("strength", 1.0))
    sc.world = world

    # Render settings.
    sc.render.engine = "CYCLES"
    cy = sc.cycles
    cy.device = "CPU"
    cy.feature_set = "SUPPORTED"
    cy.samples = a.spp
    cy.use_adaptive_sampling = a.adaptive is not None
    if a.adaptive is not None:
        cy.adaptive_threshold = a.adaptive
        cy.adaptive_min_samples = a.min_spp
    cy.time_limit = a.time_limit
    cy.use_denoising = False
    cy.seed = a.seed
    cy.max_bounces = bounces
    cy.diffuse_bounces = bounces
    cy.glossy_bounces = bounces
    cy.transmission_bounces = bounces
    cy.volume_bounces = 0
    cy.transparent_max_bounces = bounces
    cy.min_light_bounces = 0
    cy.caustics_reflective = True
    cy.caustics_refractive = True
    cy.blur_glossy = 0.0
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.light_sampling_threshold = 0.0
    cy.use_guiding = False
    cy.pixel_filter_type = "BOX"
    cy.filter_width = 1.0
    cy.film_exposure = 1.0
    sc.render.threads_mode = "FIXED"
    sc.render.threads = a.threads
    sc.render.resolution_x = width
    sc.render.resolution_y = height
    sc.render.resolution_percentage = 100
    sc.render.use_persistent_data = False
    sc.view_settings.view_transform = "Standard"
    sc.view_settings.look = "None"
    sc.view_settings.exposure = 0
    sc.view_settings.gamma = 1
    sc.display_settings.display_device = "sRGB"
    sc.render.image_settings.file_format = "OPEN_EXR"
    sc.render.image_settings.color_depth = "32"
    sc.render.image_settings.color_mode = "RGBA"
    sc.render.image_settings.exr_codec = "ZIP"

    if a.spp_out:
        sample_count_output(sc, a.spp_out)

    t0 = time.perf_counter()
    bpy.ops.render.render(write_still=False)
    t1 = time.perf_counter()
    bpy.data.images["Render Result"].save_render(a.output)
    if a.spp_out:
        os.replace(a.spp_out + f"_{sc.frame_current:04d}.exr", a.spp_out)
    print(f"CYCLES_RENDER_SECONDS {t1 - t0:.4f}")
    print(f"CYCLES_SETTINGS {width}x{height} samples={a.spp} max_bounces={bounces} "
          f"adaptive={a.adaptive} min={a.min_spp} threads={sc.render.threads}")


main()
