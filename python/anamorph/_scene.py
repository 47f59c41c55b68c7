"""Scenes: loaded from a scene file with ``set=`` overrides, described, and rendered into NumPy
arrays."""

from __future__ import annotations

import os
import re
from typing import Any, Callable, Mapping, Sequence

import numpy as np

from . import _anamorph, _toml
from ._camera import Camera


class Scene:
    """A loaded scene (``anamorph.load``). The acceleration structure is built on the first
    render (or ``info()``) and kept for the next ones."""

    def __init__(self, impl: Any):
        self._impl = impl

    def info(self) -> dict[str, Any]:
        """What the scene holds, as ``anamorph info`` prints it: path, width, height,
        integrator, antialias, spp, sampler, camera, triangles, shapes, materials, lights,
        bounds, animated keys and warnings; ``objects``: the name of each object id the
        ``id`` layer holds (a glTF node's or a shape's name)."""
        return self._impl.info()

    @property
    def camera(self) -> Camera:
        """The scene's camera at the scene's image size."""
        return Camera._wrap(self._impl.camera())

    @property
    def warnings(self) -> list[str]:
        return self._impl.warnings()

    @property
    def last_stats(self) -> dict[str, Any]:
        """The last render's seconds, rays, samples and dropped NaN samples."""
        return self._impl.last_stats()

    def form_factors(self, samples: int = 2048, rays: int = 256, *,
                     objects: Sequence[str] = (), inward: Sequence[str] = (), seed: int = 0,
                     radiosity: bool = False, depth: int = 64) -> dict[str, Any]:
        """Form factors between the scene's objects, as ``anamorph formfactors`` measures them
        (docs/formfactors.md): ``samples`` points per object, ``rays`` hemisphere-camera
        samples per point. Returns ``objects`` (names), ``areas``, ``rows`` (the measured
        objects), ``columns`` (the objects, then ``"environment"``), ``F`` and ``stderr`` as
        (rows, columns) arrays, ``reciprocity_worst_z``, ``unmeasured`` (name: why an object
        has no row, e.g. an infinite plane) and ``notes`` (a name changed to keep names unique:
        an object named "environment" is listed as "environment#2"); with ``radiosity`` also
        ``radiosity`` (B per object, RGB) and the path tracer's ``path_radiance`` and
        ``path_radiance_stderr`` (compare with B / pi). An unknown name is a ValueError; so is a
        count outside the CLI's ranges (``_anamorph.FORM_FACTOR_LIMITS``)."""
        lim = _anamorph.FORM_FACTOR_LIMITS
        samples, rays, depth, seed = (_toml.integer(k, v, *lim[k]) for k, v in (
            ("samples", samples), ("rays", rays), ("depth", depth), ("seed", seed)))
        return self._impl.form_factors(samples, rays, list(objects), list(inward), seed,
                                       radiosity, depth)

    def render(self, width: int | None = None, height: int | None = None, spp: int | None = None,
               aovs: Sequence[str] = (), threads: int = 0,
               progress: Callable[[dict[str, Any]], Any] | None = None, *,
               seed: int | None = None, integrator: str | None = None,
               sampler: str | None = None, denoise: bool = False,
               set: Mapping[str, Any] | None = None) -> dict[str, np.ndarray]:
        """Renders the scene as ``anamorph render`` does, with the same options (``spp`` implies
        uniform sampling). Returns float32 arrays of shape (H, W, C): ``rgba`` (linear colour,
        straight alpha) and one per AOV (albedo, normal, depth, position, id, uv, spp, distance,
        depth_z, position_camera, flow_forward, flow_backward, motion, ray_origin, ray_direction,
        coins; the flow and motion layers load the scene at frame + 1 and - 1 for the render).
        ``progress`` is called on this thread with a dict (fraction, seconds, rays, pass,
        passes); an exception from it, or Ctrl-C, cancels the render and is raised. The GIL is
        released while rendering. ``denoise`` is the CLI's ``--denoise`` (docs/denoise.md: uniform
        sampling, at least 2 samples; ValueError otherwise). ``set`` overrides keys of the view
        for this render only, as ``load``'s ``set`` (``{"camera.fov": 90}``, or a whole table:
        ``{"camera": {...}}``): keys under ``camera``, ``image`` and ``render``, which are read
        again while the geometry, lights and acceleration structure are kept; others raise
        ValueError, except ``object.N.transform`` (N the index of a mesh ``[[object]]`` table,
        as ``set`` addresses it; a whole table such as ``{"matrix": [...]}`` or keys under it):
        the object moves without a load (its instances take the new transform and the
        acceleration structure is posed again, as for a glTF animation's frames), giving the
        same pixels as a scene loaded with that transform. Objects not named are at their
        file's place; one that brought its model's lights or cameras cannot move so."""
        for k in set or ():
            if not isinstance(k, str) or not (k.split(".")[0] in _VIEW_TABLES
                                               or _OBJECT_TRANSFORM.fullmatch(k)):
                raise ValueError(f"render(set=...): {k!r} is not under camera, image or "
                                 "render, nor an object.N.transform (load the scene with it "
                                 "instead)")
        over = _toml.overrides(set)
        for key, v in (("image.width", width), ("image.height", height), ("render.spp", spp),
                       ("render.seed", seed), ("render.integrator", integrator),
                       ("render.sampler", sampler)):
            if v is not None:
                over.append(f"{key}={_toml.value(v)}")
        if isinstance(aovs, str):
            aovs = [a for a in aovs.split(",") if a]
        return self._impl.render(over, list(aovs), threads, progress, bool(denoise))

    def __repr__(self) -> str:
        i = self._impl.info()
        return f"<anamorph.Scene {i['path']} {i['width']}x{i['height']}>"


# The tables a render's `set` may override: what the scene reader reads again for a view.
_VIEW_TABLES = ("camera", "image", "render")
# An object's transform, which a render's `set` may override too (the object moves, no load).
_OBJECT_TRANSFORM = re.compile(r"object\.[0-9]+\.transform(\..+)?")


def load(path: str | os.PathLike[str], set: Mapping[str, Any] | None = None,
         frame: float = 0) -> Scene:
    """Loads a scene file. ``set`` overrides keys by their dotted path, like the CLI's ``--set``
    (``{"camera.fov": 90, "camera.coin.0.strength": 0.8}``); ``frame`` evaluates the scene's
    ``[[animate]]`` keys. A bad scene raises SceneError (a ValueError) naming the file, line,
    column and key."""
    return Scene(_anamorph.Scene(os.fspath(path), _toml.overrides(set), float(frame)))


def loads(text: str, set: Mapping[str, Any] | None = None, frame: float = 0) -> Scene:
    """A scene from TOML text (relative file names resolve against the working directory)."""
    return Scene(_anamorph.Scene.from_text(text, _toml.overrides(set), float(frame)))
