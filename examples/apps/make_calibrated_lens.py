#!/usr/bin/env python3
"""Writes the [camera.dir] table of calibrated_lens.toml: a 40 x 30 grid of ray directions of a
made-up real lens, the kind of per-pixel direction grid a generic calibration produces (Schops
et al., CVPR 2020: "Why having 10,000 parameters in your camera model is better than twelve").

The lens: 120 degrees across, strong barrel distortion (theta = atan(r) bent by a polynomial),
its optical axis 2 degrees off the image center (decentering), and a ripple of 0.4 degrees from
a moulded element, a term no 12-parameter model holds. Sample (i, j) is the direction at the
pixel center ((i + 0.5) / 40, (j + 0.5) / 30). Run: python3 make_calibrated_lens.py > table.toml
"""
import math

W, H = 40, 30
HALF_WIDTH = math.tan(math.radians(60))  # the undistorted half width at r = 1


def direction(u, v):
    x = (2 * u - 1) * HALF_WIDTH
    y = (1 - 2 * v) * HALF_WIDTH * H / W
    r = math.hypot(x, y)
    theta = math.atan(r) * (1 + 0.12 * r * r - 0.02 * r ** 4)  # barrel
    theta += math.radians(0.4) * math.sin(7 * u) * math.cos(5 * v)  # the ripple
    phi = math.atan2(y, x)
    d = (math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), -math.cos(theta))
    tilt = math.radians(2)  # decentering: the axis leans right
    return (d[0] * math.cos(tilt) - d[2] * math.sin(tilt), d[1],
            d[0] * math.sin(tilt) + d[2] * math.cos(tilt))


def main():
    print("[camera.dir]")
    print('type = "table"')
    print("samples = [")
    for j in range(H):
        row = ", ".join("[%.9f, %.9f, %.9f]" % direction((i + 0.5) / W, (j + 0.5) / H)
                        for i in range(W))
        print("  [" + row + "],")
    print("]")


if __name__ == "__main__":
    main()
