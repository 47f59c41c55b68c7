"""Shared by the add-on's headless tests (run.sh runs each in Debian's Blender):
blender -b --factory-startup --python tests/blender/addon/test_X.py -- REPO OUTDIR ANAMORPH

The add-on is enabled from the repository (blender/), the anamorph module found through
ANAMORPH_PYTHONPATH (run.sh sets it to the build's python folder)."""

import os
import sys

import addon_utils
import bpy
import numpy as np

REPO, OUT, ANAMORPH_BIN = sys.argv[sys.argv.index("--") + 1:][:3]
os.makedirs(OUT, exist_ok=True)
sys.path.insert(0, os.path.join(REPO, "tests", "blender"))
sys.path.insert(0, os.path.join(REPO, "blender"))
import exr_io  # noqa: E402

_failures = []


def enable_addon():
    """Enables anamorph_blender from the repository; returns its bl module."""
    addon_utils.enable("anamorph_blender", default_set=True, handle_error=None)
    from anamorph_blender import bl

    if bl._load_error:
        fail("the add-on could not load anamorph: " + bl._load_error)
        finish()
    return bl


def check(ok, message):
    """Records a failure (with the values in `message`) and goes on."""
    print(("ok: " if ok else "FAIL: ") + message, flush=True)
    if not ok:
        _failures.append(message)
    return ok


def fail(message):
    check(False, message)


def finish():
    """Exits Blender with 0 when every check passed, 1 otherwise."""
    print("%s: %d failure(s)" % (os.path.basename(sys.argv[sys.argv.index("--python") + 1]),
                                 len(_failures)), flush=True)
    sys.stdout.flush()
    os._exit(1 if _failures else 0)


def exr_settings(scene):
    im = scene.render.image_settings
    im.file_format = "OPEN_EXR"
    im.color_depth = "32"
    im.color_mode = "RGBA"
    im.exr_codec = "ZIP"
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"


def read_rgba(path):
    """(H, W, 4) float32 of an EXR, rows from the top (Blender's or anamorph's)."""
    ch = exr_io.read_exr(path)
    names = {k.split(".")[-1]: k for k in ch}
    return np.stack([ch[names[c]] for c in "RGBA"], axis=-1).astype(np.float32)


def render_still(path):
    """Renders the current frame with the scene's engine into an EXR at `path`."""
    scene = bpy.context.scene
    exr_settings(scene)
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    return path


def small_scene(width=80, height=60, spp=16):
    """A floor, a sphere, a soft point light, a grey world and a camera: the add-on's smallest
    useful scene (factory startup, no file). Enables the add-on."""
    bpy.ops.wm.read_factory_settings(use_empty=True)  # disables add-ons: enable after it
    enable_addon()
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.render.engine = "ANAMORPH"
    scene.anamorph.spp = spp
    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.05, 0.06, 0.08, 1)
    bg.inputs["Strength"].default_value = 1.0
    scene.world = world
    bpy.ops.mesh.primitive_plane_add(size=20, location=(0, 0, 0))
    bpy.ops.mesh.primitive_uv_sphere_add(radius=1, location=(0, 0, 1), segments=32,
                                         ring_count=16)
    bpy.ops.object.shade_smooth()
    light = bpy.data.lights.new("lamp", "POINT")
    light.energy = 800
    light.shadow_soft_size = 0.4
    lamp = bpy.data.objects.new("lamp", light)
    lamp.location = (2.5, -2.0, 4.0)
    scene.collection.objects.link(lamp)
    cam = bpy.data.cameras.new("camera")
    cam.angle = 0.9
    cam_ob = bpy.data.objects.new("camera", cam)
    cam_ob.location = (0, -7, 2.5)
    cam_ob.rotation_euler = (1.35, 0, 0)
    scene.collection.objects.link(cam_ob)
    scene.camera = cam_ob
    return scene


def cycles_settings(scene, spp):
    """Cycles set to what anamorph computes: CPU, fixed samples and seed, no adaptive sampling,
    denoising, clamping or glossy filter, 8 bounces of each kind, a 1-pixel box filter, an
    opaque film."""
    cy = scene.cycles
    cy.device, cy.samples, cy.seed = "CPU", spp, 1
    cy.use_adaptive_sampling = cy.use_denoising = False
    cy.max_bounces = cy.diffuse_bounces = cy.glossy_bounces = cy.transmission_bounces = 8
    cy.sample_clamp_direct = cy.sample_clamp_indirect = cy.light_sampling_threshold = 0.0
    cy.blur_glossy = 0.0  # Filter Glossy: Cycles' default 1 blurs caustics (a bias)
    cy.pixel_filter_type, cy.filter_width = "BOX", 1.0
    scene.render.film_transparent = False


def both_engines(name, cycles_spp):
    """(anamorph's image, Cycles') of the current scene, rendered into OUT/name_{a,c}.exr."""
    from anamorph_blender import bl

    scene = bpy.context.scene
    scene.render.engine = "ANAMORPH"
    mine = read_rgba(render_still(os.path.join(OUT, name + "_a.exr")))
    check(bl.last_error == "", "%s: anamorph rendered without error (%r)"
          % (name, bl.last_error))
    scene.render.engine = "CYCLES"
    cycles_settings(scene, cycles_spp)
    return mine, read_rgba(render_still(os.path.join(OUT, name + "_c.exr")))


def compare_means(name, mine, ref, tolerance=0.03):
    """Image means per channel within `tolerance` (relative) of the reference's."""
    m, r = mine[..., :3].mean(axis=(0, 1)), ref[..., :3].mean(axis=(0, 1))
    rel = m / r - 1
    check(bool(np.all(np.abs(rel) < tolerance)),
          "%s: image means per channel within %g %%: anamorph %s, Cycles %s, relative %s"
          % (name, 100 * tolerance, np.round(m, 5), np.round(r, 5), np.round(rel, 4)))


def compare_blocks(name, mine, ref, block, tolerance, floor=0.02):
    """block x block means per channel within `tolerance` of the reference's, relative to the
    reference's block mean plus `floor` (dark blocks are noise): a turned or mirrored picture
    fails it. Returns the worst relative difference."""
    h, w = ref.shape[0] // block, ref.shape[1] // block
    blocks = [img[:h * block, :w * block, :3].reshape(h, block, w, block, 3).mean(axis=(1, 3))
              for img in (mine, ref)]
    worst = np.abs(blocks[0] - blocks[1]) / (blocks[1] + floor)
    at = np.unravel_index(np.argmax(worst), worst.shape)[:2]
    check(worst.max() < tolerance, "%s: %d x %d block means within %g %% (+%g): worst %.3f at "
          "block %s, anamorph %s, Cycles %s" % (name, block, block, 100 * tolerance, floor,
                                                worst.max(), at, blocks[0][at], blocks[1][at]))
    return worst.max()


def exported_translation(toml_path, node):
    """Where the kept scene file `toml_path` places the glTF node `node` (a Blender object's
    name) of its meshes: the node's translation through its [[object]]'s transform (glTF axes),
    and the file holding it; (None, None) when no file has it."""
    import tomllib

    import gltf_inspect

    with open(toml_path, "rb") as f:
        objects = tomllib.load(f).get("object", [])
    for ob in objects:
        doc, _ = gltf_inspect.read_glb(os.path.join(os.path.dirname(toml_path), ob["file"]))
        found = next((n for n in doc["nodes"] if n.get("name") == node), None)
        if found is None:
            continue
        m = np.array(ob.get("transform", {}).get("matrix", np.eye(4).ravel()),
                     dtype=np.float64).reshape(4, 4)
        p = m @ np.array(list(found.get("translation", [0, 0, 0])) + [1.0])
        return [float(v) for v in p[:3]], ob["file"]
    return None, None
