"""Cameras from Python: ray fields equal to `anamorph rays` bit for bit, rays at samples equal
to the field, the inverse map, and keyword arguments checked by the scene reader."""

from __future__ import annotations

import json

import numpy as np
import pytest

import anamorph
from conftest import ROOT, cli, read_exr

SCENES = ["examples/apps/focus_context.toml", "examples/apps/fisheye_180.toml",
          "examples/paper/06.toml", "examples/apps/vr_ods.toml"]


def cli_rays(tmp_path, scene: str, width: int, height: int) -> np.ndarray:
    out = tmp_path / "rays.csv"
    cli("rays", ROOT / scene, "--width", width, "--height", height, "-o", out)
    return np.loadtxt(out, delimiter=",", skiprows=1, dtype=np.float64)


@pytest.mark.parametrize("scene", SCENES)
def test_rays_equal_the_cli_bit_for_bit(tmp_path, scene):
    w, h = 48, 36
    table = cli_rays(tmp_path, scene, w, h)
    rays = anamorph.load(ROOT / scene).camera.rays(w, h)
    valid = rays["valid"].reshape(-1)
    np.testing.assert_array_equal(valid, table[:, 10] == 1)
    for name, cols in (("org", slice(4, 7)), ("dir", slice(7, 10))):
        got = rays[name].reshape(-1, 3)[valid]
        want = table[valid][:, cols]
        bad = np.argwhere(got != want)
        assert bad.size == 0, f"{scene} {name}: first difference at ray {bad[0][0]}: " \
                              f"{got[bad[0][0]]} != {want[bad[0][0]]}"
    assert np.all(rays["org"][~rays["valid"]] == 0)


def test_generate_at_pixel_centers_equals_the_ray_field():
    cam = anamorph.load(ROOT / "examples/apps/focus_context.toml").camera.resized(40, 30)
    field = cam.rays()
    x, y = np.meshgrid((np.arange(40) + 0.5) / 40, (np.arange(30) + 0.5) / 30)
    rays = cam.generate(x, y)
    for k in field:
        np.testing.assert_array_equal(rays[k], field[k], err_msg=k)
    assert rays["dir"].shape == (30, 40, 3)


def test_directions_are_unit_and_differentials_match_finite_differences():
    cam = anamorph.Camera("fisheye", fov=180, width=64, height=64)
    u = np.array([0.3, 0.5, 0.62])
    v = np.array([0.4, 0.5, 0.55])
    r = cam.generate(u, v)
    np.testing.assert_allclose(np.linalg.norm(r["dir"], axis=-1), 1, atol=1e-12)
    eps = 1e-6
    du = (cam.generate(u + eps, v)["dir"] - cam.generate(u - eps, v)["dir"]) / (2 * eps)
    dv = (cam.generate(u, v + eps)["dir"] - cam.generate(u, v - eps)["dir"]) / (2 * eps)
    np.testing.assert_allclose(r["ddir_du"], du, atol=1e-6)
    np.testing.assert_allclose(r["ddir_dv"], dv, atol=1e-6)


@pytest.mark.parametrize("scene", ["examples/apps/fisheye_180.toml",
                                   "examples/apps/focus_context.toml"])
def test_project_round_trips_points_on_the_rays(scene):
    cam = anamorph.load(ROOT / scene).camera.resized(64, 48)
    rng = np.random.default_rng(7)
    u, v = rng.uniform(0.05, 0.95, 200), rng.uniform(0.05, 0.95, 200)
    r = cam.generate(u, v, differentials=False)
    ok = r["valid"]
    points = r["org"][ok] + rng.uniform(0.5, 5, ok.sum())[:, None] * r["dir"][ok]
    p = cam.project(points)
    assert p.offsets.shape == (ok.sum() + 1,)
    for i, (uu, vv) in enumerate(zip(u[ok], v[ok])):
        seen = p.of(i)
        assert len(seen) >= 1, f"point {i} ({uu}, {vv}) not found"
        err = np.min(np.hypot(seen[:, 0] - uu, seen[:, 1] - vv))
        assert err < 1e-6, f"point {i}: nearest image position is {err} from ({uu}, {vv})"


def test_project_pixels_equal_the_cli():
    scene = ROOT / "examples/apps/fisheye_180.toml"
    cam = anamorph.load(scene).camera
    point = [0.3, 1.1, -2.0]
    out = json.loads(cli("project", scene, "--point", ",".join(map(str, point)), "--json").stdout)
    want = np.array(out["pixels"], dtype=np.float64).reshape(-1, 2)
    np.testing.assert_allclose(cam.project([point]).pixels, want, atol=5e-7)


def test_a_composed_camera_equals_the_same_camera_from_a_scene_file(tmp_path):
    rng = np.random.default_rng(3)
    grid = np.stack(np.meshgrid(np.linspace(-2, 2, 4), np.linspace(1.5, -1.5, 4)), -1)
    points = np.concatenate([grid, rng.uniform(-0.3, 0.3, (4, 4, 1))], -1)
    coin = dict(position=[0.1234567890123, 0.3, -4.0], strength=0.4, radius=0.3)
    cam = anamorph.Camera(org=anamorph.org.bspline(points=points, degree_u=3, degree_v=3),
                          dir=anamorph.dir.deviated_normal(angle=12.5, azimuth=30),
                          coins=[anamorph.Coin(**coin)], width=32, height=24)
    text = (f"[image]\nwidth = 32\nheight = 24\n[camera.org]\ntype = \"bspline\"\n"
            f"points = {anamorph._toml.value(points)}\n[camera.dir]\ntype = \"deviated_normal\"\n"
            f"angle = 12.5\nazimuth = 30\n[[camera.coin]]\n"
            + "".join(f"{k} = {anamorph._toml.value(v)}\n" for k, v in coin.items()))
    scene = tmp_path / "composed.toml"
    scene.write_text(text)
    table = cli_rays(tmp_path, str(scene), 32, 24)
    rays = cam.rays()
    valid = rays["valid"].reshape(-1)
    assert valid.any()
    np.testing.assert_array_equal(valid, table[:, 10] == 1)
    np.testing.assert_array_equal(rays["dir"].reshape(-1, 3)[valid], table[valid][:, 7:10])
    np.testing.assert_array_equal(rays["org"].reshape(-1, 3)[valid], table[valid][:, 4:7])


def test_python_floats_reach_the_reader_exactly():
    rng = np.random.default_rng(11)
    for x in list(rng.uniform(-1e3, 1e3, 50)) + [1e-300, 5e-324, 1e12, -0.0]:
        cam = anamorph.Camera("perspective", look_from=[float(x), 0, 0], look_at=[x, 0, -1.0],
                              width=2, height=2)
        assert cam.generate([0.5], [0.5])["org"][0, 0] == x, x
    # Beyond the world's 1e12 scene units (docs/scene-format.md, Coordinates): the reader's error.
    with pytest.raises(anamorph.SceneError, match="out of range"):
        anamorph.Camera("perspective", look_from=[1.7976931348623157e308, 0, 0], width=2, height=2)


def test_an_unknown_keyword_names_the_key_and_suggests_one():
    with pytest.raises(anamorph.SceneError) as e:
        anamorph.Camera("fisheye", fvo=180)
    assert e.value.key == "camera.fvo"
    assert "did you mean 'fov'" in str(e.value)
    assert isinstance(e.value, ValueError)


def test_keyword_messages_equal_the_scene_readers(tmp_path):
    scene = tmp_path / "bad.toml"
    scene.write_text('[camera]\npreset = "fisheye"\nfov = 400\n')
    p = cli("info", scene, check=False)
    assert p.returncode == 2
    with pytest.raises(ValueError) as e:
        anamorph.Camera("fisheye", fov=400)
    assert str(e.value) == "camera.fov: " + e.value.message
    assert p.stderr.strip().endswith("camera.fov: " + e.value.message), p.stderr


@pytest.mark.parametrize("make, key", [
    (lambda: anamorph.Coin(position=[0, 0, -1], strength=2), "coin.strength"),
    (lambda: anamorph.Coin(strength=0.5), "coin.position"),
    (lambda: anamorph.Coin(position=[0, 0, -1], radiuss=0.1), "coin.radiuss"),
    (lambda: anamorph.org.sphere(radius=-1), "org.radius"),
    (lambda: anamorph.dir.normal(flop=True), "dir.flop"),
    (lambda: anamorph.Camera("fishey"), "camera.preset"),
    (lambda: anamorph.Camera(width=0), "image.width"),
])
def test_bad_values_raise_value_errors_naming_the_key(make, key):
    with pytest.raises(anamorph.SceneError) as e:
        make()
    assert e.value.key == key, str(e.value)
    assert str(e.value).startswith(key + ": ")


def test_resized_follows_the_aspect_ratio():
    cam = anamorph.Camera("perspective", fov=90, fov_axis="horizontal", width=100, height=50)
    tall = cam.resized(50, 100)
    assert (tall.width, tall.height) == (50, 100)
    # The horizontal field stays 90 degrees: the left edge ray is 45 degrees off axis.
    d = tall.generate([0.0], [0.5])["dir"][0]
    np.testing.assert_allclose(np.degrees(np.arctan2(-d[0], -d[2])), 45, atol=1e-9)


def test_schema_is_the_clis(tmp_path):
    out = tmp_path / "schema.json"
    cli("schema", "-o", out)
    import json
    assert anamorph.schema() == json.loads(out.read_text())


def test_coins_report_their_image_positions():
    cam = anamorph.load(ROOT / "examples/apps/focus_context.toml").camera
    coins = cam.coins
    assert [c["coin"] for c in coins] == [0, 1, 2]
    info = cli("info", ROOT / "examples/apps/focus_context.toml").stdout
    for c in coins:
        assert f"(uc, vc) = ({c['uv'][0]:.4f}, {c['uv'][1]:.4f})" in info


@pytest.mark.parametrize("inverse", [False, True])
def test_stmap_equals_the_cli_map(tmp_path, inverse):
    scene = ROOT / "examples/apps/fisheye_180.toml"
    cam = anamorph.load(scene).camera.resized(40, 30)
    extra = ["--inverse", "--source-size", "64x32"] if inverse else []
    cli("stmap", scene, "--width", 40, "--height", 30, "--source", "equirect", *extra,
        "-o", tmp_path / "m.exr")
    want = read_exr(tmp_path / "m.exr")
    m = cam.stmap("equirect", inverse=inverse, source_size=(64, 32) if inverse else None)
    h, w = (32, 64) if inverse else (30, 40)
    assert m["st"].shape == (h, w, 2) and m["st"].dtype == np.float32
    for got, name in ((m["st"][..., 0], "R"), (m["st"][..., 1], "G"), (m["alpha"], "A"),
                      (m["direction"][..., 0], "direction.X"),
                      (m["direction"][..., 2], "direction.Z")):
        np.testing.assert_array_equal(got, want[name], err_msg=name)
    assert 0 < m["alpha"].sum() < h * w  # (a 180 degree fisheye: rays inside its circle only)


def test_stmap_of_the_equirect_to_itself_is_the_identity():
    m = anamorph.Camera("equirectangular", width=32, height=16).stmap("equirect")
    x, y = np.meshgrid(np.arange(32), np.arange(16))
    np.testing.assert_allclose(m["st"][..., 0], (x + 0.5) / 32, atol=1e-6)
    np.testing.assert_allclose(m["st"][..., 1], 1 - (y + 0.5) / 16, atol=1e-6)
    assert np.all(m["alpha"] == 1)


def test_stmap_refuses_a_camera_that_is_not_central():
    with pytest.raises(ValueError, match="not central"):
        anamorph.Camera("orthographic", width=16, height=16).stmap("equirect")
    with pytest.raises(ValueError, match="unknown projection"):
        anamorph.Camera("fisheye", width=16, height=16).stmap("mercator")


def test_stmap_with_a_depth_maps_a_camera_that_is_not_central():
    # An orthographic view 2 wide along -z (the default view) at depth 4: each ray from (x, y, 0)
    # leaves the sphere at (x, y, -sqrt(16 - x^2 - y^2)), seen from the centre.
    cam = anamorph.Camera("orthographic", width=16, height=16, view_width=2)
    m = cam.stmap("equirect", depth=4.0)
    assert np.all(m["alpha"] == 1)
    c = (np.arange(16) + 0.5) / 16 * 2 - 1
    x, y = np.meshgrid(c, -c)
    d = np.stack([x, y, -np.sqrt(16 - x * x - y * y)], axis=-1) / 4
    np.testing.assert_allclose(m["direction"], d, atol=1e-6)
    s = 0.5 + np.arctan2(d[..., 0], -d[..., 2]) / (2 * np.pi)
    np.testing.assert_allclose(m["st"][..., 0], s, atol=1e-6)
    with pytest.raises(ValueError, match="depth"):
        cam.stmap("equirect", depth=0)


@pytest.fixture(scope="module")
def small_equirect(tmp_path_factory):
    """A 128 x 64 equirect render of the fisheye example's world (EXR, 4 spp)."""
    out = tmp_path_factory.mktemp("warp") / "eq.exr"
    cli("render", "-q", ROOT / "examples/apps/fisheye_180.toml", "--camera", "equirectangular",
        "--width", 128, "--height", 64, "--set", "render.spp=4", "-o", out)
    return out


@pytest.mark.parametrize("filter_", ["area", "bilinear"])
def test_warp_equals_the_cli_output(tmp_path, small_equirect, filter_):
    scene = ROOT / "examples/apps/fisheye_180.toml"
    cli("warp", "-q", scene, small_equirect, "--source", "equirect", "--filter", filter_,
        "--width", 48, "--height", 40, "-o", tmp_path / "w.exr")
    want = anamorph.read_exr(tmp_path / "w.exr")["rgba"]
    cam = anamorph.load(scene).camera
    got = anamorph.warp(cam, small_equirect, "equirect", filter=filter_, width=48, height=40)
    assert got.shape == (40, 48, 4) and got.dtype == np.float32
    np.testing.assert_array_equal(got, want)
    # The same values from the image as an array, and for any thread count.
    pixels = anamorph.read_exr(small_equirect)["rgba"]
    np.testing.assert_array_equal(
        anamorph.warp(cam, pixels, "equirect", filter=filter_, width=48, height=40, threads=1),
        want)
    assert 0 < (got[..., 3] > 0).sum() < 48 * 40  # (the image circle only)


def test_warp_refuses_bad_inputs(small_equirect):
    cam = anamorph.Camera("fisheye", fov=180, width=16, height=16)
    with pytest.raises(anamorph.SceneError, match="aspect"):
        anamorph.warp(cam, np.zeros((10, 30, 3), np.float32), "equirect")
    with pytest.raises(ValueError, match="filter"):
        anamorph.warp(cam, small_equirect, "equirect", filter="sharp")
    with pytest.raises(ValueError, match="not central"):
        anamorph.warp(anamorph.Camera("orthographic", width=8, height=8), small_equirect,
                      "equirect")


@pytest.mark.parametrize("filter_", ["area", "bilinear", "aniso", "bicubic"])
def test_warp_of_a_constant_rgb_array_is_that_constant_with_alpha_one(filter_):
    cam = anamorph.Camera("fisheye", fov=180, width=24, height=24)
    img = np.full((32, 64, 3), 0.25, np.float32)  # (no alpha: every filter makes it 1)
    got = anamorph.warp(cam, img, "equirect", filter=filter_)
    inside = cam.rays()["valid"]
    assert inside.any() and not inside.all()
    np.testing.assert_allclose(got[inside][:, :3], 0.25, atol=1e-5)
    np.testing.assert_allclose(got[inside][:, 3], 1, atol=1e-5)
    assert np.all(got[~inside] == 0)
