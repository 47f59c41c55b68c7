#!/usr/bin/python3
"""Projects world points with an exported calibration through independent code, for
calib_cli_test: `opencv FILE` uses cv2.projectPoints / cv2.fisheye.projectPoints on the
FileStorage file; `colmap DIR` parses cameras.txt and images.txt per COLMAP's documented text
format and applies COLMAP's camera models (written out here with numpy); `kalibr FILE` reads
the camchain with PyYAML and projects with cv2. Points come as
X,Y,Z arguments; prints one "px py" line per point in anamorph's pixel units (u W, v H: the
top-left pixel's centre at (0.5, 0.5), as `anamorph project` prints them)."""
import sys

import numpy as np


def opencv(path, pts):
    import cv2
    fs = cv2.FileStorage(path, cv2.FILE_STORAGE_READ)
    K = fs.getNode("camera_matrix").mat()
    D = fs.getNode("distortion_coefficients").mat()
    rvec, tvec = fs.getNode("rvec").mat(), fs.getNode("tvec").mat()
    if rvec is None:  # (a file of OpenCV's calibration samples: no pose)
        rvec, tvec = np.zeros(3), np.zeros(3)
    model = fs.getNode("distortion_model").string()
    if model == "fisheye" or fs.getNode("fisheye_model").real() == 1:
        out, _ = cv2.fisheye.projectPoints(pts.reshape(-1, 1, 3), rvec, tvec, K, D.reshape(-1))
    else:
        out, _ = cv2.projectPoints(pts, rvec, tvec, K, D)
    return out.reshape(-1, 2) + 0.5  # OpenCV puts the top-left pixel's centre at 0


def quat_to_r(w, x, y, z):
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def data_lines(path):
    with open(path) as f:
        return [l.split() for l in f if l.strip() and not l.startswith("#")]


def colmap(d, pts):
    cam = data_lines(d + "/cameras.txt")[0]  # CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]
    model, p = cam[1], [float(v) for v in cam[4:]]
    img = data_lines(d + "/images.txt")[0]  # IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME
    R = quat_to_r(*[float(v) for v in img[1:5]])
    t = np.array([float(v) for v in img[5:8]])
    res = []
    for X in pts:
        c = R @ X + t
        x, y = c[0] / c[2], c[1] / c[2]
        fx, fy, cx, cy = p[:4]
        if model in ("OPENCV", "FULL_OPENCV"):
            k1, k2, p1, p2 = p[4:8]
            k3, k4, k5, k6 = p[8:12] if model == "FULL_OPENCV" else (0, 0, 0, 0)
            r2 = x * x + y * y
            rad = (1 + r2 * (k1 + r2 * (k2 + r2 * k3))) / (1 + r2 * (k4 + r2 * (k5 + r2 * k6)))
            x, y = (x * rad + 2 * p1 * x * y + p2 * (r2 + 2 * x * x),
                    y * rad + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y)
        elif model == "OPENCV_FISHEYE":
            r = np.hypot(x, y)
            th = np.arctan(r)
            td = th * (1 + th**2 * (p[4] + th**2 * (p[5] + th**2 * (p[6] + th**2 * p[7]))))
            s = td / r if r > 0 else 1.0
            x, y = x * s, y * s
        elif model != "PINHOLE":
            raise SystemExit("unexpected COLMAP model " + model)
        res.append((fx * x + cx, fy * y + cy))  # COLMAP: top-left pixel centre at 0.5
    return np.array(res)


def kalibr(path, pts):
    """Kalibr's camchain (PyYAML), projected by cv2: radtan is cv2.projectPoints' k1 k2 p1 p2,
    equidistant cv2.fisheye's k1..k4; T_cam_imu takes the points to the camera."""
    import cv2
    import yaml
    with open(path) as f:
        cam = yaml.safe_load(f)["cam0"]
    assert cam["camera_model"] == "pinhole"
    fu, fv, pu, pv = cam["intrinsics"]
    K = np.array([[fu, 0, pu], [0, fv, pv], [0, 0, 1]], dtype=np.float64)
    D = np.array(cam["distortion_coeffs"], dtype=np.float64)
    T = np.array(cam["T_cam_imu"], dtype=np.float64)
    rvec, _ = cv2.Rodrigues(T[:3, :3])
    tvec = T[:3, 3].copy()
    if cam["distortion_model"] == "equidistant":
        out, _ = cv2.fisheye.projectPoints(pts.reshape(-1, 1, 3), rvec, tvec, K, D)
    else:
        assert cam["distortion_model"] == "radtan"
        out, _ = cv2.projectPoints(pts, rvec, tvec, K, D)
    return out.reshape(-1, 2) + 0.5  # OpenCV's (and Kalibr's) top-left pixel centre at 0


def main():
    kind, path = sys.argv[1], sys.argv[2]
    pts = np.array([[float(v) for v in a.split(",")] for a in sys.argv[3:]], dtype=np.float64)
    out = {"opencv": opencv, "colmap": colmap, "kalibr": kalibr}[kind](path, pts)
    for px, py in out:
        print(f"{px!r} {py!r}")


if __name__ == "__main__":
    main()
