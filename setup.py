"""Builds the `anamorph._anamorph` extension with the project's CMake build (the same targets,
flags and dependencies as scripts/build) for `pip install --no-build-isolation .`.
ANAMORPH_BUILD_DIR reuses an already configured build tree instead of a fresh one."""

import os
import pathlib
import re
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


def version() -> str:
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(anamorph VERSION ([0-9.]+)", text).group(1)


def require_wheel() -> None:
    """pip builds a wheel with `setup.py bdist_wheel`: setuptools has that command itself from
    70.1 on, older ones (Debian 12's 66.1) take it from the `wheel` package. Without either pip
    fails with "invalid command 'bdist_wheel'", which says nothing of the cause."""
    if not {"bdist_wheel", "dist_info", "editable_wheel"} & set(sys.argv[1:]):
        return  # (pip's metadata step, dist_info, runs bdist_wheel's options too)
    try:
        import setuptools.command.bdist_wheel  # noqa: F401  (setuptools >= 70.1)
        return
    except ImportError:
        pass
    try:
        import wheel  # noqa: F401
    except ImportError:
        import setuptools
        sys.exit(
            f"error: building anamorph's wheel needs the Python package `wheel` with this "
            f"setuptools ({setuptools.__version__}), and {sys.executable} has none.\n"
            f"Use Debian's Python, whose python3-wheel, python3-setuptools and python3-numpy "
            f"scripts/install-deps installs:\n"
            f"  /usr/bin/python3 -m venv --system-site-packages venv\n"
            f"  venv/bin/pip install -v --no-build-isolation .\n"
            f"or install `wheel` into this environment first (`pip install wheel`, which needs "
            f"the network).")


class CMakeBuild(build_ext):
    def build_extension(self, ext: Extension) -> None:
        build = pathlib.Path(os.environ.get("ANAMORPH_BUILD_DIR") or
                             pathlib.Path(self.build_temp).resolve() / "cmake")
        # pip shows this, and CMake's progress below, only with -v: without it a first build is
        # minutes of a spinner (docs/python.md says so).
        print(f"anamorph: building the C++ module with CMake in {build} (several minutes the "
              f"first time)", file=sys.stderr, flush=True)
        if not (build / "CMakeCache.txt").exists():
            subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build), "-G", "Ninja",
                            "-DCMAKE_BUILD_TYPE=Release", "-DANAMORPH_TESTS=OFF",
                            "-DANAMORPH_BENCH=OFF", "-DANAMORPH_PYTHON=ON",
                            f"-DPython_EXECUTABLE={sys.executable}"], check=True)
        subprocess.run(["cmake", "--build", str(build), "--target", "_anamorph"], check=True)
        built = next((build / "python" / "anamorph").glob("_anamorph.*.so"))
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)
        # The program the module starts to read models with assimp (src/scene/isolated.h).
        shutil.copy2(build / "anamorph-loader", target.parent / "anamorph-loader")


require_wheel()
setup(
    version=version(),
    packages=["anamorph"],
    package_dir={"": "python"},
    package_data={"anamorph": ["__init__.pyi", "py.typed"]},
    ext_modules=[Extension("anamorph._anamorph", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
)
