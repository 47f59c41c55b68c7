"""An OpenCV round trip: render a checkerboard through the `opencv_fisheye` preset from several
poses, find its corners with OpenCV, recover the intrinsics with cv2.fisheye.calibrate, and
compare them with the ones the scene was rendered with.

    scripts/python examples/python/opencv_roundtrip.py --out out/
"""

from __future__ import annotations

import argparse
import pathlib

import cv2
import numpy as np

import anamorph

SQUARES = (10, 7)  # squares across and down; OpenCV finds the (9, 6) inner corners (even x
#                   odd: the board has one orientation)
SQUARE = 0.1      # side of a square (scene units)
TRUTH = dict(fx=230.0, fy=228.0, cx=319.5, cy=239.5, k1=0.04, k2=-0.012, k3=0.003, k4=-0.0005)


def board_scene() -> str:
    """A checkerboard in the z = 0 plane, corners at multiples of SQUARE (the checker texture's
    edges), on a larger white card so OpenCV sees a quiet border."""
    w, h = SQUARES[0] * SQUARE, SQUARES[1] * SQUARE
    return f"""
[render]
integrator = "albedo"
sampler = "stratified"

[[material]]
name = "board"
color = {{ type = "checker", scale = {SQUARE}, color_a = 0.02, color_b = 0.9 }}

[[material]]
name = "card"
color = 0.9

[[object]]
type = "box"
min = [0, 0, -0.01]
max = [{w}, {h}, 0]
material = "board"

[[object]]
type = "box"
min = [{-SQUARE}, {-SQUARE}, -0.03]
max = [{w + SQUARE}, {h + SQUARE}, -0.02]
material = "card"
"""


def poses(n: int) -> list[tuple[list[float], list[float]]]:
    """Eye positions around the board, each looking at a point on it, so the board falls in
    the image's centre and its wide-angle edges."""
    rng = np.random.default_rng(1)
    center = np.array([SQUARES[0] * SQUARE / 2, SQUARES[1] * SQUARE / 2, 0])
    out = []
    for i in range(n):
        eye = center + [rng.uniform(-0.5, 0.5), rng.uniform(-0.4, 0.4), rng.uniform(0.35, 0.7)]
        # Look past the board to put it off-centre, where the lens distorts most.
        target = center + [rng.uniform(-0.6, 0.6), rng.uniform(-0.45, 0.45), 0]
        out.append((eye.tolist(), target.tolist()))
    return out


def calibrate(objects: list, images: list, used: list[int], size: tuple[int, int]):
    """cv2.fisheye.calibrate over the views; when its initialisation fails on a view (an
    assertion in InitExtrinsics, for a view too oblique for its homography), without that one."""
    flags = cv2.fisheye.CALIB_RECOMPUTE_EXTRINSIC | cv2.fisheye.CALIB_FIX_SKEW
    criteria = (cv2.TERM_CRITERIA_COUNT + cv2.TERM_CRITERIA_EPS, 200, 1e-12)
    for drop in [None, *range(len(used))]:
        keep = [i for i in range(len(used)) if i != drop]
        try:
            rms, K, D, _, _ = cv2.fisheye.calibrate(
                [objects[i] for i in keep], [images[i] for i in keep], size, np.eye(3),
                np.zeros((4, 1)), flags=flags, criteria=criteria)
            return rms, K, D, [used[i] for i in keep]
        except cv2.error:
            continue
    raise SystemExit("cv2.fisheye.calibrate failed on every subset of the views")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=pathlib.Path, default=pathlib.Path("."))
    ap.add_argument("--views", type=int, default=12)
    ap.add_argument("--spp", type=int, default=16)
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    width, height = 640, 480
    pattern = (SQUARES[0] - 1, SQUARES[1] - 1)
    grid = np.zeros((pattern[0] * pattern[1], 1, 3), np.float64)
    # OpenCV lists corners row by row as the image shows them: x to the right, then rows
    # downward, which is -y on a board seen from +z with +y up (the same handedness).
    xs, ys = np.meshgrid(np.arange(1, pattern[0] + 1), np.arange(pattern[1], 0, -1))
    grid[:, 0, 0], grid[:, 0, 1] = xs.reshape(-1) * SQUARE, ys.reshape(-1) * SQUARE

    scene_text = board_scene()
    objects, images, used = [], [], []
    for i, (eye, target) in enumerate(poses(args.views)):
        scene = anamorph.loads(scene_text, set={
            "image.width": width, "image.height": height, "camera.preset": "opencv_fisheye",
            "camera.look_from": eye, "camera.look_at": target, **{f"camera.{k}": v
                                                                   for k, v in TRUTH.items()}})
        rgba = scene.render(spp=args.spp)["rgba"]
        grey = (np.clip(rgba[..., 0], 0, 1) ** (1 / 2.2) * 255).astype(np.uint8)
        found, corners = cv2.findChessboardCorners(grey, pattern)
        if not found:
            continue
        corners = cv2.cornerSubPix(grey, corners, (5, 5), (-1, -1),
                                   (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER, 100, 1e-4))
        objects.append(grid)
        images.append(corners.reshape(-1, 1, 2).astype(np.float64))
        used.append(i)
        if len(used) == 1:
            shown = cv2.cvtColor(grey, cv2.COLOR_GRAY2BGR)
            cv2.drawChessboardCorners(shown, pattern, corners, True)
            cv2.imwrite(str(args.out / "opencv_corners.png"), shown)
    if len(used) < 3:
        raise SystemExit(f"only {len(used)} of {args.views} views showed the whole board")

    rms, K, D, used = calibrate(objects, images, used, (width, height))
    got = dict(fx=K[0, 0], fy=K[1, 1], cx=K[0, 2], cy=K[1, 2],
               k1=D[0, 0], k2=D[1, 0], k3=D[2, 0], k4=D[3, 0])
    print(f"{len(used)} of {args.views} views, reprojection RMS {rms:.4f} px")
    for k in TRUTH:
        print(f"  {k}: rendered with {TRUTH[k]:+.6g}, recovered {got[k]:+.6g} "
              f"(error {got[k] - TRUTH[k]:+.3g})")
    # Where the two lenses put rays: the recovered model's image of the truth's rays.
    theta = np.linspace(0, np.radians(80), 50)
    r = lambda c: theta * (1 + c["k1"] * theta**2 + c["k2"] * theta**4 + c["k3"] * theta**6 +
                           c["k4"] * theta**8)
    worst = np.max(np.abs(r(got) * got["fx"] - r(TRUTH) * TRUTH["fx"]))
    print(f"  radial image position of rays up to 80 degrees off axis differs by at most "
          f"{worst:.3f} px")
    (args.out / "opencv_roundtrip.txt").write_text(
        "\n".join(f"{k} {TRUTH[k]!r} {got[k]!r}" for k in TRUTH) + f"\nrms {rms!r}\n"
        f"radial_px {worst!r}\nviews {len(used)}\n")


if __name__ == "__main__":
    main()
