#!/usr/bin/env python3
"""Reads a .glb with the standard library only: lists what it holds (extensions, lights,
cameras, animations and their interpolations, skins, morph targets, images) and evaluates its
node animation at a time, per the glTF 2.0 specification (LINEAR with quaternion slerp, STEP,
CUBICSPLINE with tangents; times clamped to the first and last key).

  python3 tests/blender/gltf_inspect.py FILE.glb [--time SECONDS]

make_gltf.py uses it to check each export against Blender's own evaluation of the scene.
"""
import json
import math
import struct
import sys

_COMPONENTS = {5120: ("b", 127.0), 5121: ("B", 255.0), 5122: ("h", 32767.0),
               5123: ("H", 65535.0), 5125: ("I", None), 5126: ("f", None)}
_WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}


def read_glb(path):
    """(json dict, binary chunk bytes or b"")."""
    with open(path, "rb") as f:
        data = f.read()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    if magic != b"glTF" or version != 2 or length != len(data):
        raise ValueError(f"{path}: not a glTF 2.0 binary (magic {magic!r}, version {version})")
    off, doc, binary = 12, None, b""
    while off < length:
        size, kind = struct.unpack_from("<I4s", data, off)
        chunk = data[off + 8:off + 8 + size]
        if kind == b"JSON":
            doc = json.loads(chunk.decode("utf-8"))
        elif kind == b"BIN\0":
            binary = chunk
        off += 8 + size
    return doc, binary


def read_accessor(doc, binary, index):
    """The accessor's elements as tuples of floats (normalized integers mapped to [0, 1])."""
    acc = doc["accessors"][index]
    fmt, norm = _COMPONENTS[acc["componentType"]]
    n = _WIDTH[acc["type"]]
    view = doc["bufferViews"][acc["bufferView"]]
    base = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    size = struct.calcsize(fmt)
    stride = view.get("byteStride", n * size)
    out = []
    for i in range(acc["count"]):
        vals = struct.unpack_from("<%d%s" % (n, fmt), binary, base + i * stride)
        if norm is not None and acc.get("normalized", False):
            vals = tuple(max(v / norm, -1.0) for v in vals)
        out.append(tuple(float(v) for v in vals))
    return out


# ---------------------------------------------------------------------------------------------
# Animation sampling


def _slerp(a, b, s):
    d = sum(x * y for x, y in zip(a, b))
    if d < 0:
        b, d = tuple(-x for x in b), -d
    if d > 0.9995:
        q = tuple(x + s * (y - x) for x, y in zip(a, b))
    else:
        th = math.acos(d)
        wa, wb = math.sin((1 - s) * th) / math.sin(th), math.sin(s * th) / math.sin(th)
        q = tuple(wa * x + wb * y for x, y in zip(a, b))
    n = math.sqrt(sum(x * x for x in q))
    return tuple(x / n for x in q)


def sample(times, values, interpolation, t, path, width):
    """The channel's value at time t; `values` are the output elements (for weights: scalars,
    `width` of them per key)."""
    flat = [x for v in values for x in v]
    per_key = width * (3 if interpolation == "CUBICSPLINE" else 1)
    keys = [flat[i * per_key:(i + 1) * per_key] for i in range(len(times))]

    def value(k):
        return keys[k][width:2 * width] if interpolation == "CUBICSPLINE" else keys[k]

    if t <= times[0]:
        return tuple(value(0))
    if t >= times[-1]:
        return tuple(value(len(times) - 1))
    k = max(i for i in range(len(times)) if times[i] <= t)
    dt = times[k + 1] - times[k]
    s = (t - times[k]) / dt
    if interpolation == "STEP":
        return tuple(value(k))
    if interpolation == "LINEAR":
        a, b = value(k), value(k + 1)
        if path == "rotation":
            return _slerp(tuple(a), tuple(b), s)
        return tuple(x + s * (y - x) for x, y in zip(a, b))
    # CUBICSPLINE: keys hold (in-tangent, value, out-tangent), tangents per second.
    p0, m0 = value(k), keys[k][2 * width:3 * width]
    p1, m1 = value(k + 1), keys[k + 1][0:width]
    s2, s3 = s * s, s * s * s
    h = (2 * s3 - 3 * s2 + 1, s3 - 2 * s2 + s, -2 * s3 + 3 * s2, s3 - s2)
    v = tuple(h[0] * a + h[1] * dt * b + h[2] * c + h[3] * dt * d
              for a, b, c, d in zip(p0, m0, p1, m1))
    if path == "rotation":
        n = math.sqrt(sum(x * x for x in v))
        v = tuple(x / n for x in v)
    return v


def _matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def _trs(t, r, s):
    x, y, z, w = r
    rot = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
           [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
           [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    m = [[rot[i][j] * s[j] for j in range(3)] + [t[i]] for i in range(3)]
    return m + [[0.0, 0.0, 0.0, 1.0]]


def evaluate(doc, binary, t):
    """{node index: (world matrix 4x4 as rows, morph weights or None)} at time t (seconds),
    with every animation of the file applied at once."""
    local = {}
    for i, node in enumerate(doc.get("nodes", [])):
        local[i] = {"translation": tuple(node.get("translation", (0, 0, 0))),
                    "rotation": tuple(node.get("rotation", (0, 0, 0, 1))),
                    "scale": tuple(node.get("scale", (1, 1, 1))),
                    "weights": None}
        mesh = doc["meshes"][node["mesh"]] if "mesh" in node else None
        if mesh is not None and "weights" in mesh:
            local[i]["weights"] = tuple(node.get("weights", mesh["weights"]))
    for anim in doc.get("animations", []):
        for ch in anim["channels"]:
            target = ch["target"]
            if "node" not in target:
                continue
            smp = anim["samplers"][ch["sampler"]]
            times = [v[0] for v in read_accessor(doc, binary, smp["input"])]
            values = read_accessor(doc, binary, smp["output"])
            path = target["path"]
            width = len(local[target["node"]]["weights"]) if path == "weights" else \
                len(values[0])
            local[target["node"]][path] = sample(times, values, smp.get("interpolation",
                                                                         "LINEAR"), t, path,
                                                 width)
    parent = {c: i for i, n in enumerate(doc.get("nodes", [])) for c in n.get("children", [])}
    world = {}

    def world_of(i):
        if i not in world:
            n = doc["nodes"][i]
            if "matrix" in n:
                m = [[n["matrix"][c * 4 + r] for c in range(4)] for r in range(4)]
            else:
                m = _trs(local[i]["translation"], local[i]["rotation"], local[i]["scale"])
            world[i] = _matmul(world_of(parent[i]), m) if i in parent else m
        return world[i]

    return {i: (world_of(i), local[i]["weights"]) for i in range(len(doc.get("nodes", [])))}


# ---------------------------------------------------------------------------------------------
# Summary


def summary(doc, binary):
    """What the file holds, as a JSON-able dict."""
    out = {"generator": doc.get("asset", {}).get("generator"),
           "copyright": doc.get("asset", {}).get("copyright"),
           "extensionsUsed": sorted(doc.get("extensionsUsed", [])),
           "extensionsRequired": sorted(doc.get("extensionsRequired", []))}
    nodes = doc.get("nodes", [])
    out["nodes"] = len(nodes)
    lights = doc.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    out["lights"] = []
    for i, n in enumerate(nodes):
        li = n.get("extensions", {}).get("KHR_lights_punctual", {}).get("light")
        if li is not None:
            out["lights"].append({"node": n.get("name"), **lights[li]})
    out["cameras"] = [{"node": n.get("name"), **doc["cameras"][n["camera"]]}
                      for n in nodes if "camera" in n]
    out["materials"] = [{"name": m.get("name"), "extensions": m.get("extensions", {}),
                         "pbr": m.get("pbrMetallicRoughness", {}),
                         "emissiveFactor": m.get("emissiveFactor"),
                         "doubleSided": m.get("doubleSided", False)}
                        for m in doc.get("materials", [])]
    out["animations"] = []
    for a in doc.get("animations", []):
        chans = []
        for ch in a["channels"]:
            smp = a["samplers"][ch["sampler"]]
            times = read_accessor(doc, binary, smp["input"])
            chans.append({"node": nodes[ch["target"]["node"]].get("name"),
                          "path": ch["target"]["path"],
                          "interpolation": smp.get("interpolation", "LINEAR"),
                          "keys": len(times), "t0": times[0][0], "t1": times[-1][0]})
        out["animations"].append({"name": a.get("name"), "channels": chans})
    out["skins"] = [{"name": s.get("name"), "joints": [nodes[j].get("name") for j in s["joints"]],
                     "inverseBindMatrices": "inverseBindMatrices" in s,
                     "skinned_nodes": [n.get("name") for n in nodes if n.get("skin") == k]}
                    for k, s in enumerate(doc.get("skins", []))]
    out["morph_meshes"] = [{"name": m.get("name"),
                            "targets": len(m["primitives"][0]["targets"]),
                            "target_names": m.get("extras", {}).get("targetNames"),
                            "weights": m.get("weights")}
                           for m in doc.get("meshes", []) if "targets" in m["primitives"][0]]
    out["images"] = [{"name": im.get("name"), "mimeType": im.get("mimeType"),
                      "bytes": doc["bufferViews"][im["bufferView"]]["byteLength"]
                      if "bufferView" in im else None} for im in doc.get("images", [])]
    out["triangles"] = sum(doc["accessors"][p["indices"]]["count"] // 3
                           for m in doc.get("meshes", []) for p in m["primitives"]
                           if "indices" in p)
    return out


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if argv else 2
    doc, binary = read_glb(argv[0])
    print(json.dumps(summary(doc, binary), indent=1))
    if "--time" in argv:
        t = float(argv[argv.index("--time") + 1])
        for i, (m, w) in evaluate(doc, binary, t).items():
            pos = [round(m[r][3], 6) for r in range(3)]
            print(doc["nodes"][i].get("name"), "position", pos, "weights", w)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
