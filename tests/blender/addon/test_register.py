"""The add-on registers from the repository and from the packaged zip; its panels hold every
key anamorph declares (the properties are made from anamorph.declarations(), the editor's and
the Python keywords' source); without the module it says where it looked."""

import os
import subprocess
import sys

import addon_utils
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

bl = common.enable_addon()
am = __import__("anamorph")


def engine_available():
    try:
        bpy.context.scene.render.engine = "ANAMORPH"
        return True
    except TypeError:
        return False


common.check(engine_available(), "the render engine 'anamorph' is registered")

# Every preset and every key a property can hold, by an independent walk of the declarations.
decl = am.declarations()
cam = bpy.data.cameras.new("c")
items = {i.identifier for i in cam.anamorph.bl_rna.properties["preset"].enum_items}
extra = {"BLENDER", "FUNCTIONS"}
common.check(items == set(decl["presets"]) | extra,
             "preset choices = the declared presets + BLENDER, FUNCTIONS (missing %s, extra %s)"
             % (set(decl["presets"]) - items, items - set(decl["presets"]) - extra))
holdable = {"number", "integer", "bool", "string", "[x, y, z]", "[a, b]", "colour", "number list",
            "grid of [x, y, z]", "grid of numbers", "list of [x, y, z]", "table name = number",
            "origin function"}
missing = []
groups = [("p_" + n, p) for n, p in decl["presets"].items()]
for kind in ("org", "dir"):
    types = {i.identifier for i in cam.anamorph.bl_rna.properties[kind + "_type"].enum_items}
    common.check(types == set(decl[kind]), "%s function choices = the declared ones (missing "
                 "%s, extra %s)" % (kind, set(decl[kind]) - types, types - set(decl[kind])))
    groups += [(kind + "_" + n, f) for n, f in decl[kind].items()]
for attr, p in groups:
    group = getattr(cam.anamorph, attr)
    for k in p["params"]:
        if k["type"] in holdable and k["name"] not in {"look_from", "look_at", "up"} \
                and k["name"] not in group.bl_rna.properties:
            missing.append(attr + "." + k["name"])
for k in decl["coin"]:
    if k["name"] != "position" and k["name"] not in bpy.types.Object.bl_rna.properties[
            "anamorph_coin"].fixed_type.bl_rna.properties:
        missing.append("coin." + k["name"])
common.check(not missing, "every declared key has a property (missing: %s)" % missing)
fov = cam.anamorph.p_fisheye.bl_rna.properties["fov"]
d = next(k for k in decl["presets"]["fisheye"]["params"] if k["name"] == "fov")
common.check(fov.default == float(d["default"]) and fov.description.startswith(d["doc"]),
             "fisheye.fov's default %s and doc from the declaration (%s)" % (fov.default,
                                                                             d["default"]))

addon_utils.disable("anamorph_blender", default_set=True)
bpy.context.scene.render.engine = "CYCLES"
common.check(not hasattr(bpy.types.Camera, "anamorph") and not engine_available(),
             "disabling removes the engine and the camera properties")
common.check(not hasattr(bpy.types.ViewLayer, "anamorph_albedo") and not any(
    getattr(h, "__module__", "").startswith("anamorph_blender")
    for h in bpy.app.handlers.depsgraph_update_post),
             "disabling removes the Albedo pass's property and the depsgraph handler")

# The packaged zip, installed into this test's own user folder (run.sh sets it).
zip_path = os.path.join(common.OUT, "anamorph_blender.zip")
pkg = subprocess.run([os.path.join(common.REPO, "scripts", "package-blender-addon"), "--out",
                      zip_path, "--module-dir", os.environ["ANAMORPH_PYTHONPATH"]],
                     capture_output=True, text=True)
common.check(pkg.returncode == 0, "package-blender-addon: %s" % pkg.stderr.strip())
sys.path.remove(os.path.join(common.REPO, "blender"))
for m in [m for m in sys.modules if m.startswith("anamorph_blender")]:
    del sys.modules[m]
bpy.ops.preferences.addon_install(filepath=zip_path)
addon_utils.enable("anamorph_blender", default_set=True, handle_error=None)
from anamorph_blender import bl as installed  # noqa: E402

common.check(installed.__file__.startswith(os.environ["BLENDER_USER_SCRIPTS"]),
             "the zip installed into the user folder (%s)" % installed.__file__)
common.check(installed._load_error == "" and hasattr(bpy.types.Camera, "anamorph")
             and engine_available(),
             "the installed add-on found the module (%r)" % installed._load_error)
from anamorph_blender import _build_location  # noqa: E402

common.check(_build_location.PYTHON_DIR == os.path.abspath(os.environ["ANAMORPH_PYTHONPATH"]),
             "the zip records the module's folder (%s)" % _build_location.PYTHON_DIR)

# Without any module: a plain Python with nothing to find names every place it looked.
probe = ("import sys; sys.path.insert(0, %r); from anamorph_blender import locate\n"
         "try:\n    locate.import_anamorph('/nonexistent/pref')\nexcept locate.NotFound as e:\n"
         "    print(e); sys.exit(3)\n" % os.path.join(common.REPO, "blender"))
env = {k: v for k, v in os.environ.items() if k not in {"ANAMORPH_PYTHONPATH", "PYTHONPATH"}}
env["ANAMORPH_PYTHONPATH"] = os.path.join(common.OUT, "empty")
run = subprocess.run([sys.executable, "-c", probe.replace(
    "from anamorph_blender import locate",
    "from anamorph_blender import locate; locate._HERE = '/nonexistent/a/b'")],
    capture_output=True, text=True, env=env)
msg = run.stdout
common.check(run.returncode == 3 and "/nonexistent/pref (add-on preference)" in msg
             and "ANAMORPH_PYTHONPATH" in msg and "scripts/build _anamorph" in msg
             and "Python 3.11" in msg,
             "without a module the error names each place tried:\n" + msg + run.stderr)
common.finish()
