"""The second probe's honest messages from Python (docs/robustness.md, "Second probe: honest
numbers and messages"): integers too large for C++ say which key and range, a NUL in a file name
is refused wherever a path enters, and messages escape control characters."""

from __future__ import annotations

import pytest

import anamorph

SPHERE = "[image]\nwidth = 8\nheight = 8\n[[object]]\ntype = \"sphere\"\n"


@pytest.mark.parametrize("make, key, range_text", [
    (lambda: anamorph.Camera("fisheye", width=2**70), "image.width", "[1, 65536]"),
    (lambda: anamorph.Camera("fisheye", fov=2**70), "camera.fov", "(0, 360]"),
    (lambda: anamorph.Camera("fisheye", height=-2**70), "image.height", "[1, 65536]"),
    (lambda: anamorph.loads(SPHERE, set={"image.width": 2**70}), "image.width", "[1, 65536]"),
    (lambda: anamorph.loads(SPHERE, set={"render.spp": 2**200}), "render.spp", "[1, 1048576]"),
    (lambda: anamorph.loads(SPHERE).render(width=2**70), "image.width", "[1, 65536]"),
    (lambda: anamorph.Camera("fisheye").resized(2**70, 8), "image.width", "[1, 65536]"),
    (lambda: anamorph.loads(SPHERE).form_factors(samples=2**70), "samples", "[1, 16777216]"),
    (lambda: anamorph.loads(SPHERE).form_factors(seed=2**64), "seed", "18446744073709551615]"),
])
def test_an_integer_too_large_for_cpp_is_out_of_the_keys_range(make, key, range_text):
    with pytest.raises(anamorph.SceneError) as e:
        make()
    assert e.value.key == key, str(e.value)
    assert "out of range" in str(e.value) and range_text in str(e.value), str(e.value)
    assert "string" not in str(e.value) and "syntax" not in str(e.value), str(e.value)


def test_an_integer_key_given_a_fraction_still_asks_for_an_integer():
    with pytest.raises(TypeError, match="samples: expected an integer, got float"):
        anamorph.loads(SPHERE).form_factors(samples=1.5)


def test_a_nul_in_a_file_name_is_refused_everywhere(tmp_path):
    scene = tmp_path / "s.toml"
    scene.write_text(SPHERE)
    exr = tmp_path / "a.exr"
    anamorph.loads(SPHERE)  # (a valid scene loads)
    cases = [
        lambda: anamorph.load(str(scene) + "\0junk"),
        lambda: anamorph.load(scene, set={"environment.file": str(exr) + "\0.hdr"}),
        lambda: anamorph.read_exr(str(exr) + "\0x"),
        lambda: anamorph.Camera(org={"type": "table", "file": "t.exr\0x"}, dir={"type": "constant"}),
    ]
    for make in cases:
        with pytest.raises(ValueError, match="contains a NUL character") as e:
            make()
        assert "\0" not in str(e.value)


def test_messages_escape_control_characters():
    with pytest.raises(anamorph.SceneError) as e:
        anamorph.loads(SPHERE, set={"camera.\x1b[2Jfov": 1})
    assert "\x1b" not in str(e.value) and "\\x1b[2J" in str(e.value), str(e.value)
    assert e.value.key == "camera.\x1b[2Jfov"  # the attribute keeps the key as given


DOME = """[[material]]
name = "lamp"
color = {lamp_color}
emission = 1
[[material]]
name = "wall"
color = {wall_color}
[[object]]
type = "sphere"
name = "{lamp_name}"
radius = {radius}
material = "lamp"
[[object]]
type = "sphere"
name = "dome"
radius = 2
material = "wall"
"""


def dome(radius="0.5", lamp_color="0.5", wall_color="0.6", lamp_name="lamp"):
    return anamorph.loads(DOME.format(radius=radius, lamp_color=lamp_color,
                                      wall_color=wall_color, lamp_name=lamp_name))


def test_form_factors_say_why_an_object_has_no_row_and_stay_finite():
    import numpy as np
    f = dome(radius="1e-200").form_factors(samples=16, rays=16, inward=["dome"])
    assert f["rows"] == ["dome"]
    assert f["unmeasured"] == {
        "lamp": "its surface area underflows to 0 (too small for double precision)"}
    assert np.isfinite(f["F"]).all() and np.isfinite(f["stderr"]).all()
    with pytest.raises(ValueError, match="'lamp' can have none: its surface area underflows"):
        dome(radius="1e-200").form_factors(samples=16, rays=16, inward=["dome"], radiosity=True)
    tiny = dome(radius="1e-100").form_factors(samples=32, rays=16, inward=["dome"],
                                              radiosity=True)
    for key in ("F", "stderr", "areas", "radiosity", "path_radiance", "path_radiance_stderr"):
        assert np.isfinite(tiny[key]).all(), (key, tiny[key])


def test_an_object_named_environment_is_renamed_and_noted():
    f = dome(lamp_name="environment").form_factors(samples=8, rays=16, inward=["dome"])
    assert f["columns"] == ["environment#2", "dome", "environment"]
    assert f["notes"] == ["the object named 'environment' is listed as 'environment#2': "
                          "'environment' names the column of rays that hit nothing"]


def test_radiosity_refuses_a_lossless_enclosure_and_out_of_range_reflectance():
    with pytest.raises(ValueError, match="light is never absorbed"):
        dome(lamp_color="1", wall_color="1").form_factors(samples=32, rays=16, inward=["dome"],
                                                          radiosity=True)
    with pytest.raises(anamorph.SceneError, match=r"color: value 5 is out of range"):
        dome(wall_color="5")
