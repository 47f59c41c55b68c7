#!/usr/bin/env python3
"""Writes the glTF fuzz seeds of the material extensions anamorph reads (issue 34): one small
quad per material (KHR_materials_transmission, _volume, _unlit, alphaMode BLEND, _clearcoat with
its textures, _sheen with its textures, _specular with its textures, _ior, _emissive_strength,
KHR_texture_transform inside an extension's textureInfo), as .gltf (data URIs) and .glb. Standard library only.
Usage: python3 fuzz/seeds/gltf/make_seeds.py   (writes next to itself)"""
import base64
import json
import os
import struct

# A 2x2 RGBA PNG (red, green, blue, white), made here so the seed needs no image file.
def png_2x2():
    import zlib
    rows = b"".join(b"\x00" + r for r in (b"\xff\x00\x00\xff\x00\xff\x00\xff",
                                           b"\x00\x00\xff\xff\xff\xff\xff\xff"))
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 2, 2, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def geometry():
    pos = [-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0]
    nrm = [0, 0, 1] * 4
    uv = [0, 1, 1, 1, 1, 0, 0, 0]
    idx = [0, 1, 2, 0, 2, 3]
    data = struct.pack("<12f", *pos) + struct.pack("<12f", *nrm) + struct.pack("<8f", *uv)
    data += struct.pack("<6H", *idx)
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
             {"buffer": 0, "byteOffset": 48, "byteLength": 48},
             {"buffer": 0, "byteOffset": 96, "byteLength": 32},
             {"buffer": 0, "byteOffset": 128, "byteLength": 12}]
    accessors = [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                  "min": [-1, -1, 0], "max": [1, 1, 0]},
                 {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
                 {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
                 {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}]
    return data, views, accessors


def tex(i, **kw):
    return dict({"index": i}, **kw)


MATERIALS = [
    {"name": "glass", "extensions": {
        "KHR_materials_transmission": {"transmissionFactor": 1, "transmissionTexture": tex(0)},
        "KHR_materials_volume": {"thicknessFactor": 0.5, "thicknessTexture": tex(0),
                                 "attenuationDistance": 2, "attenuationColor": [0.9, 0.5, 0.2]},
        "KHR_materials_ior": {"ior": 1.33}},
     "pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0}},
    {"name": "thin", "extensions": {"KHR_materials_transmission": {"transmissionFactor": 0.5}}},
    {"name": "flat", "extensions": {"KHR_materials_unlit": {}},
     "pbrMetallicRoughness": {"baseColorTexture": tex(0), "baseColorFactor": [1, 0.5, 0.2, 1]}},
    {"name": "veil", "alphaMode": "BLEND",
     "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.2, 0.2, 0.3],
                              "baseColorTexture": tex(0)}},
    {"name": "cutout", "alphaMode": "MASK", "alphaCutoff": 0.4,
     "pbrMetallicRoughness": {"baseColorTexture": tex(0)}},
    {"name": "coat", "normalTexture": tex(0, scale=0.8), "extensions": {
        "KHR_materials_clearcoat": {
            "clearcoatFactor": 1, "clearcoatRoughnessFactor": 0.2,
            "clearcoatTexture": tex(0, texCoord=0),
            "clearcoatRoughnessTexture": tex(0, extensions={
                "KHR_texture_transform": {"offset": [0.5, 0], "scale": [2, 2], "rotation": 0.3}}),
            "clearcoatNormalTexture": tex(0, scale=0.5)},
        "KHR_materials_specular": {"specularFactor": 0.5, "specularColorFactor": [1, 0.9, 0.8],
                                   "specularTexture": tex(0),
                                   "specularColorTexture": tex(0, extensions={
                                       "KHR_texture_transform": {"offset": [0.5, 0.5]}})}}},
    {"name": "velvet", "extensions": {
        "KHR_materials_sheen": {"sheenColorFactor": [0.8, 0.6, 1.0], "sheenRoughnessFactor": 0.4,
                                "sheenColorTexture": tex(0), "sheenRoughnessTexture": tex(0)},
        "KHR_materials_emissive_strength": {"emissiveStrength": 4}},
     "emissiveFactor": [0.1, 0.1, 0.1]},
]

EXTENSIONS = sorted({e for m in MATERIALS for e in m.get("extensions", {})} |
                    {"KHR_texture_transform"})


def document(uri_or_none, png_view):
    data, views, accessors = geometry()
    doc = {"asset": {"version": "2.0", "copyright": "anamorph fuzz seed, CC0-1.0"},
           "extensionsUsed": EXTENSIONS, "scene": 0,
           "scenes": [{"nodes": list(range(len(MATERIALS)))}],
           "nodes": [{"mesh": i, "translation": [2.2 * i, 0, 0]} for i in range(len(MATERIALS))],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                       "indices": 3, "material": i}]}
                      for i in range(len(MATERIALS))],
           "materials": MATERIALS, "accessors": accessors, "bufferViews": views,
           "samplers": [{"magFilter": 9728, "wrapS": 33648}],
           "textures": [{"source": 0, "sampler": 0}]}
    if png_view is None:
        doc["images"] = [{"uri": "data:image/png;base64," + base64.b64encode(png_2x2()).decode()}]
    else:
        doc["images"] = [{"bufferView": png_view, "mimeType": "image/png"}]
    doc["buffers"] = [{"byteLength": 0}]
    if uri_or_none:
        doc["buffers"][0]["uri"] = uri_or_none
    return doc


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    data, _, _ = geometry()
    doc = document("data:application/octet-stream;base64," + base64.b64encode(data).decode(), None)
    doc["buffers"][0]["byteLength"] = len(data)
    with open(os.path.join(here, "material_extensions.gltf"), "w") as f:
        json.dump(doc, f, separators=(",", ":"))
    # .glb: the PNG in a buffer view after the geometry.
    png = png_2x2()
    binary = data + png + b"\x00" * ((4 - len(png) % 4) % 4)
    doc = document(None, 4)
    doc["bufferViews"].append({"buffer": 0, "byteOffset": len(data), "byteLength": len(png)})
    doc["buffers"][0]["byteLength"] = len(binary)
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * ((4 - len(text) % 4) % 4)
    glb = (struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(text) + 8 + len(binary)) +
           struct.pack("<I4s", len(text), b"JSON") + text +
           struct.pack("<I4s", len(binary), b"BIN\x00") + binary)
    with open(os.path.join(here, "material_extensions.glb"), "wb") as f:
        f.write(glb)


if __name__ == "__main__":
    main()
