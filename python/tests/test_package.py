"""The package itself: stubs generated from the declarations, every declared function and
preset reachable from Python, and `pip install --no-build-isolation .` into a virtualenv."""

from __future__ import annotations

import ast
import inspect
import os
import pathlib
import shutil
import subprocess
import sys

import pytest

import anamorph
from anamorph import _stubs
from conftest import ROOT


def test_the_committed_stubs_are_generated_from_the_declarations():
    committed = (ROOT / "python/anamorph/__init__.pyi").read_text()
    assert committed == _stubs.stub_text(), (
        "python/anamorph/__init__.pyi is stale: run "
        "`scripts/python -m anamorph._stubs > python/anamorph/__init__.pyi`")
    ast.parse(committed)


def test_every_declared_function_has_a_python_factory_with_its_keywords():
    decl = anamorph.declarations()
    for kind, ns in (("org", anamorph.org), ("dir", anamorph.dir)):
        assert sorted(ns.__all__) == sorted(decl[kind])
        for name, d in decl[kind].items():
            sig = inspect.signature(getattr(ns, name))
            assert list(sig.parameters) == [p["name"] for p in d["params"]], name
            assert d["doc"] in getattr(ns, name).__doc__


def test_every_preset_builds_with_its_defaults():
    for preset, d in anamorph.declarations()["presets"].items():
        # The required keys (a lens's focal lengths) are all numbers above 0.
        required = {p["name"]: 12.0 for p in d["params"] if p["required"]}
        assert all(p["type"] == "number" for p in d["params"] if p["required"])
        cam = anamorph.Camera(preset, width=16, height=16, **required)
        assert cam.rays()["valid"].any(), preset


def test_the_public_names_are_documented():
    doc = (ROOT / "docs/python.md").read_text()
    for name in anamorph.__all__:
        assert f"`{name}" in doc or f"anamorph.{name}" in doc, f"docs/python.md lacks {name}"


@pytest.mark.skipif(not os.environ.get("ANAMORPH_BUILD_DIR"),
                    reason="set ANAMORPH_BUILD_DIR (ctest does) to reuse a configured build")
def test_pip_installs_into_a_virtualenv_offline(tmp_path):
    venv = tmp_path / "venv"
    subprocess.run(["/usr/bin/python3", "-m", "venv", "--system-site-packages", venv],
                   check=True)
    py = venv / "bin/python"
    env = dict(os.environ, PIP_NO_INDEX="1", PIP_DISABLE_PIP_VERSION_CHECK="1")
    env.pop("PYTHONPATH", None)
    src = tmp_path / "src"  # pip builds in the tree it is given: a copy keeps the checkout clean
    shutil.copytree(ROOT, src, ignore=shutil.ignore_patterns(
        "build*", ".git", "node_modules", "__pycache__"))
    p = subprocess.run([py, "-m", "pip", "install", "--no-build-isolation", "-q", src],
                       env=env, capture_output=True, text=True, cwd=tmp_path)
    assert p.returncode == 0, p.stdout + p.stderr
    check = ("import anamorph, os, pathlib; c = anamorph.Camera('fisheye', fov=180, width=8, "
             "height=8); assert c.rays()['valid'].sum() > 0; print(anamorph.__file__); "
             "h = pathlib.Path(anamorph.__file__).parent / 'anamorph-loader'; "
             "assert os.access(h, os.X_OK), f'{h} is not installed'; "
             f"anamorph.load({str(src / 'examples/demo.toml')!r})")  # (an OBJ: the loader)
    p = subprocess.run([py, "-c", check], env=env, capture_output=True, text=True, cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert str(venv) in p.stdout


def test_a_python_without_wheel_is_told_what_to_do():
    """pip's metadata step (`setup.py dist_info`) with a setuptools older than 70.1 and no `wheel`
    package (a pyenv or conda python3): setup.py says which Python to use instead of setuptools'
    "invalid command 'bdist_wheel'"."""
    try:
        import setuptools.command.bdist_wheel  # noqa: F401
        pytest.skip("this setuptools builds wheels itself (70.1 or later): nothing to check")
    except ImportError:
        pass
    code = ("import runpy, sys; sys.modules['wheel'] = None; sys.argv = ['setup.py', 'dist_info']; "
            "runpy.run_path('setup.py', run_name='__main__')")
    p = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True)
    assert p.returncode == 1, p.stdout + p.stderr
    assert "needs the Python package `wheel`" in p.stderr, p.stderr
    assert "/usr/bin/python3 -m venv --system-site-packages venv" in p.stderr, p.stderr
    assert "invalid command" not in p.stderr, p.stderr
