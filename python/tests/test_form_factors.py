"""Form factors and radiosity from Python (Scene.form_factors): the closed form for coaxial
discs, shapes of the result, errors, and the radiosity check against the path tracer."""

from __future__ import annotations

import numpy as np
import pytest

import anamorph


def test_form_factors_of_coaxial_discs_match_the_closed_form():
    scene = anamorph.loads("""
[[object]]
type = "disk"
name = "d1"
radius = 1
[[object]]
type = "disk"
name = "d2"
radius = 0.6
transform = { rotate = [180, 1, 0, 0], translate = [0, 0.8, 0] }
""")
    f = scene.form_factors(samples=1024)
    assert f["columns"] == ["d1", "d2", "environment"] and f["rows"] == ["d1", "d2"]
    R1, R2 = 1 / 0.8, 0.6 / 0.8
    X = 1 + (1 + R2 ** 2) / R1 ** 2
    F12 = 0.5 * (X - np.sqrt(X * X - 4 * (R2 / R1) ** 2))
    assert abs(f["F"][0, 1] - F12) <= 3 * f["stderr"][0, 1], (f["F"][0, 1], f["stderr"][0, 1])
    np.testing.assert_allclose(f["F"].sum(axis=1), 1, atol=1e-12)
    np.testing.assert_allclose(f["areas"], [np.pi, np.pi * 0.36], rtol=1e-12)
    with pytest.raises(ValueError, match="no object named 'd3'"):
        scene.form_factors(objects=["d3"])


def test_radiosity_of_concentric_spheres_agrees_with_the_path_tracer(root):
    scene = anamorph.load(root / "examples/apps/radiosity_spheres.toml")
    f = scene.form_factors(samples=512, rays=64, inward=["dome"], radiosity=True)
    L = f["radiosity"] / np.pi
    err = np.abs(L - f["path_radiance"]) - 4 * f["path_radiance_stderr"] - 0.01 * L
    assert (err <= 0).all(), (L, f["path_radiance"], f["path_radiance_stderr"])
