#!/usr/bin/env python3
"""Regenerates the tiny image fixtures used by tests/io (standard library only).

Written independently of anamorph's own encoders so the tests check the reader against
files it did not produce."""
import struct
import zlib
from pathlib import Path

here = Path(__file__).resolve().parent


def chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def png(width, height, bit_depth, color_type, rows) -> bytes:
    ihdr = struct.pack(">IIBBBBB", width, height, bit_depth, color_type, 0, 0, 0)
    raw = b"".join(b"\x00" + r for r in rows)  # filter type 0 per row
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw))
            + chunk(b"IEND", b""))


# 3x1 8-bit grey: 0, 188, 255.
(here / "grey.png").write_bytes(png(3, 1, 8, 0, [bytes([0, 188, 255])]))
# 1x1 16-bit grey: 0x8000.
(here / "grey16.png").write_bytes(png(1, 1, 16, 0, [struct.pack(">H", 0x8000)]))
# A valid start (signature and IHDR) followed by garbage instead of image data.
good = png(4, 4, 8, 2, [bytes(12)] * 4)
(here / "corrupt.png").write_bytes(good[:33] + b"\x00\x00\x00\x10IDATgarbage-garbage-garbage")
# 2x1 Radiance HDR, flat RGBE: (0.5, 1, 2) and (0.25, 0.125, 3), both exponent 2 (E=130).
(here / "tiny.hdr").write_bytes(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n"
                                + bytes([32, 64, 128, 130, 16, 8, 192, 130]))
