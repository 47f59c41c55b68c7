"""Scenes from Python: renders equal to `anamorph render` bit for bit, overrides, progress,
cancellation by Ctrl-C, the GIL released while rendering, and no memory growth over renders."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import anamorph
from conftest import ROOT, cli, read_exr

DEMO = ROOT / "examples/demo.toml"


def assert_layers_equal(got: dict, want: dict) -> None:
    assert sorted(got) == sorted(want)
    for k in want:
        a, b = got[k], want[k]
        assert a.shape == b.shape, (k, a.shape, b.shape)
        diff = np.argwhere(~((a == b) | (np.isnan(a) & np.isnan(b))))
        assert diff.size == 0, f"layer {k}: {len(diff)} values differ, first at {diff[0]}: " \
                               f"{a[tuple(diff[0])]} != {b[tuple(diff[0])]}"


@pytest.mark.parametrize("scene, args, kwargs", [
    ("examples/demo.toml", [], {}),  # whitted, adaptive lattice
    ("examples/apps/focus_context.toml", ["--spp", "2", "--seed", "5"], dict(spp=2, seed=5)),
    ("examples/demo.toml", ["--integrator", "path", "--spp", "3"],
     dict(integrator="path", spp=3)),
])
def test_render_equals_the_cli_bit_for_bit(tmp_path, scene, args, kwargs):
    out = tmp_path / "cli.exr"
    cli("render", ROOT / scene, "--width", 64, "--height", 48, "-q", "--aov",
        "albedo,depth,normal,spp,coins", *args, "-o", out)
    img = anamorph.load(ROOT / scene).render(
        width=64, height=48, aovs=["albedo", "depth", "normal", "spp", "coins"], **kwargs)
    assert img["rgba"].dtype == np.float32 and img["rgba"].shape == (48, 64, 4)
    assert_layers_equal(img, anamorph.read_exr(out))


def test_set_overrides_are_the_clis_set(tmp_path):
    out = tmp_path / "cli.exr"
    cli("render", DEMO, "--width", 40, "--height", 30, "-q", "--set", "camera.fov=75",
        "--set", "render.antialias=uniform", "--set", 'camera.look_at=[0, 0.5, 0]', "-o", out)
    scene = anamorph.load(DEMO, set={"camera.fov": 75, "render.antialias": "uniform",
                                     "camera.look_at": np.array([0, 0.5, 0])})
    assert_layers_equal(scene.render(width=40, height=30), anamorph.read_exr(out))


def test_render_set_reads_the_view_again_over_the_same_geometry():
    # A whole camera table replaces the file's (a fisheye keeps none of the perspective's
    # keys); a dotted key sets one. Each equals a scene loaded with the same set, bit for bit.
    scene = anamorph.load(DEMO)
    first = scene.render(width=40, height=30, spp=1)  # (builds the acceleration structure)
    fisheye = {"preset": "fisheye", "fov": 170, "look_from": [0, 1, 5], "look_at": [0, 0.5, 0]}
    for over in ({"camera": fisheye}, {"camera.fov": 75, "render.max_depth": 2}):
        got = scene.render(width=40, height=30, spp=1, set=over)
        assert_layers_equal(got, anamorph.load(DEMO, set=over).render(width=40, height=30,
                                                                       spp=1))
        assert not np.array_equal(got["rgba"], first["rgba"])
    assert_layers_equal(scene.render(width=40, height=30, spp=1), first)  # for one render
    with pytest.raises(ValueError, match="not under camera, image or render, nor"):
        scene.render(width=8, height=8, set={"object.0.name": "x"})


GLTF = ROOT / "tests/data/gltf/blender"
KNOT = "object.4.transform"  # examples/demo.toml's torus knot, the one mesh [[object]]


def test_render_set_moves_a_mesh_object_without_a_load():
    # An object's transform in a render's set moves its instances over the loaded geometry:
    # the same bits as a scene loaded with that transform (a whole table, a key under it),
    # and a render without it puts the object back where the file has it.
    scene = anamorph.load(DEMO)
    first = scene.render(width=40, height=30, spp=1)
    for over in ({KNOT: {"scale": 0.8, "translate": [0.6, 0.4, 2.0]}},
                 {KNOT + ".translate": [-0.5, 0.7, 2.4], "camera.fov": 70}):
        got = scene.render(width=40, height=30, spp=1, set=over)
        assert_layers_equal(got, anamorph.load(DEMO, set=over).render(width=40, height=30,
                                                                       spp=1))
        assert not np.array_equal(got["rgba"], first["rgba"])
    assert_layers_equal(scene.render(width=40, height=30, spp=1), first)


def test_render_set_moves_an_animated_models_object(tmp_path):
    # A glTF rig's instances: moved by the object's transform and posed at the scene's frame.
    text = (f'[image]\nwidth = 32\nheight = 24\n[camera]\nlook_from = [4, 3, 6]\n'
            f'look_at = [0, 0.5, 0]\n[[object]]\ntype = "mesh"\n'
            f'file = "{GLTF / "animated.glb"}"\nlights = false\ncameras = false\n')
    path = tmp_path / "animated.toml"
    path.write_text(text)
    over = {"object.0.transform": {"rotate": [30, 0, 1, 0], "translate": [0.3, 0, 0]}}
    scene = anamorph.load(path, frame=12)
    first = scene.render(spp=1, aovs=["id", "depth"])
    got = scene.render(spp=1, aovs=["id", "depth"], set=over)
    assert_layers_equal(got, anamorph.load(path, frame=12, set=over).render(
        spp=1, aovs=["id", "depth"]))
    assert not np.array_equal(got["depth"], first["depth"])


def test_objects_that_cannot_move_without_a_load_say_why(tmp_path):
    scene = anamorph.load(DEMO)
    with pytest.raises(ValueError, match="only a mesh object moves without a load"):
        scene.render(width=8, height=8, set={"object.1.transform": {"translate": [1, 0, 0]}})
    with pytest.raises(ValueError, match=KNOT.replace(".", r"\.") + ": it reaches"):
        scene.render(width=8, height=8, set={KNOT: {"translate": [1e12, 0, 0]}})
    lit = tmp_path / "lit.toml"
    lit.write_text(f'[[object]]\ntype = "mesh"\nfile = "{GLTF / "point_only.glb"}"\n')
    with pytest.raises(ValueError, match="brought lights or cameras"):
        anamorph.load(lit).render(width=8, height=8,
                                  set={"object.0.transform": {"translate": [0, 1, 0]}})
    assert scene.render(width=8, height=8)["rgba"].shape == (8, 8, 4)  # (still usable)


def test_a_bad_override_names_the_key():
    with pytest.raises(anamorph.SceneError) as e:
        anamorph.load(DEMO, set={"camera.fov": "wide"})
    assert e.value.key == "camera.fov"
    assert str(e.value).startswith("camera.fov: ")
    with pytest.raises(anamorph.SceneError) as e:
        anamorph.load(DEMO).render(width=-3)
    assert e.value.key == "image.width"


def test_a_bad_scene_file_names_file_line_and_key(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[render]\nspp = 0\n")
    with pytest.raises(anamorph.SceneError) as e:
        anamorph.load(bad)
    assert (e.value.file, e.value.line, e.value.key) == (str(bad), 2, "render.spp")
    assert str(e.value) == cli("info", bad, check=False).stderr.strip().removeprefix("error: ")


def test_info_agrees_with_the_cli():
    info = anamorph.load(DEMO).info()
    text = cli("info", DEMO).stdout
    assert f"{info['unique_triangles']} unique" in text
    assert f"camera      {info['camera']}" in text
    assert f"{info['width']}x{info['height']}" in text
    assert [s["type"] for s in info["shapes"]] == [
        line.split()[0] for line in text.split("shapes")[1].split("materials")[0].splitlines()[1:]]


def test_info_names_each_object_id_of_the_id_layer():
    scene = anamorph.loads("""
[image]
width = 40
height = 20
[camera]
preset = "perspective"
look_from = [0, 0, 5]
look_at = [0, 0, 0]
fov = 60
[[object]]
type = "sphere"
name = "left"
center = [-1.2, 0, 0]
radius = 0.8
[[object]]
type = "sphere"
name = "right"
center = [1.2, 0, 0]
radius = 0.8
""")
    ids = scene.render(aovs=["id"], spp=1, sampler="center")["id"][..., 0]
    names = scene.info()["objects"]
    assert sorted(names) == ["left", "right"], names
    seen = {(x, y): names[int(ids[y, x])] if ids[y, x] >= 0 else None
            for x, y in ((10, 10), (30, 10), (20, 1))}
    assert seen == {(10, 10): "left", (30, 10): "right", (20, 1): None}, seen


def test_progress_is_reported_on_the_calling_thread_and_reaches_one():
    seen = []
    caller = threading.get_ident()

    def progress(p):
        assert threading.get_ident() == caller
        seen.append(p["fraction"])

    anamorph.load(DEMO).render(width=160, height=120, spp=16, progress=progress)
    assert seen and seen[-1] == pytest.approx(1.0)
    assert all(a <= b for a, b in zip(seen, seen[1:])), seen


def test_an_exception_in_progress_cancels_the_render():
    scene = anamorph.load(DEMO)

    def stop(p):
        raise RuntimeError("enough")

    t0 = time.monotonic()
    with pytest.raises(RuntimeError, match="enough"):
        scene.render(width=640, height=480, spp=4096, progress=stop)
    # The scene still renders afterwards.
    assert scene.render(width=8, height=6)["rgba"].shape == (6, 8, 4)


def test_ctrl_c_cancels_a_render_cleanly(tmp_path):
    script = (
        "import anamorph, sys\n"
        f"s = anamorph.load({str(DEMO)!r})\n"
        "print('rendering', flush=True)\n"
        "try:\n"
        "    s.render(width=640, height=480, spp=100000)\n"
        "except KeyboardInterrupt:\n"
        "    print('cancelled', s.render(width=4, height=3)['rgba'].shape, flush=True)\n")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True,
                         env=env)
    assert p.stdout.readline().strip() == "rendering"
    time.sleep(0.5)
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=60)
    assert p.returncode == 0, out
    assert out.strip() == "cancelled (3, 4, 4)"


def test_the_gil_is_released_while_rendering():
    scene = anamorph.load(DEMO)
    ticks = 0
    done = threading.Event()

    def count():
        nonlocal ticks
        while not done.is_set():
            ticks += 1

    t = threading.Thread(target=count)
    t.start()
    try:
        scene.render(width=320, height=240, spp=8)
    finally:
        done.set()
        t.join()
    # With the GIL held for the whole render the counter would not move at all (it is started
    # before the render and stopped after).
    assert ticks > 1000, ticks


def rss_kb() -> int:
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith("VmRSS"))


def test_no_memory_growth_over_a_thousand_renders():
    # Uniform sampling: the adaptive lattice's fixed cost per frame would make this 20 s.
    scene = anamorph.load(DEMO, set={"render.antialias": "uniform", "render.spp": 2})
    cam = scene.camera
    for _ in range(100):
        scene.render(width=16, height=12, aovs=["albedo"])
        cam.rays(16, 12)
    warm = rss_kb()
    for _ in range(1000):
        scene.render(width=16, height=12, aovs=["albedo"])
        cam.rays(16, 12)
    grown = rss_kb() - warm
    assert grown < 0.05 * warm, f"RSS grew by {grown} kB over 1000 renders (from {warm} kB)"


def test_a_progress_callback_cannot_render_its_own_scene():
    scene = anamorph.load(DEMO)

    def again(p):
        scene.render(width=4, height=3)

    with pytest.raises(RuntimeError, match="own render's progress callback"):
        scene.render(width=320, height=240, spp=64, progress=again)
    assert scene.render(width=4, height=3)["rgba"].shape == (3, 4, 4)


def test_a_time_limit_stops_at_whole_passes_with_every_pixel_sampled():
    # 100000 samples a pixel would take hours; the budget stops the progressive passes after
    # whole tiles, and the first pass (one sample a pixel) covers the image.
    scene = anamorph.load(DEMO, set={"render.time_limit": 0.3})
    img = scene.render(width=96, height=64, integrator="path", spp=100000, aovs=["spp"])
    spp = img["spp"]
    assert spp.min() >= 1, "a pixel without samples"
    assert spp.max() < 100000, "the time limit did not stop the render"
    assert (img["rgba"][..., 3] > 0).all()


def test_depth_layers_from_python():
    # A plane 5 units in front of a perspective camera: depth_z is 5 at every pixel, distance
    # 5 / cos(angle to the axis), and position_camera's z is -5.
    scene = anamorph.loads(
        '[image]\nwidth = 8\nheight = 6\n[render]\nintegrator = "albedo"\nsampler = "center"\n'
        '[camera]\nlook_from = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 90\n'
        '[[object]]\ntype = "plane"\nnormal = [0, 0, 1]\n')
    img = scene.render(aovs=["distance", "depth_z", "position_camera"])
    np.testing.assert_allclose(img["depth_z"], 5, rtol=1e-6)
    np.testing.assert_allclose(img["position_camera"][..., 2], -5, rtol=1e-6)
    xy = img["position_camera"][..., :2]
    np.testing.assert_allclose(img["distance"][..., 0],
                               np.sqrt(25 + (xy ** 2).sum(axis=-1)), rtol=1e-6)


def test_ray_layers_are_the_cameras_pixel_centre_rays():
    # ray_origin / ray_direction at every pixel, hit or miss, equal Camera.rays (float32 of its
    # float64), NaN outside a fisheye's circle.
    for preset in ("perspective", "fisheye"):
        scene = anamorph.loads(
            '[image]\nwidth = 10\nheight = 8\n[render]\nintegrator = "albedo"\nspp = 2\n'
            f'[camera]\npreset = "{preset}"\nfov = 120\nlook_from = [1, 2, 3]\n'
            'look_at = [0, 0, 0]\n[[object]]\ntype = "sphere"\nradius = 1\n')
        img = scene.render(aovs=["ray_origin", "ray_direction", "id"])
        rays = scene.camera.rays(differentials=False)
        valid = rays["valid"]
        assert (img["id"][..., 0] < 0).sum() > 10, "misses"
        assert (~valid).any() == (preset == "fisheye")
        for layer, key in (("ray_origin", "org"), ("ray_direction", "dir")):
            np.testing.assert_array_equal(img[layer][valid], rays[key][valid].astype(np.float32))
            assert np.isnan(img[layer][~valid]).all()


# A fisheye turning between frames 0 and 2 before a sphere moving across a still one: flow
# (with occlusion) and motion from Python equal the CLI's EXR, which loads frames F +- 1 the same.
FLOW_SCENE = """[image]\nwidth = 24\nheight = 20\n[render]\nintegrator = "albedo"
sampler = "center"\n[camera]\npreset = "fisheye"\nfov = 160\nlook_from = [0, 0, 0]
look_at = [0, 0, -1]\n[[object]]\ntype = "sphere"\ncenter = [0, 0, 0]\nradius = 20
[[object]]\ntype = "sphere"\ncenter = [0, 0, -3]\nradius = 1
[[animate]]\nkey = "camera.look_at"\nkeys = [[0, [0, 0, -1]], [2, [0.1, 0.04, -1]]]
[[animate]]\nkey = "object.1.center"\nkeys = [[0, [0, 0, -3]], [2, [0.6, 0, -3]]]
"""


@pytest.mark.parametrize("set_", [{}, {"image.width": 16}])
def test_flow_and_motion_layers_equal_the_cli(tmp_path, set_):
    path = tmp_path / "s.toml"
    path.write_text(FLOW_SCENE)
    layers = ["flow_forward", "flow_backward", "motion"]
    img = anamorph.load(path, frame=1, set=set_).render(aovs=layers)
    over = [a for k, v in set_.items() for a in ("--set", f"{k}={v}")]
    cli("render", path, "--frames", "1:1", "-o", tmp_path / "f_%04d.exr", "--aov",
        ",".join(layers), "-q", *over)
    want = read_exr(tmp_path / "f_0001.exr")
    for layer, chans in (("flow_forward", "X Y valid"), ("flow_backward", "X Y valid"),
                         ("motion", "X Y Z W")):
        for k, c in enumerate(chans.split()):
            np.testing.assert_array_equal(img[layer][..., k], want[f"{layer}.{c}"],
                                          err_msg=f"{layer}.{c}")
    valid = img["flow_forward"][..., 2]
    assert (valid == 1).sum() > valid.size // 2 and (valid == 0).sum() > 0  # some hidden
    assert np.isnan(img["flow_forward"][..., 0][valid == 0]).all()


def test_denoise_equals_the_clis_bit_for_bit(tmp_path):
    out = tmp_path / "cli.exr"
    cli("render", DEMO, "--width", 40, "--height", 30, "-q", "--spp", 4, "--integrator", "path",
        "--denoise", "--aov", "depth", "-o", out)
    img = anamorph.load(DEMO).render(width=40, height=30, spp=4, integrator="path", aovs=["depth"],
                                     denoise=True)
    assert_layers_equal(img, anamorph.read_exr(out))
    noisy = anamorph.load(DEMO).render(width=40, height=30, spp=4, integrator="path")
    assert not np.array_equal(img["rgba"][..., :3], noisy["rgba"][..., :3])
    with pytest.raises(ValueError, match="at least 2 samples"):
        anamorph.load(DEMO).render(width=40, height=30, spp=1, denoise=True)
