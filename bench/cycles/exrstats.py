# Statistics of linear EXR images, run inside Blender (its image reader and numpy):
#   blender -b --factory-startup --python exrstats.py -- mean FILE
#       the mean of the first channel (Cycles' sample-count pass: samples per pixel)
#   blender -b --factory-startup --python exrstats.py -- bias A.exr B.exr [BLOCK]
#       relative differences of A against B that noise averages out: of the image means of R, G
#       and B, and the mean over BLOCKxBLOCK blocks of |mean_A - mean_B| / (mean_B + 0.01).
import sys

import bpy
import numpy as np


def load(path):
    img = bpy.data.images.load(path)
    img.colorspace_settings.name = "Non-Color"  # raw float values
    w, h = img.size
    px = np.empty(w * h * 4, dtype=np.float32)
    img.pixels.foreach_get(px)
    return px.reshape(h, w, 4)[::-1].astype(np.float64)  # top row first


def main():
    argv = sys.argv[sys.argv.index("--") + 1:]
    if argv[0] == "mean":
        print(f"EXRSTATS_MEAN {load(argv[1])[..., 0].mean():.6g}")
        return
    a, b = load(argv[1])[..., :3], load(argv[2])[..., :3]
    k = int(argv[3]) if len(argv) > 3 else 8
    ma, mb = a.mean(axis=(0, 1)), b.mean(axis=(0, 1))
    rel = (ma - mb) / mb
    h, w = (a.shape[0] // k) * k, (a.shape[1] // k) * k
    ba = a[:h, :w].reshape(h // k, k, w // k, k, 3).mean(axis=(1, 3))
    bb = b[:h, :w].reshape(h // k, k, w // k, k, 3).mean(axis=(1, 3))
    block = (np.abs(ba - bb) / (np.abs(bb) + 0.01)).mean()
    print(f"EXRSTATS_MEANREL {rel[0]:+.4f} {rel[1]:+.4f} {rel[2]:+.4f}")
    print(f"EXRSTATS_BLOCKREL {block:.4f}")


main()
