#!/usr/bin/python3
# Writes bench/cycles/sky_sun.hdr: a 256 x 128 equirectangular sky (a blue-to-white gradient
# above the horizon, dark grey below) with a small bright sun, 4 x 3 pixels (about 5.6 x 4.2
# degrees) of radiance 3000 at 35 degrees elevation: the sun carries most of the light, so an
# environment map that is not importance-sampled shows it as fireflies. Deterministic (no random
# numbers). Uses Debian's python3-openimageio: `bench/cycles/make_sky_sun.py`.
import os

import numpy as np
import OpenImageIO as oiio

W, H = 256, 128
img = np.zeros((H, W, 3), np.float32)
for y in range(H):
    elev = 90.0 - (y + 0.5) * 180.0 / H
    if elev > 0:
        t = elev / 90.0
        img[y, :] = (1 - t) * np.array([1.0, 1.0, 1.0]) + t * np.array([0.25, 0.45, 0.9])
    else:
        img[y, :] = [0.08, 0.08, 0.08]
sun_row = int((90.0 - 35.0) / 180.0 * H)  # 35 degrees up
sun_col = W // 2 + W // 8  # 45 degrees to the right of -z
img[sun_row - 1:sun_row + 2, sun_col - 2:sun_col + 2] = 3000.0
out = oiio.ImageOutput.create("sky_sun.hdr")
path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "sky_sun.hdr")
out.open(path, oiio.ImageSpec(W, H, 3, "float"))
out.write_image(img)
out.close()
