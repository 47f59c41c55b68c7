"""Shared pieces of the Python API's tests: the repository, the CLI binary beside the module
(ANAMORPH_BINARY, set by ctest) and a runner for it."""

from __future__ import annotations

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
BINARY = os.environ.get("ANAMORPH_BINARY", str(ROOT / "build" / "anamorph"))


def cli(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    """Runs `anamorph ARGS...`; returns the finished process (stdout, stderr as text)."""
    p = subprocess.run([BINARY, *map(str, args)], capture_output=True, text=True)
    if check and p.returncode != 0:
        raise AssertionError(f"anamorph {' '.join(map(str, args))} exited {p.returncode}:\n"
                             f"{p.stderr}")
    return p


@pytest.fixture
def root() -> pathlib.Path:
    return ROOT


def read_exr(path) -> dict:
    """An EXR's channels by name, as float32 arrays (H, W); skips without OpenImageIO."""
    oiio = pytest.importorskip("OpenImageIO")
    i = oiio.ImageInput.open(str(path))
    names = i.spec().channelnames
    a = i.read_image(format="float")
    i.close()
    return {n: a[..., k] for k, n in enumerate(names)}
