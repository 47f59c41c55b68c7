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
