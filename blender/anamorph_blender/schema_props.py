"""anamorph's parameter declarations as property descriptions (no bpy here).

`anamorph.declarations()` is what the editor's panels and the Python keyword arguments are
built from (scene/declarations.h); the add-on builds its Blender properties from the same
entries, so a key declared in C++ appears in Blender's camera panel on the next build. Nothing
here names a preset's key.
"""

import tomllib

# Keys Blender gives through its own objects: the camera's pose (look_from, look_at, up and
# transform come from the camera object) and glTF cameras (the add-on exports none).
POSE_KEYS = frozenset({"look_from", "look_at", "up", "transform", "gltf_camera"})
# Names a bpy PropertyGroup reserves.
_RESERVED = frozenset({"name", "rna_type", "bl_rna"})
# Types a property can hold: name -> (kind, vector size).
_KINDS = {
    "number": ("float", 0),
    "integer": ("int", 0),
    "bool": ("bool", 0),
    "string": ("string", 0),
    "[x, y, z]": ("vector", 3),
    "[a, b]": ("vector", 2),
    "colour": ("vector", 3),
    "number list": ("toml", 0),
    # Typed as TOML text too: grids and lists of points, tables of constants, a nested
    # origin function (dir.from_surface's surface, e.g. {type = "sphere", radius = 2}).
    "grid of [x, y, z]": ("toml", 0),
    "grid of numbers": ("toml", 0),
    "list of [x, y, z]": ("toml", 0),
    "table name = number": ("toml", 0),
    "origin function": ("toml", 0),
}


def parse_default(text):
    """The declared default (TOML text) as a Python value, or None when it has none."""
    if text is None:
        return None
    try:
        return tomllib.loads("v = " + text)["v"]
    except tomllib.TOMLDecodeError:
        return None


def prop_name(key):
    return "key_" + key if key in _RESERVED else key


def describe(param):
    """One declared parameter as {key, prop, kind, size, default, min, max, choices, doc, unit},
    or None for a type no Blender property can hold (functions, tables, transforms)."""
    if param["name"] in POSE_KEYS or param["type"] not in _KINDS:
        return None
    kind, size = _KINDS[param["type"]]
    if kind == "string" and param["choices"]:
        kind = "enum"
    default = parse_default(param.get("default"))
    if kind == "float" and isinstance(default, int):
        default = float(default)
    if kind == "vector" and not (isinstance(default, list) and len(default) == size):
        default = [float(v) for v in default] if isinstance(default, list) else None
        if default is not None and len(default) != size:
            default = None
    note = param.get("default_note") or ""
    doc = param["doc"] + (f" (default: {note})" if note else "")
    return {
        "key": param["name"],
        "prop": prop_name(param["name"]),
        "kind": kind,
        "size": size,
        "default": default,
        "min": param.get("min"),
        "max": param.get("max"),
        "choices": list(param.get("choices") or []),
        "doc": doc,
        "unit": param.get("unit") or "",
    }


def describe_all(params):
    """The parameters a property can hold, in declaration order."""
    return [d for d in (describe(p) for p in params) if d is not None]


def preset_specs(declarations):
    """{preset name: (doc, [descriptions])} for every declared preset."""
    return {name: (p["doc"], describe_all(p["params"]))
            for name, p in declarations["presets"].items()}


def function_specs(declarations, kind):
    """{type: (doc, [descriptions])} of every declared origin ("org") or direction ("dir")
    function: the camera panel's org/dir compositions."""
    return {name: (f["doc"], describe_all(f["params"]))
            for name, f in declarations[kind].items()}


def coin_specs(declarations):
    """The coin keys other than its position (the empty's location gives that)."""
    return [d for d in describe_all(declarations["coin"]) if d["key"] != "position"]


def camera_common_specs(declarations):
    """Keys every camera takes (depth of field, shutter, rolling shutter), minus the pose."""
    return describe_all(declarations["camera"])


def render_specs(declarations):
    return describe_all(declarations["render"])
