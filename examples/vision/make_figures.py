#!/usr/bin/python3
"""The figures of docs/vision.md (for the docs, not needed to use the dataset): one PNG per layer
of frame 0 of a dataset from make_dataset.sh, written into OUT_DIR.
  rgb: the render; distance, depth_z: viridis over [0, the 98th percentile of distance], black
  where nothing is hit; normal: (n + 1) / 2 as RGB; id: a colour per object; flow_forward: the
  Middlebury colour wheel (Baker et al. 2011: hue = direction, saturation = magnitude normalized
  by the largest valid magnitude), black without flow; flow_valid: white where valid;
  flow_wheel: the wheel itself.
Usage: make_figures.py DATASET_DIR OUT_DIR   (e.g. after make_dataset.sh /tmp/v anamorph 0:1 320)
Needs numpy, cv2 and OpenImageIO (Debian: python3-opencv, python3-openimageio)."""
import os
import sys

import cv2
import numpy as np
import OpenImageIO as oiio


def read_exr(path):
    inp = oiio.ImageInput.open(path)
    spec = inp.spec()
    px = inp.read_image(oiio.FLOAT)
    inp.close()
    return {n: px[:, :, i] for i, n in enumerate(spec.channelnames)}


def colour_wheel():
    """Baker et al.'s wheel: 55 hues, red-yellow-green-cyan-blue-magenta, as RGB 0..1."""
    segs = [(15, (1, 0, 0), (1, 1, 0)), (6, (1, 1, 0), (0, 1, 0)), (4, (0, 1, 0), (0, 1, 1)),
            (11, (0, 1, 1), (0, 0, 1)), (13, (0, 0, 1), (1, 0, 1)), (6, (1, 0, 1), (1, 0, 0))]
    rows = []
    for n, a, b in segs:
        for i in range(n):
            t = i / n
            rows.append([a[c] + (b[c] - a[c]) * t for c in range(3)])
    return np.array(rows)


def flow_to_rgb(fx, fy, valid, max_mag):
    wheel = colour_wheel()
    ncols = len(wheel)
    mag = np.hypot(fx, fy) / max_mag
    ang = np.arctan2(-fy, -fx) / np.pi  # (-1, 1], as Middlebury's computeColor
    k = (ang + 1) / 2 * (ncols - 1)
    k0 = np.floor(k).astype(int) % ncols
    k1 = (k0 + 1) % ncols
    f = (k - np.floor(k))[..., None]
    col = (1 - f) * wheel[k0] + f * wheel[k1]
    m = np.clip(mag, 0, 1)[..., None]
    col = 1 - m * (1 - col)  # saturation grows with magnitude, white at rest
    col[mag > 1] *= 0.75
    col[~valid] = 0
    return col


def viridis(v, lo, hi, hit):
    g = np.clip((v - lo) / (hi - lo), 0, 1)
    g = np.where(hit, g, 0)
    bgr = cv2.applyColorMap((g * 255).astype(np.uint8), cv2.COLORMAP_VIRIDIS)
    bgr[~hit] = 0
    return bgr


def write(out, name, bgr):
    path = os.path.join(out, name + ".png")
    cv2.imwrite(path, bgr, [cv2.IMWRITE_PNG_COMPRESSION, 9])
    print(f"{path}: {os.path.getsize(path)} bytes")


def main():
    data, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    ch = read_exr(os.path.join(data, "frame_0000.exr"))
    write(out, "rgb", cv2.imread(os.path.join(data, "frame_0000.png")))
    hit = ch["id.id"] >= 0
    hi = np.percentile(ch["distance.D"][hit], 98)
    write(out, "distance", viridis(ch["distance.D"], 0, hi, hit))
    write(out, "depth_z", viridis(ch["depth_z.Z"], 0, hi, hit))
    n = np.stack([ch["normal.X"], ch["normal.Y"], ch["normal.Z"]], -1)
    rgb = np.where(hit[..., None], (n + 1) / 2, 0)
    write(out, "normal", (rgb[..., ::-1] * 255).round().astype(np.uint8))
    ids = ch["id.id"].astype(int)
    hue = ((ids * 0.618034) % 1 * 179).astype(np.uint8)
    hsv = np.stack([hue, np.full_like(hue, 200), np.where(hit, 230, 0).astype(np.uint8)], -1)
    write(out, "id", cv2.cvtColor(hsv, cv2.COLOR_HSV2BGR))
    valid = ch["flow_forward.valid"] == 1
    fx, fy = np.nan_to_num(ch["flow_forward.X"]), np.nan_to_num(ch["flow_forward.Y"])
    max_mag = np.hypot(fx, fy)[valid].max()
    print(f"largest valid forward flow {max_mag:.3f} px")
    rgb = flow_to_rgb(fx, fy, valid, max_mag)
    write(out, "flow_forward", (rgb[..., ::-1] * 255).round().astype(np.uint8))
    write(out, "flow_valid", np.where(valid, 255, 0).astype(np.uint8))
    s = 96
    y, x = np.mgrid[0:s, 0:s] + 0.5 - s / 2
    inside = np.hypot(x, y) <= s / 2
    rgb = flow_to_rgb(x, y, inside, s / 2)
    write(out, "flow_wheel", (rgb[..., ::-1] * 255).round().astype(np.uint8))


if __name__ == "__main__":
    main()
