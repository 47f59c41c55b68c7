"""The bounds of what the module reads, as the CLI has them (math/input_limits.h, issue 32 part 2):
coordinates beyond 1e12 scene units, input nested more than 64 levels and thread counts beyond
1024 are ValueErrors naming their key, where they faulted or aborted the interpreter before
(Embree's asserts, stack overflows, 200,000 TBB workers). The C++ side: tests/limits/."""

from __future__ import annotations

import random

import numpy as np
import pytest

import anamorph

HEAD = "[image]\nwidth = 8\nheight = 6\n[[material]]\nname = \"m\"\nreflectivity = 0.5\n"


def scene_file(tmp_path, body: str):
    p = tmp_path / "s.toml"
    p.write_text(HEAD + body)
    return p


def test_a_camera_at_2e18_is_a_scene_error_at_its_line(tmp_path):
    s = scene_file(tmp_path, "[camera]\nlook_from = [2e18, 1, 4]\n[[object]]\ntype = \"sphere\"\n")
    with pytest.raises(anamorph.SceneError) as e:
        anamorph.load(s)
    assert (e.value.line, e.value.key) == (8, "camera.look_from")
    assert "out of range" in str(e.value)


def test_coordinates_beyond_the_world_in_overrides_are_scene_errors(tmp_path):
    s = scene_file(tmp_path, "[[object]]\ntype = \"sphere\"\n")
    for key, value in [("camera.look_from", [2e18, 1, 4]), ("object.0.radius", 1e30),
                       ("object.0.center", [0, 1e13, 0])]:
        with pytest.raises(anamorph.SceneError) as e:
            anamorph.load(s, set={key: value})
        assert e.value.key.replace("[0]", ".0") == key, str(e.value)
        assert "out of range" in str(e.value) or "reaches" in str(e.value)


def test_ray_tables_with_huge_origins_or_only_zero_directions_are_scene_errors(tmp_path):
    table = ("[camera.org]\ntype = \"table\"\nsamples = [[[0, 0, 0], [{}, 0, 0]]]\n"
             "[camera.dir]\ntype = \"table\"\nsamples = [[[0, 0, {}], [0, 0, {}]]]\n")
    for org, d, says in [("3e18", "-1", "out of range"), ("1", "0", "no valid sample")]:
        with pytest.raises(anamorph.SceneError) as e:
            anamorph.load(scene_file(tmp_path, table.format(org, d, d)))
        assert says in str(e.value) and e.value.line > 0


def test_deep_nesting_is_a_scene_error(tmp_path):
    deep = scene_file(tmp_path, ".".join(["a"] * 50000) + " = 1\n")
    with pytest.raises(anamorph.SceneError) as e:
        anamorph.load(deep)
    assert "nested more than 64 levels" in str(e.value)
    with pytest.raises(anamorph.SceneError) as e:
        anamorph.load(scene_file(tmp_path, ""), set={".".join(["a"] * 50000): 1})
    assert "nests deeper than the 64 levels" in str(e.value)


def test_thread_counts_beyond_1024_are_value_errors(tmp_path):
    scene = anamorph.load(scene_file(tmp_path, "[[object]]\ntype = \"sphere\"\n"))
    for n in (200000, 1025, -1):
        with pytest.raises(ValueError, match="0 \\(all cores\\) to 1024"):
            scene.render(threads=n)
        with pytest.raises(ValueError, match="0 \\(all cores\\) to 1024"):
            scene.camera.rays(threads=n)
    assert scene.render(threads=2)["rgba"].shape == (6, 8, 4)


def wild(rng: random.Random) -> float:
    """Mostly ordinary, one in ten zero, huge, tiny or around the world's bound."""
    sign = rng.choice((-1.0, 1.0))
    if rng.random() < 0.9:
        return sign * 10 ** rng.uniform(-2, 2)
    kind = rng.randrange(4)
    if kind == 0:
        return 0.0
    if kind == 1:
        return sign * 10 ** rng.uniform(11, 308)
    if kind == 2:
        return sign * 10 ** rng.uniform(-308, -10)
    return sign * 1e12 * rng.uniform(0.5, 1.5)


def test_random_coordinates_render_or_are_scene_errors(tmp_path):
    rng = random.Random(11)
    rendered = refused = 0
    for _ in range(120):
        def vec() -> str:
            return "[" + ", ".join(repr(wild(rng)) for _ in range(3)) + "]"
        body = (f"[camera]\nlook_from = {vec()}\nlook_at = {vec()}\n"
                f"[[object]]\ntype = \"sphere\"\nmaterial = \"m\"\ncenter = {vec()}\n"
                f"radius = {abs(wild(rng)) or 1.0!r}\n"
                f"transform = {{ scale = {abs(wild(rng)) or 1.0!r}, translate = {vec()} }}\n"
                f"[[object]]\ntype = \"plane\"\npoint = {vec()}\nnormal = {vec()}\n"
                f"[[light]]\ntype = \"point\"\nposition = {vec()}\n")
        try:
            scene = anamorph.load(scene_file(tmp_path, body))
        except anamorph.SceneError as e:
            assert e.line > 0 and e.key, str(e)
            refused += 1
            continue
        rays = scene.camera.rays()
        org = rays["org"][rays["valid"]]
        assert np.all(np.abs(org) <= 1e12), org
        scene.render(threads=1)
        rendered += 1
    assert rendered > 10 and refused > 10, (rendered, refused)
