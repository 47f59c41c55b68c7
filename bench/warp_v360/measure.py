"""Accuracy of fisheye images against a reference (bench/warp_v360/run): mean absolute
difference and bias in 8-bit sRGB over the image circle and over its rim (r > 0.9 of the
radius), printed as a markdown table; with --crops DIR, crops at the rim (the reference's most
detailed block there) of the reference, the first image and v360's lanczos one (else its first), enlarged 2x,
as PNGs."""
import argparse
import os

import numpy as np
import OpenImageIO as oiio


def read(path):
    i = oiio.ImageInput.open(path)
    if i is None:
        raise SystemExit(f"cannot read {path}: {oiio.geterror()}")
    a = i.read_image(format="uint8")
    i.close()
    return a[..., :3].astype(np.float64)


def write(path, a):
    big = np.repeat(np.repeat(a, 2, axis=0), 2, axis=1).astype(np.uint8)
    out = oiio.ImageOutput.create(path)
    out.open(path, oiio.ImageSpec(big.shape[1], big.shape[0], 3, "uint8"))
    out.write_image(big)
    out.close()


def main():
    p = argparse.ArgumentParser()
    p.add_argument("reference")
    p.add_argument("images", nargs="+")
    p.add_argument("--crops")
    p.add_argument("--prefix", default="warp_v360_", help="of the crops' file names")
    a = p.parse_args()
    ref = read(a.reference)
    h, w = ref.shape[:2]
    y, x = np.mgrid[0:h, 0:w]
    r = np.hypot((x + 0.5) / w - 0.5, (y + 0.5) / h - 0.5) * 2
    disc, rim = r < 0.995, (r > 0.9) & (r < 0.995)
    print("| image | mean abs diff (circle) | bias (circle) | mean abs diff (rim) |")
    print("|---|---:|---:|---:|")
    for path in a.images:
        d = read(path) - ref
        print(f"| {os.path.basename(path)} | {np.abs(d[disc]).mean():.3f} | "
              f"{d[disc].mean():+.3f} | {np.abs(d[rim]).mean():.3f} |")
    if a.crops:
        # The most detailed 128 x 128 block of the reference centered 80 px inside the rim.
        n = 128
        blocks = []
        for t in np.linspace(0, 2 * np.pi, 72, endpoint=False):
            cx, cy = (int(w / 2 + (w / 2 - 80) * np.cos(t)), int(h / 2 + (h / 2 - 80) * np.sin(t)))
            blocks.append((ref[cy - n // 2:cy + n // 2, cx - n // 2:cx + n // 2].std(),
                           cx - n // 2, cy - n // 2))
        _, x0, y0 = max(blocks)
        print(f"crops: {n} x {n} at x = {x0}, y = {y0}")
        crop = lambda img: img[y0:y0 + n, x0:x0 + n]
        v360s = [i for i in a.images if "v360" in os.path.basename(i)]
        v360 = next((i for i in v360s if "lanczos" in i), v360s[0])  # (lanczos when there)
        for name, img in (("reference", ref), ("anamorph", read(a.images[0])),
                          ("v360", read(v360))):
            write(os.path.join(a.crops, f"{a.prefix}{name}.png"), crop(img))


if __name__ == "__main__":
    main()
