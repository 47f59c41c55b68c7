#!/usr/bin/python3
"""examples/vision/make_dataset.sh, run for real at a small size (frames 0..1, 64 x 64), and its
dataset checked:
  * every file the script names exists (PNG + EXR per frame, the three calibrations);
  * each EXR has the channels of every layer, its `anamorph.layer.NAME` definition and
    `anamorph.frame`; a pixel has a hit (id >= 0) exactly where distance and depth_z are finite,
    and its normal is a unit vector there;
  * the calibrations: world points in front of the camera are projected by cv2 from
    camera_opencv.yml, by cv2 after Kalibr's T_cam_imu from camchain.yaml and by COLMAP's model
    from colmap/ (tests/app/calib_check.py), and each agrees with `anamorph project` of the scene
    with the shutter closed within 1e-9 px (`project --json` prints every digit); `calib --import` of
    the OpenCV and Kalibr files gives a camera that `anamorph project` agrees with as well;
  * the flow: for every pixel of frame 0 with valid forward flow, frame 1's backward flow at the
    pixel it flows to (bilinear over valid pixels) brings it back (forward-backward consistency)
    and frame 1 sees the same object there (id).
Exit 77 (skipped) when numpy, cv2, yaml or OpenImageIO is missing.
Usage: vision_dataset_test.py ANAMORPH SOURCE_DIR WORK_DIR"""
import json
import os
import shutil
import subprocess
import sys

try:
    import cv2
    import numpy as np
    import OpenImageIO as oiio
    import yaml
except ImportError as e:
    print(f"SKIP: {e} (Debian: python3-numpy, python3-opencv, python3-openimageio, python3-yaml)")
    sys.exit(77)
del yaml  # (calib_check.py reads the Kalibr file with it)

LAYERS = {"distance": ["D"], "depth_z": ["Z"], "normal": ["X", "Y", "Z"], "id": ["id"],
          "flow_forward": ["X", "Y", "valid"], "flow_backward": ["X", "Y", "valid"],
          "motion": ["X", "Y", "Z", "W"]}
SIZE, FRAMES = 64, 2
CLOSED = ["--set", "camera.shutter=[0, 0]", "--set", "camera.rolling_shutter=none"]
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)


def run(*args):
    r = subprocess.run([str(a) for a in args], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"FAIL: {' '.join(map(str, args))} exited {r.returncode}:\n{r.stdout}{r.stderr}")
    return r.stdout


def read_exr(path):
    inp = oiio.ImageInput.open(path)
    if inp is None:
        sys.exit(f"FAIL: cannot open {path}: {oiio.geterror()}")
    spec = inp.spec()
    pixels = inp.read_image(oiio.FLOAT)
    inp.close()
    ch = {n: pixels[:, :, i] for i, n in enumerate(spec.channelnames)}
    attrs = {a.name: a.value for a in spec.extra_attribs}
    return ch, attrs


def check_frame(out, f):
    path = os.path.join(out, f"frame_{f:04d}.exr")
    ch, attrs = read_exr(path)
    for layer, comps in LAYERS.items():
        for c in comps:
            check(f"{layer}.{c}" in ch, f"{path}: channel {layer}.{c} (has {sorted(ch)})")
        check(len(attrs.get(f"anamorph.layer.{layer}", "")) > 20,
              f"{path}: attribute anamorph.layer.{layer} with its definition")
    frame = attrs.get("anamorph.frame")
    check(frame == str(f), f"{path}: anamorph.frame {frame}")
    hit = ch["id.id"] >= 0
    check(0 < hit.sum() < hit.size, f"{path}: {hit.sum()} of {hit.size} pixels hit")
    for name in ("distance.D", "depth_z.Z"):
        bad = (np.isfinite(ch[name]) != hit).sum()
        check(bad == 0, f"{path}: {bad} pixels where {name} is finite but nothing is hit or back")
    n = np.sqrt(ch["normal.X"] ** 2 + ch["normal.Y"] ** 2 + ch["normal.Z"] ** 2)[hit]
    check(np.abs(n - 1).max() < 1e-4, f"{path}: normals' lengths in [{n.min()}, {n.max()}]")
    return ch


def project(bin, scene, pt, extra):
    out = run(bin, "project", scene, "--width", SIZE, "--height", SIZE, *extra, "--json",
              "--point", ",".join(map(repr, pt)))
    return json.loads(out)["pixels"][0]  # every digit


def check_calibration(bin, src, out):
    scene = os.path.join(src, "examples/vision/sequence.toml")
    fs = cv2.FileStorage(os.path.join(out, "camera_opencv.yml"), cv2.FILE_STORAGE_READ)
    R, _ = cv2.Rodrigues(fs.getNode("rvec").mat())
    centre = -R.T @ fs.getNode("tvec").mat().reshape(3)
    # Directions 0..75 degrees off the axis (OpenCV's fisheye model covers < 90), 2..9 units away.
    pts = []
    for k in range(8):
        th, ph = np.radians(75) * k / 7, 2.4 * k
        d = np.array([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)])
        pts.append(centre + R.T @ d * (2 + k))
    ref = np.array([project(bin, scene, p, CLOSED) for p in pts])
    checker = os.path.join(src, "tests/app/calib_check.py")
    args = [",".join(map(repr, p)) for p in pts]
    for kind, f in (("opencv", "camera_opencv.yml"), ("kalibr", "camchain.yaml"),
                    ("colmap", "colmap")):
        lines = run(sys.executable, checker, kind, os.path.join(out, f), *args).splitlines()
        got = np.array([[float(v) for v in line.split()] for line in lines])
        worst = np.abs(got - ref).max()
        print(f"{kind}: worst difference from anamorph project {worst:.3g} px, {len(pts)} points")
        check(worst < 1e-9, f"{f}: projects {got.tolist()}, anamorph project {ref.tolist()}")
    for f in ("camera_opencv.yml", "camchain.yaml"):
        toml = os.path.join(out, f + ".toml")
        run(bin, "calib", "--import", os.path.join(out, f), "-o", toml)
        got = np.array([project(bin, toml, p, []) for p in pts])
        worst = np.abs(got - ref).max()
        print(f"calib --import {f}: worst difference {worst:.3g} px")
        check(worst < 1e-9, f"import of {f}: projects {got.tolist()}, scene {ref.tolist()}")


def bilinear_valid(img, valid, x, y):
    """img at the continuous pixel position (x, y) (pixel centres at integers), from the valid
    ones among the four neighbours; None when none is valid."""
    x0, y0 = int(np.floor(x)), int(np.floor(y))
    acc, wsum = 0.0, 0.0
    for yy, wy in ((y0, 1 - (y - y0)), (y0 + 1, y - y0)):
        for xx, wx in ((x0, 1 - (x - x0)), (x0 + 1, x - x0)):
            if 0 <= xx < SIZE and 0 <= yy < SIZE and valid[yy, xx] and wx * wy > 0:
                acc, wsum = acc + wx * wy * img[yy, xx], wsum + wx * wy
    return acc / wsum if wsum > 0 else None


def check_flow(f0, f1):
    valid0 = f0["flow_forward.valid"] == 1
    valid1 = f1["flow_backward.valid"] == 1
    errs, same_id, n = [], 0, 0
    for y, x in zip(*np.nonzero(valid0)):
        fx, fy = f0["flow_forward.X"][y, x], f0["flow_forward.Y"][y, x]
        tx, ty = x + fx, y + fy
        bx = bilinear_valid(f1["flow_backward.X"], valid1, tx, ty)
        by = bilinear_valid(f1["flow_backward.Y"], valid1, tx, ty)
        n += 1
        x0, y0 = int(np.floor(tx)), int(np.floor(ty))
        near = f1["id.id"][max(y0, 0):y0 + 2, max(x0, 0):x0 + 2]
        same_id += bool((near == f0["id.id"][y, x]).any())
        if bx is not None:
            errs.append(np.hypot(fx + bx, fy + by))
    errs = np.array(errs)
    mag = np.hypot(f0["flow_forward.X"], f0["flow_forward.Y"])[valid0]
    print(f"flow: {n} valid pixels of frame 0 (flow up to {mag.max():.2f} px), forward + backward "
          f"at the target: median {np.median(errs):.3g} px, 95th percentile "
          f"{np.percentile(errs, 95):.3g} px; same id among the target's 4 pixels: {same_id}")
    check(n > SIZE * SIZE // 3, f"flow: only {n} pixels with valid forward flow")
    check(mag.max() > 0.5, f"flow: largest forward flow {mag.max()} px (the camera moves)")
    check(len(errs) > 0.95 * n, f"flow: {len(errs)} of {n} targets with a valid backward flow")
    check(np.median(errs) < 0.02, f"flow: forward-backward median {np.median(errs)} px")
    check(np.percentile(errs, 95) < 0.2, f"flow: 95th percentile {np.percentile(errs, 95)} px")
    check(same_id > 0.99 * n, f"flow: {same_id} of {n} targets see the same object")


def main():
    bin, src, work = sys.argv[1:4]
    out = os.path.join(work, "dataset")
    shutil.rmtree(out, ignore_errors=True)
    run(os.path.join(src, "examples/vision/make_dataset.sh"), out, bin, f"0:{FRAMES - 1}", SIZE)
    names = [f"frame_{f:04d}.{e}" for f in range(FRAMES) for e in ("png", "exr")]
    names += ["camera_opencv.yml", "camchain.yaml", "colmap/cameras.txt", "colmap/images.txt",
              "colmap/points3D.txt"]
    for n in names:
        check(os.path.isfile(os.path.join(out, n)), f"{n} written")
    frames = [check_frame(out, f) for f in range(FRAMES)]
    check_calibration(bin, src, out)
    check_flow(frames[0], frames[1])
    if failures:
        sys.exit(f"{len(failures)} check(s) failed")
    print("the dataset holds")


if __name__ == "__main__":
    main()
