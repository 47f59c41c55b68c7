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


class CMakeBuild(build_ext):
    def build_extension(self, ext: Extension) -> None:
        build = pathlib.Path(os.environ.get("ANAMORPH_BUILD_DIR") or
                             pathlib.Path(self.build_temp).resolve() / "cmake")
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


setup(
    version=version(),
    packages=["anamorph"],
    package_dir={"": "python"},
    package_data={"anamorph": ["__init__.pyi", "py.typed"]},
    ext_modules=[Extension("anamorph._anamorph", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
)
