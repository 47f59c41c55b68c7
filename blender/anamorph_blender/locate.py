"""Finds and imports the anamorph Python module (no bpy here).

Where it looks, in order:
  1. the add-on preference "anamorph module folder" (a folder holding the anamorph package),
  2. the environment variable ANAMORPH_PYTHONPATH,
  3. the build folder recorded by scripts/package-blender-addon (_build_location.py),
  4. the build folder of the repository the add-on is run from (<repo>/build/python),
  5. an installed module (`import anamorph` as is: pip install into Blender's Python).
The module must be built for the Python Blender runs (its version is in the message).
"""

import importlib
import os
import sys

_HERE = os.path.dirname(os.path.abspath(__file__))


class NotFound(RuntimeError):
    """The anamorph module could not be imported; the message says where it looked and why."""


def _recorded():
    try:
        from . import _build_location  # written by scripts/package-blender-addon
    except ImportError:
        return None
    return getattr(_build_location, "PYTHON_DIR", None)


def candidates(preference=""):
    """The folders to try, each with where it came from."""
    out = []
    if preference:
        out.append((os.path.abspath(os.path.expanduser(preference)), "add-on preference"))
    env = os.environ.get("ANAMORPH_PYTHONPATH", "")
    for part in filter(None, env.split(os.pathsep)):
        out.append((os.path.abspath(part), "ANAMORPH_PYTHONPATH"))
    recorded = _recorded()
    if recorded:
        out.append((recorded, "recorded by scripts/package-blender-addon"))
    repo_build = os.path.normpath(os.path.join(_HERE, "..", "..", "build", "python"))
    out.append((repo_build, "the repository's build"))
    return out


def _has_package(folder):
    return os.path.isfile(os.path.join(folder, "anamorph", "__init__.py"))


def import_anamorph(preference=""):
    """The anamorph module, or NotFound with every place tried and why each failed."""
    if "anamorph" in sys.modules:
        return sys.modules["anamorph"]
    tried = []
    for folder, origin in candidates(preference):
        if not _has_package(folder):
            tried.append(f"{folder} ({origin}): no anamorph package there")
            continue
        sys.path.insert(0, folder)
        try:
            return importlib.import_module("anamorph")
        except ImportError as e:
            sys.path.remove(folder)
            sys.modules.pop("anamorph", None)
            tried.append(f"{folder} ({origin}): {e}")
    try:
        return importlib.import_module("anamorph")
    except ImportError as e:
        tried.append(f"installed module: {e}")
    py = "%d.%d" % sys.version_info[:2]
    raise NotFound(
        "anamorph: the Python module was not found (Blender runs Python " + py + "). Tried:\n  "
        + "\n  ".join(tried)
        + "\nBuild it with `scripts/build _anamorph` in the anamorph repository, then set its "
        "build/python folder in the add-on's preferences or in ANAMORPH_PYTHONPATH.")
