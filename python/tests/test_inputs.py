"""Inputs that are not regular files, and requests larger than the machine, from Python: each
is refused at once with an exception that says what is wrong, in bounded memory. Before, /dev/zero
given to `load` or `read_exr` grew to the address limit, a FIFO blocked the interpreter (Ctrl-C
ignored), and `render(width=65536, height=65536)` allocated 7.8 GB before its MemoryError.

Each case runs in a child interpreter limited to 4 GiB of address space and 60 s."""

from __future__ import annotations

import os
import resource
import socket
import subprocess
import sys

import pytest

from conftest import ROOT

KINDS = {
    "zero": "is a character device, not a regular file",
    "urandom": "is a character device, not a regular file",
    "fifo": "is a FIFO, not a regular file",
    "dir": "is a directory",
    "socket": "is a socket, not a regular file",
}


@pytest.fixture
def kinds(tmp_path):
    """A file of each kind in tmp_path, by name."""
    (tmp_path / "zero").symlink_to("/dev/zero")
    (tmp_path / "urandom").symlink_to("/dev/urandom")
    os.mkfifo(tmp_path / "fifo")
    (tmp_path / "dir").mkdir()
    s = socket.socket(socket.AF_UNIX)
    s.bind(str(tmp_path / "socket"))
    yield tmp_path
    s.close()


def run_bounded(code: str) -> subprocess.CompletedProcess:
    """`code` in a new interpreter with the anamorph package, under a 4 GiB address limit."""
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))
    return subprocess.run([sys.executable, "-c", "import anamorph\n" + code],
                          capture_output=True, text=True, timeout=60, preexec_fn=limit,
                          env=os.environ.copy())


@pytest.mark.parametrize("kind", sorted(KINDS))
@pytest.mark.parametrize("call", ["anamorph.load", "anamorph.read_exr"])
def test_files_that_are_not_regular_raise_at_once(kinds, kind, call):
    path = kinds / kind
    p = run_bounded(f"""
try:
    {call}({str(path)!r})
except ValueError as e:
    print("ValueError:", e)
""")
    assert p.returncode == 0, p.stderr
    assert "ValueError:" in p.stdout and KINDS[kind] in p.stdout, p.stdout + p.stderr


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_a_scene_naming_such_a_file_raises_at_once(kinds, kind):
    scene = kinds / "scene.toml"
    scene.write_text(f'[image]\nwidth = 8\nheight = 8\n[environment]\nfile = "{kinds / kind}"\n')
    p = run_bounded(f"""
try:
    anamorph.load({str(scene)!r})
except anamorph.SceneError as e:
    print("SceneError:", e.key, e.message)
""")
    assert p.returncode == 0, p.stderr
    assert "SceneError: environment.file" in p.stdout and KINDS[kind] in p.stdout, \
        p.stdout + p.stderr


def test_a_render_larger_than_the_machine_is_a_memory_error_up_front():
    p = run_bounded(f"""
scene = anamorph.load({str(ROOT / "examples/demo.toml")!r})
try:
    scene.render(width=65536, height=65536)
except MemoryError as e:
    print("MemoryError:", e)
img = scene.render(width=16, height=12)
print("then", img["rgba"].shape)
""")
    assert p.returncode == 0, p.stderr
    # The CLI's itemized estimate (render/memory_estimate.h), not an allocation's failure.
    assert "MemoryError: this render needs about" in p.stdout, p.stdout + p.stderr
    assert "film (65536 x 65536 pixels x 32 B) 128.0 GiB" in p.stdout, p.stdout
    assert "then (12, 16, 4)" in p.stdout, p.stdout


def test_rays_larger_than_the_machine_are_a_memory_error_up_front():
    p = run_bounded("""
cam = anamorph.Camera("fisheye", fov=180, width=8, height=8)
try:
    cam.rays(65536, 65536)
except MemoryError as e:
    print("MemoryError:", e)
""")
    assert p.returncode == 0, p.stderr
    assert "MemoryError: these rays need about" in p.stdout, p.stdout + p.stderr
