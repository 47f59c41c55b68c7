"""anamorph: a ray tracer built around a programmable distortion camera.

    import anamorph
    scene = anamorph.load("examples/basic.toml", set={"camera.fov": 90})
    img = scene.render(width=320, height=240)          # {"rgba": (240, 320, 4) float32}
    cam = anamorph.Camera("fisheye", fov=180, width=512, height=512)
    rays = cam.rays()                                  # org, dir, valid, differentials

See docs/python.md.
"""

from __future__ import annotations

import json
import os
from typing import Any

import numpy as np

from . import _anamorph
from ._anamorph import SceneError
from ._camera import Camera, Coin, Projection, Solved
from ._functions import Function, dir, org
from ._scene import Scene, load, loads

__version__: str = _anamorph.__version__
__all__ = ["Camera", "Coin", "Function", "Projection", "Scene", "SceneError", "declarations",
           "Solved", "dir", "load", "loads", "org", "read_exr", "schema", "warp"]


def schema() -> dict[str, Any]:
    """The scene format as a JSON Schema (draft 2020-12), the one ``anamorph schema`` writes."""
    return json.loads(_anamorph.schema_json())


def declarations() -> dict[str, Any]:
    """Every declared parameter (presets, org/dir functions, coin, camera, image, render): name,
    type, default, range, unit, choices and doc, as the C++ tables declare them."""
    return _anamorph.declarations()


def warp(camera: Camera, image: str | os.PathLike[str] | np.ndarray, source: str, *,
         filter: str = "area", width: int | None = None, height: int | None = None,
         threads: int = 0) -> np.ndarray:
    """An image in a source projection (``"equirect"``, ``"cubemap[:3x2]"``,
    ``"fisheye:FOV[:ASPECT]"``, ``"perspective:FOV[:ASPECT]"``) reprojected through the camera
    without rendering, what ``anamorph warp`` writes (docs/compositing.md): an (H, W, 4) float32
    array of linear RGBA at the camera's size (or ``width`` x ``height``), alpha 0 where the
    camera has no ray or the source does not show its direction. ``image``: a file (PNG, JPEG,
    EXR, HDR; 8-bit files are sRGB, read as the CLI reads them) or an (H, W[, C]) array of
    linear values, C in 1..4. ``filter``: ``"area"`` (default), ``"bilinear"``, ``"aniso"`` or
    ``"bicubic"`` (as ``warp --filter``). A camera whose rays leave different points, or an
    image whose aspect does not fit the source, raises ValueError (SceneError for the
    latter)."""
    cam = camera._at(width, height)
    img = os.fspath(image) if isinstance(image, (str, os.PathLike)) else image
    return _anamorph.warp(cam._impl, img, source, filter, threads)


def read_exr(path: str | os.PathLike[str]) -> dict[str, np.ndarray]:
    """The layers of an EXR as anamorph writes them (``render -o x.exr``, ``rays -o x.exr``):
    float32 arrays of shape (H, W, C) keyed as ``Scene.render`` returns them: ``rgba`` for the
    unnamed R, G, B, A channels, else the layer name (``albedo``, ``org``, ...), channels in
    the order the file's layer names them (X, Y, Z / R, G, B / ...)."""
    channels = _anamorph.read_exr_channels(os.fspath(path))
    order = {"R": 0, "G": 1, "B": 2, "A": 3, "X": 0, "Y": 1, "Z": 2, "U": 0, "V": 1}
    layers: dict[str, list[tuple[str, np.ndarray]]] = {}
    for name, data in channels.items():
        layer, _, channel = name.rpartition(".")
        layers.setdefault(layer or "rgba", []).append((channel, data))
    return {name: np.stack([d for _, d in sorted(chs, key=lambda c: (order.get(c[0], 9), c[0]))],
                           axis=-1)
            for name, chs in layers.items()}
