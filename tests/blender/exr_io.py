#!/usr/bin/env python3
"""A small reader and writer of scanline OpenEXR files, with the standard library and numpy:
reads what Blender writes (single- and multilayer, compression NONE, ZIPS or ZIP, HALF or FLOAT
channels), writes FLOAT channels with ZIP compression. Blender's Python API can neither read
the passes of a multilayer EXR nor write a chosen subset of them; make_gltf.py uses this to keep
Cycles' Vector and Depth passes (all four Vector components) without the Combined image.

  python3 tests/blender/exr_io.py FILE.exr      # lists channels, size and per-channel ranges
"""
import os
import struct
import sys
import zlib

import numpy as np

_LINES = {0: 1, 2: 1, 3: 16}  # compression -> scanlines per chunk (NONE, ZIPS, ZIP)
_DTYPE = {1: np.float16, 2: np.float32, 0: np.uint32}


def _header(data):
    if data[:4] != b"\x76\x2f\x31\x01":
        raise ValueError("not an OpenEXR file")
    if struct.unpack_from("<I", data, 4)[0] & 0x1200:  # tiled or multipart
        raise ValueError("tiled or multi-part EXR: not supported")
    off, attrs = 8, {}
    while data[off] != 0:
        end = data.index(b"\0", off)
        name = data[off:end].decode()
        end2 = data.index(b"\0", end + 1)
        kind = data[end + 1:end2].decode()
        size = struct.unpack_from("<i", data, end2 + 1)[0]
        attrs[name] = (kind, data[end2 + 5:end2 + 5 + size])
        off = end2 + 5 + size
    return attrs, off + 1


def _channels(raw):
    out, off = [], 0
    while raw[off] != 0:
        end = raw.index(b"\0", off)
        ptype = struct.unpack_from("<i", raw, end + 1)[0]
        out.append((raw[off:end].decode(), ptype))
        off = end + 17
    return out


def _unzip(chunk, expected):
    t = np.frombuffer(zlib.decompress(chunk), np.uint8).astype(np.int64)
    if len(t) != expected:
        raise ValueError("EXR chunk: %d bytes, expected %d" % (len(t), expected))
    d = ((np.cumsum(t) - 128 * np.arange(len(t))) % 256).astype(np.uint8)
    half = (len(d) + 1) // 2
    out = np.empty_like(d)
    out[0::2], out[1::2] = d[:half], d[half:]
    return out.tobytes()


def read_exr(path):
    """{channel name: 2-D float array, rows from the top}."""
    with open(path, "rb") as f:
        data = f.read()
    attrs, off = _header(data)
    chans = _channels(attrs["channels"][1])
    comp = attrs["compression"][1][0]
    if comp not in _LINES:
        raise ValueError("%s: compression %d not supported" % (path, comp))
    x0, y0, x1, y1 = struct.unpack("<4i", attrs["dataWindow"][1])
    w, h = x1 - x0 + 1, y1 - y0 + 1
    per_chunk = _LINES[comp]
    n_chunks = (h + per_chunk - 1) // per_chunk
    offsets = struct.unpack_from("<%dQ" % n_chunks, data, off)
    sizes = [np.dtype(_DTYPE[t]).itemsize for _, t in chans]
    out = {name: np.empty((h, w), np.float32) for name, _ in chans}
    for off in offsets:
        y, size = struct.unpack_from("<ii", data, off)
        lines = min(per_chunk, y1 - y + 1)
        expected = lines * w * sum(sizes)
        chunk = data[off + 8:off + 8 + size]
        raw = chunk if size == expected else _unzip(chunk, expected)
        pos = 0
        for line in range(lines):
            row = y - y0 + line
            for (name, t), s in zip(chans, sizes):
                out[name][row] = np.frombuffer(raw, _DTYPE[t], w, pos)
                pos += w * s
    return out


def _attr(name, kind, payload):
    return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(payload)) + \
        payload


def _zip(raw):
    b = np.frombuffer(raw, np.uint8)
    t = np.concatenate([b[0::2], b[1::2]]).astype(np.int64)
    d = t.copy()
    d[1:] = (t[1:] - t[:-1] + 128) % 256
    packed = zlib.compress(d.astype(np.uint8).tobytes(), 9)
    return packed if len(packed) < len(raw) else raw  # the format's rule for incompressible data


def write_exr(path, channels):
    """Writes {name: 2-D array, rows from the top} as FLOAT channels, ZIP compression."""
    names = sorted(channels)
    h, w = channels[names[0]].shape
    chlist = b"".join(n.encode() + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for n in names)
    box = struct.pack("<4i", 0, 0, w - 1, h - 1)
    header = (b"\x76\x2f\x31\x01" + struct.pack("<I", 2) +
              _attr("channels", "chlist", chlist + b"\0") +
              _attr("compression", "compression", bytes([3])) +
              _attr("dataWindow", "box2i", box) + _attr("displayWindow", "box2i", box) +
              _attr("lineOrder", "lineOrder", bytes([0])) +
              _attr("pixelAspectRatio", "float", struct.pack("<f", 1.0)) +
              _attr("screenWindowCenter", "v2f", struct.pack("<2f", 0.0, 0.0)) +
              _attr("screenWindowWidth", "float", struct.pack("<f", 1.0)) + b"\0")
    arrays = [np.ascontiguousarray(channels[n], np.float32) for n in names]
    chunks = []
    for y in range(0, h, 16):
        raw = b"".join(a[line].tobytes() for line in range(y, min(y + 16, h)) for a in arrays)
        chunks.append(struct.pack("<ii", y, 0) + _zip(raw))
        chunks[-1] = chunks[-1][:4] + struct.pack("<i", len(chunks[-1]) - 8) + chunks[-1][8:]
    offsets, pos = [], len(header) + 8 * len(chunks)
    for c in chunks:
        offsets.append(pos)
        pos += len(c)
    tmp = path + ".partial"
    with open(tmp, "wb") as f:
        f.write(header + struct.pack("<%dQ" % len(offsets), *offsets) + b"".join(chunks))
    os.replace(tmp, path)


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if argv else 2
    for name, a in read_exr(argv[0]).items():
        print("%-28s %dx%d  min %.6g  max %.6g  mean %.6g" % (name, a.shape[1], a.shape[0],
                                                            a.min(), a.max(), a.mean()))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
