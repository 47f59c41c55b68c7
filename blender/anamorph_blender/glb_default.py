"""Blender's default surface for meshes without a material, written into an exported .glb
(no bpy here).

Blender's glTF exporter leaves such primitives without a material, and glTF's default material
is white, fully metallic and fully rough; Cycles and EEVEE shade them with a grey diffuse
surface of albedo 0.8 instead (measured before this: anamorph half as bright as Cycles on an
unassigned floor). Every primitive without a material gets one that is exactly that: base
colour 0.8, metallic 0, and KHR_materials_specular's specularColorFactor 0 (per the extension a
pure Lambertian, as tests/blender/README.md explains for the exporter's own diffuse materials).
"""

import json
import struct

DEFAULT = {
    "name": "blender_default_surface",
    "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0], "metallicFactor": 0.0,
                             "roughnessFactor": 1.0},
    "extensions": {"KHR_materials_specular": {"specularColorFactor": [0.0, 0.0, 0.0]}},
}


def _chunks(data):
    magic, version, _ = struct.unpack_from("<4sII", data, 0)
    if magic != b"glTF" or version != 2:
        raise ValueError("not a glTF 2.0 binary file")
    off, out = 12, []
    while off < len(data):
        length, kind = struct.unpack_from("<I4s", data, off)
        out.append((kind, data[off + 8:off + 8 + length]))
        off += 8 + length
    return out


def patch(path):
    """Gives every primitive of the .glb at `path` without a material Blender's default
    surface; returns how many primitives it changed (0: the file is left as it was)."""
    with open(path, "rb") as f:
        chunks = _chunks(f.read())
    doc = json.loads(chunks[0][1])
    bare = [p for m in doc.get("meshes", []) for p in m["primitives"] if "material" not in p]
    if not bare:
        return 0
    materials = doc.setdefault("materials", [])
    for p in bare:
        p["material"] = len(materials)
    materials.append(DEFAULT)
    used = doc.setdefault("extensionsUsed", [])
    if "KHR_materials_specular" not in used:
        used.append("KHR_materials_specular")
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    body = struct.pack("<I4s", len(text), b"JSON") + text
    for kind, payload in chunks[1:]:
        body += struct.pack("<I4s", len(payload), kind) + payload
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body)
    import os

    os.replace(tmp, path)
    return len(bare)
