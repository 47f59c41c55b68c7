"""Scattered-data cameras against SciPy's RBFInterpolator (the reference the issue names): the
planar interpolant of org `scattered` and the chordal-distance interpolant over the sphere of dir
`scattered_sphere`, on random data, to 1e-9."""

from __future__ import annotations

import numpy as np
import pytest

import anamorph

scipy_interpolate = pytest.importorskip("scipy.interpolate")

# Our kernel names -> SciPy's, and the polynomial degree each takes (the minimum SciPy allows).
KERNELS = {"thin_plate": ("thin_plate_spline", 1), "cubic": ("cubic", 1),
           "multiquadric": ("multiquadric", 0), "gaussian": ("gaussian", -1),
           "inverse_multiquadric": ("inverse_multiquadric", -1)}


def rel_error(got: np.ndarray, want: np.ndarray) -> float:
    return float(np.abs(got - want).max() / max(1.0, np.abs(want).max()))


@pytest.mark.parametrize("kernel", KERNELS)
@pytest.mark.parametrize("smoothing", [0.0, 0.01])
def test_scattered_surface_equals_scipy(kernel, smoothing):
    rng = np.random.default_rng(20261124)
    data = np.c_[rng.random((30, 2)), rng.normal(size=(30, 3))]
    scipy_kernel, degree = KERNELS[kernel]
    cam = anamorph.Camera(org=anamorph.org.scattered(points=data.tolist(), kernel=kernel, shape=2.5,
                                                     smoothing=smoothing),
                          dir=anamorph.dir.constant())
    u, v = rng.random(2000), rng.random(2000)
    got = cam.generate(u, v)["org"]
    want = scipy_interpolate.RBFInterpolator(data[:, :2], data[:, 2:], kernel=scipy_kernel,
                                             degree=degree, epsilon=2.5,
                                             smoothing=smoothing)(np.c_[u, v])
    err = rel_error(got, want)
    assert err < 1e-9, f"{kernel}, smoothing {smoothing}: largest relative difference {err:.3g}"


def fisheye_layout(u: np.ndarray, v: np.ndarray, fov_degrees: float) -> np.ndarray:
    """The equidistant layout of scattered_sphere: angle from -z proportional to the radius."""
    x, y = 2 * u - 1, 1 - 2 * v
    r = np.hypot(x, y)
    t = np.radians(fov_degrees) / 2 * r
    s = np.where(r > 0, np.sin(t) / np.where(r > 0, r, 1), 0)
    return np.c_[s * x, s * y, -np.cos(t)]


@pytest.mark.parametrize("kernel", KERNELS)
def test_scattered_sphere_equals_scipy_over_the_sphere(kernel):
    rng = np.random.default_rng(7)
    # Samples inside the image circle, each asking for a direction near its layout direction.
    uv = 0.5 + 0.35 * (rng.random((12, 2)) - 0.5) * 2
    base = fisheye_layout(uv[:, 0], uv[:, 1], 200)
    want_dirs = base + 0.3 * rng.normal(size=base.shape)
    data = np.c_[uv, want_dirs]
    scipy_kernel, degree = KERNELS[kernel]
    cam = anamorph.Camera(org=anamorph.org.point(),
                          dir=anamorph.dir.scattered_sphere(points=data.tolist(), fov=200,
                                                            kernel=kernel, shape=1.5))
    u, v = 0.5 + 0.3 * (rng.random((2, 1500)) - 0.5) * 2
    got = cam.generate(u, v)["dir"]
    # SciPy interpolates the samples' offsets from the layout over the sphere (sites = layout
    # directions, distances = chords); the camera adds the layout back and normalizes.
    unit = want_dirs / np.linalg.norm(want_dirs, axis=1, keepdims=True)
    offsets = scipy_interpolate.RBFInterpolator(base, unit - base, kernel=scipy_kernel,
                                                degree=degree, epsilon=1.5)
    b = fisheye_layout(u, v, 200)
    f = b + offsets(b)
    want = f / np.linalg.norm(f, axis=1, keepdims=True)
    err = rel_error(got, want)
    assert err < 1e-9, f"{kernel}: largest difference {err:.3g}"
    # And every sample's direction is met.
    at = cam.generate(uv[:, 0], uv[:, 1])["dir"]
    assert rel_error(at, unit) < 1e-12

