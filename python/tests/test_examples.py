"""The examples in examples/python run, at reduced sizes, and say what they should: the
OpenCV round trip recovers the intrinsics the checkerboard was rendered with."""

from __future__ import annotations

import os
import subprocess
import sys

from conftest import ROOT

EXAMPLES = ROOT / "examples/python"


def run(name: str, *args: str, out) -> str:
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path), MPLBACKEND="Agg")
    p = subprocess.run([sys.executable, EXAMPLES / name, "--out", out, *args],
                       capture_output=True, text=True, env=env)
    assert p.returncode == 0, p.stdout + p.stderr
    return p.stdout


def test_distortion_map(tmp_path):
    out = run("distortion_map.py", "--width", "160", "--height", "120", out=tmp_path)
    assert (tmp_path / "distortion_map.png").stat().st_size > 1000
    lo, hi = (float(x) for x in out.split("from ")[1].split(" (")[0].split(" to "))
    # The coins magnify (above 1) at their centres and compress around them (below 1).
    assert lo < 1 < hi, out


def test_coin_sweep(tmp_path):
    run("coin_sweep.py", "--width", "96", "--height", "72", "--steps", "3", out=tmp_path)
    assert (tmp_path / "coin_sweep.png").stat().st_size > 1000


def test_opencv_recovers_the_rendered_intrinsics(tmp_path):
    run("opencv_roundtrip.py", "--spp", "8", out=tmp_path)
    lines = (tmp_path / "opencv_roundtrip.txt").read_text().split("\n")
    values = {k: [float(x) for x in v] for k, *v in (line.split() for line in lines if line)}
    for k in ("fx", "fy", "cx", "cy"):
        truth, got = values[k]
        assert abs(got - truth) < 0.25, f"{k}: rendered with {truth}, OpenCV recovered {got}"
    assert values["rms"][0] < 0.25, values["rms"]
    assert values["radial_px"][0] < 0.5, values["radial_px"]
