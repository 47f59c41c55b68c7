"""The scene file the add-on hands to anamorph, from plain Python data (no bpy here).

Axes: Blender is right-handed +Z up; anamorph's world is glTF's, +Y up, and Blender's glTF
exporter writes (x, y, z)_glTF = (x, z, -y)_Blender. Everything placed here (the camera rig,
coins, lights) is converted the same way, so it lands where the exported meshes are.
"""

import math

# glTF (= anamorph) world from Blender world.
GLTF_FROM_BLENDER = ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (0.0, -1.0, 0.0))


def to_gltf(p):
    """A point or direction from Blender's axes to anamorph's."""
    return [p[0], p[2], -p[1]]


def rig_matrix(m):
    """The camera's `transform.matrix` (16 numbers, row-major) from Blender's 4x4 matrix_world
    (a sequence of rows): glTF-from-Blender times the matrix, each axis normalized (a scaled
    camera object does not scale anamorph's rig). The camera's local frame is anamorph's camera
    space already: x right, y up, looking along -z."""
    rows = [[sum(GLTF_FROM_BLENDER[i][k] * m[k][j] for k in range(3)) for j in range(4)]
            for i in range(3)]
    for j in range(3):
        n = math.sqrt(sum(rows[i][j] ** 2 for i in range(3)))
        if n > 0:
            for i in range(3):
                rows[i][j] /= n
    return [v for row in rows for v in row] + [0.0, 0.0, 0.0, 1.0]


def environment_image(path, strength, z_rotation=0.0):
    """The [environment] table of a Blender world whose Background shows an equirectangular
    image `path` (times `strength`), its lookup direction turned by `z_rotation` radians about
    Blender's +Z first (a Mapping node of type Point or Vector; Texture is the inverse).

    Cycles looks a direction (x, y, z) up at u = 0.5 - atan2(y, x) / 2pi (its
    direction_to_equirectangular: the image's centre faces +X, u grows clockwise seen from
    above); anamorph at u = (atan2(x', -z') - rotation) / 2pi + 0.5 in its own axes
    (x', y', z') = (x, z, -y), i.e. atan2(x, y). A direction at azimuth a in Blender's xy plane,
    turned by z_rotation, has Cycles' u at 0.5 - (a + z_rotation) / 2pi and anamorph's at
    0.5 + (pi/2 - a - rotation) / 2pi: they agree when rotation = z_rotation + 90 degrees (the
    glTF issue's "undocumented 90 degrees"). Both put +Z (anamorph's +y) at the top row."""
    degrees = (math.degrees(z_rotation) + 90.0 + 180.0) % 360.0 - 180.0
    return {"file": path, "strength": float(strength), "rotation": degrees}


def nurbs_image_surface(points, weights, order_u, order_v, endpoint_u, endpoint_v):
    """The camera's org and dir for a Blender NURBS surface as the image surface: `points` rows
    of [x, y, z] in the camera's own space (Blender's row v = 0 first: the image's top edge;
    each row along u, left to right), `weights` in the same rows. Rays leave along the
    surface's normal dp/du x dp/dv, so a patch in front of the camera with u toward the
    camera's right and v toward its bottom looks where the camera does. Orders are Blender's
    (degree + 1); "Endpoint" knots are anamorph's clamped ones, else uniform."""
    org = {"type": "nurbs", "points": points, "weights": weights,
           "degree_u": order_u - 1, "degree_v": order_v - 1,
           "knot_type_u": "clamped" if endpoint_u else "uniform",
           "knot_type_v": "clamped" if endpoint_v else "uniform"}
    return {"org": org, "dir": {"type": "normal"}}


def _table(lines, header, values, fmt):
    lines.append(header)
    for k, v in values.items():
        lines.append(f"{fmt.key(k)} = {fmt.value(v)}")
    lines.append("")


# The [[object]] of the exported meshes: anamorph names its glTF nodes "blender/<node>", the
# node being the Blender object's name (the object index pass looks them up).
MESH_OBJECT = "blender"


def write(scene, fmt):
    """TOML text of `scene`: {image, render, camera, coins, environment, mesh_file or
    mesh_objects ([(file, transform matrix or None, ...)]), lights, animate (optional: the
    [[animate]] tables, {key, keys})}.
    `fmt` is anamorph's TOML formatter (anamorph._toml: key(), value()), the one the Python
    module's keyword arguments go through, so numbers reach the reader exactly."""
    lines = ["# Written by the anamorph Blender add-on (blender/anamorph_blender).", ""]
    _table(lines, "[image]", scene["image"], fmt)
    _table(lines, "[render]", scene["render"], fmt)
    camera = dict(scene["camera"])
    matrix = camera.pop("matrix")
    lines.append("[camera]")
    for k, v in camera.items():
        lines.append(f"{fmt.key(k)} = {fmt.value(v)}")
    lines.append(f"transform = {{ matrix = {fmt.value(matrix)} }}")
    lines.append("")
    for coin in scene["coins"]:
        _table(lines, "[[camera.coin]]", coin, fmt)
    if scene.get("environment"):
        _table(lines, "[environment]", scene["environment"], fmt)
    objects = scene.get("mesh_objects") or (
        [(scene["mesh_file"], None)] if scene.get("mesh_file") else [])
    for file, matrix, *_ in objects:
        _table(lines, "[[object]]", {"type": "mesh", "name": MESH_OBJECT, "file": file,
                                     "lights": False, "cameras": False, "animation": False},
               fmt)
        if matrix is not None:
            lines.insert(-1, f"transform = {{ matrix = {fmt.value(matrix)} }}")
    for light in scene["lights"]:
        _table(lines, "[[light]]", light, fmt)
    for table in scene.get("animate") or ():
        _table(lines, "[[animate]]", table, fmt)
    return "\n".join(lines)


def light(kind, name, power, color, radius, matrix, spot_size=0.0, spot_blend=0.0,
          size=(0.0, 0.0)):
    """A Blender light as an anamorph [[light]] table (Blender 3.4 Cycles' units, measured in
    tests/blender/README.md): point and spot of power P [W] have radiant intensity P / (4 pi);
    a point of radius r > 0 is a sphere of radiance P / (4 pi^2 r^2) (the same power); a sun of
    strength S is irradiance S; an area light of power P and area A is a one-sided quad of
    radiance P / (pi A). Returns None for a kind that is not carried over."""
    pos = to_gltf([matrix[0][3], matrix[1][3], matrix[2][3]])
    # A light shines along its local -Z.
    axis = to_gltf([-matrix[0][2], -matrix[1][2], -matrix[2][2]])
    rgb = [float(c) for c in color[:3]]
    if kind == "POINT" and radius > 0:
        radiance = power / (4 * math.pi ** 2 * radius ** 2)
        return {"type": "sphere", "name": name, "center": pos, "radius": radius,
                "radiance": [c * radiance for c in rgb]}
    if kind == "POINT":
        return {"type": "point", "name": name, "position": pos,
                "intensity": [c * power / (4 * math.pi) for c in rgb]}
    if kind == "SPOT":
        half = math.degrees(spot_size) / 2
        return {"type": "spot", "name": name, "position": pos, "direction": axis,
                "intensity": [c * power / (4 * math.pi) for c in rgb],
                "cone_angle": half * (1 - spot_blend), "cone_falloff": half * spot_blend}
    if kind == "SUN":
        return {"type": "directional", "name": name, "direction": axis,
                "irradiance": [c * power for c in rgb]}
    if kind == "AREA":
        ex = [matrix[i][0] * size[0] for i in range(3)]
        ey = [matrix[i][1] * size[1] for i in range(3)]
        centre = [matrix[i][3] for i in range(3)]
        corner = [centre[i] - ex[i] / 2 - ey[i] / 2 for i in range(3)]
        area = math.sqrt(sum(v * v for v in _cross(ex, ey)))
        if area <= 0:
            return None
        # edge_u x edge_v must be the light's -Z: y x x = -z.
        return {"type": "quad", "name": name, "corner": to_gltf(corner), "edge_u": to_gltf(ey),
                "edge_v": to_gltf(ex), "radiance": [c * power / (math.pi * area) for c in rgb]}
    return None


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


class Raw(str):
    """TOML text written as given (a number list the user typed, e.g. "[0, 1.2, 0.1]"); the
    scene reader checks its values."""

    @classmethod
    def checked(cls, text, key):
        """Raw text that is one TOML value, else ValueError naming the key."""
        import tomllib

        try:
            tomllib.loads("v = " + text)
        except tomllib.TOMLDecodeError as e:
            raise ValueError(f"{key}: {text!r} is not a TOML value ({e})") from None
        return cls(text)


class Formatter:
    """anamorph's own TOML formatter (anamorph._toml, the one its keyword arguments go through:
    numbers reach the reader exactly), passing Raw text through."""

    def __init__(self, anamorph):
        from importlib import import_module

        self._toml = import_module(anamorph.__name__ + "._toml")

    def key(self, k):
        return self._toml.key(k)

    def value(self, v):
        return str(v) if isinstance(v, Raw) else self._toml.value(v)
