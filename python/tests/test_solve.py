"""Camera.solve: a perspective camera's fov and look_at recovered from pins it made (its own
Camera.project), the same numbers as `anamorph solve` on the same goals (one library, one
answer), and unmet goals raised by name."""

from __future__ import annotations

import math
import tomllib

import pytest

import anamorph
from conftest import cli

POINTS = [[1, 0, 0], [-1, 0.5, 0], [0.5, -0.5, 1]]


def pins(truth: anamorph.Camera) -> list[dict]:
    uv = truth.project(POINTS)
    return [{"kind": "pin", "point": p, "uv": uv.of(i)[0].tolist(), "tolerance": 1e-4}
            for i, p in enumerate(POINTS)]


def test_solve_recovers_fov_and_look_at_as_the_cli_does(tmp_path):
    truth = anamorph.Camera(look_from=[0, 1, 5], look_at=[0.3, 0.2, 0], fov=52, width=320,
                            height=240)
    start = anamorph.Camera(look_from=[0, 1, 5], look_at=[0, 0, 0], fov=40, width=320,
                            height=240)
    goals = pins(truth)
    free = ["camera.fov", "camera.look_at.0", {"key": "camera.look_at.1", "min": -1, "max": 1}]
    r = start.solve(goals, free)
    assert r.met
    values = {v["name"]: v["value"] for v in r.values}
    assert values["camera.fov"] == pytest.approx(52, abs=1e-6)
    assert values["camera.look_at.0"] == pytest.approx(0.3, abs=1e-6)
    assert values["camera.look_at.1"] == pytest.approx(0.2, abs=1e-6)
    # The solved camera shows each pinned point where the truth does.
    got, want = r.camera.project(POINTS), truth.project(POINTS)
    for i in range(len(POINTS)):
        d = (got.of(i)[0] - want.of(i)[0]) * [320, 240]
        assert math.hypot(*d) <= r.constraints[i]["residual"] + 1e-9, (i, got.of(i), want.of(i))
    # The CLI on the same goals writes the same numbers.
    text = ["[image]", "width = 320", "height = 240", "[camera]", start.toml]
    for g in goals:
        text += ["[[camera.constraint]]", 'kind = "pin"', f"point = {g['point']}",
                 f"uv = [{g['uv'][0]!r}, {g['uv'][1]!r}]", "tolerance = 1e-4"]
    text += ['[[camera.free]]\nkey = "camera.fov"', '[[camera.free]]\nkey = "camera.look_at.0"',
             '[[camera.free]]\nkey = "camera.look_at.1"\nmin = -1\nmax = 1']
    scene = tmp_path / "start.toml"
    scene.write_text("\n".join(text) + "\n")
    cli("solve", scene, "-o", tmp_path / "solved.toml")
    solved = tomllib.loads((tmp_path / "solved.toml").read_text())["camera"]
    assert solved["fov"] == values["camera.fov"]
    assert solved["look_at"][:2] == [values["camera.look_at.0"], values["camera.look_at.1"]]


def test_unmet_goals_raise_naming_the_conflict():
    cam = anamorph.Camera(look_from=[0, 1, 5], look_at=[0, 0, 0], fov=40)
    goals = [{"kind": "pin", "point": [1, 0, 0], "uv": [0.7, 0.5]},
             {"kind": "pin", "point": [1, 0, 0], "uv": [0.6, 0.5]}]
    with pytest.raises(ValueError, match=r"camera.constraint\[0\] \(pin\).*conflicts with "
                                         r"camera.constraint\[1\]"):
        cam.solve(goals, ["camera.fov"])
    r = cam.solve(goals, ["camera.fov"], check=False)
    assert not r.met and r.constraints[1]["conflicts"] == ["camera.constraint[0]"]
    with pytest.raises(anamorph.SceneError, match="not a declared key"):
        cam.solve(goals, ["camera.nothing"])
