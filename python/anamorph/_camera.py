"""Cameras: built from keyword arguments (a preset or an org/dir composition with coins) or
taken from a scene, and their ray fields, rays at sample positions and inverse map as NumPy
arrays."""

from __future__ import annotations

import inspect
from typing import Any, Iterator, Mapping, NamedTuple, Sequence

import numpy as np

from . import _anamorph, _toml
from ._functions import _DECLARATIONS, describe_param, rename_key, signature

_IMAGE = {s["name"]: s for s in _DECLARATIONS["image"]}
_DEFAULT_WIDTH = int(_IMAGE["width"]["default"])
_DEFAULT_HEIGHT = int(_IMAGE["height"]["default"])


class Coin(Mapping[str, Any]):
    """A center of interest: a world point the camera magnifies locally (the paper's coins).
    Checked when made, by the scene reader ([[camera.coin]])."""

    def __init__(self, **values: Any):
        self._values = dict(values)
        text = "[[camera.coin]]\n" + "\n".join(
            f"{_toml.key(k)} = {_toml.value(v)}" for k, v in self._values.items())
        try:
            _anamorph.Camera.from_text(text, "<anamorph.Coin>")
        except _anamorph.SceneError as e:
            raise rename_key(e, "camera.coin[0].", "coin.") from None

    def _toml_table(self) -> dict[str, Any]:
        return dict(self._values)

    def __getitem__(self, k: str) -> Any:
        return self._values[k]

    def __iter__(self) -> Iterator[str]:
        return iter(self._values)

    def __len__(self) -> int:
        return len(self._values)

    def __repr__(self) -> str:
        return "anamorph.Coin(" + ", ".join(f"{k}={v!r}" for k, v in self._values.items()) + ")"


Coin.__init__.__signature__ = signature(  # type: ignore[attr-defined]
    _DECLARATIONS["coin"], [inspect.Parameter("self", inspect.Parameter.POSITIONAL_ONLY)])
Coin.__doc__ += "\n\nKeyword arguments:\n" + "\n".join(
    "  " + describe_param(p) for p in _DECLARATIONS["coin"])


class Projection(NamedTuple):
    """Every image position of each point: point i is seen at ``uv[offsets[i]:offsets[i+1]]``
    (u, v in [0, 1], u left to right, v top to bottom); none when the camera does not see it,
    several when it sees it more than once."""

    uv: np.ndarray  # (M, 2) float64
    offsets: np.ndarray  # (N + 1,) uint64
    width: int
    height: int

    @property
    def pixels(self) -> np.ndarray:
        """``uv`` in pixels from the top-left corner, as ``anamorph project`` prints them."""
        return self.uv * np.array([self.width, self.height], dtype=np.float64)

    def of(self, i: int) -> np.ndarray:
        """The (k, 2) image positions of point i."""
        return self.uv[int(self.offsets[i]):int(self.offsets[i + 1])]


class Solved(NamedTuple):
    """What ``Camera.solve`` found: the solved camera, each free number (name, start, value, min,
    max, at_bound), each constraint's residual (where, kind, residual, unit, tolerance, met;
    when not met, met_alone and the constraints it conflicts with), as ``anamorph solve``
    prints them."""

    camera: "Camera"
    values: list[dict[str, Any]]
    constraints: list[dict[str, Any]]
    iterations: int
    termination: str
    met: bool


class Camera:
    """A virtual camera: org(u, v) and dir(u, v) for an image of ``width`` x ``height`` pixels.

    ``Camera("fisheye", fov=180)`` builds a preset; ``Camera(org=anamorph.org.bspline(...),
    dir=anamorph.dir.normal(), coins=[anamorph.Coin(...)])`` a composition. Every other keyword
    is a key of the scene format's ``[camera]`` table (docs/scene-format.md), checked by the same
    reader, so a bad one raises ``SceneError`` (a ValueError) naming the key, with a suggestion
    for a misspelt one."""

    def __init__(self, preset: str | None = None, *, width: int | None = None,
                 height: int | None = None, org: Mapping[str, Any] | None = None,
                 dir: Mapping[str, Any] | None = None, coins: Sequence[Mapping[str, Any]] = (),
                 **keys: Any):
        table: dict[str, Any] = {}
        if preset is not None:
            table["preset"] = preset
        table.update(keys)
        if org is not None:
            table["org"] = org
        if dir is not None:
            table["dir"] = dir
        if coins:
            table["coin"] = list(coins)
        w = _DEFAULT_WIDTH if width is None else width
        h = _DEFAULT_HEIGHT if height is None else height
        lines = ["[image]", f"width = {_toml.value(w)}", f"height = {_toml.value(h)}", "[camera]"]
        lines += [f"{_toml.key(k)} = {_toml.value(v)}" for k, v in table.items()]
        self._impl = _anamorph.Camera.from_text("\n".join(lines) + "\n", "<anamorph.Camera>")

    @classmethod
    def _wrap(cls, impl: Any) -> "Camera":
        cam = cls.__new__(cls)
        cam._impl = impl
        return cam

    @property
    def width(self) -> int:
        return self._impl.width

    @property
    def height(self) -> int:
        return self._impl.height

    @property
    def toml(self) -> str:
        """The ``[camera]`` table this camera was read from, as TOML."""
        return self._impl.toml()

    @property
    def warnings(self) -> list[str]:
        return self._impl.warnings()

    @property
    def coins(self) -> list[dict[str, Any]]:
        """The coins with their image positions: coin (index), uv = (uc, vc), radius, strength,
        stiffness. Coins the camera does not see are absent."""
        return self._impl.coins()

    def resized(self, width: int, height: int) -> "Camera":
        """The same camera for a ``width`` x ``height`` image (presets follow the aspect ratio)."""
        w, h = (_toml.integer(f"image.{k}", v, int(_IMAGE[k]["min"]), int(_IMAGE[k]["max"]))
                for k, v in (("width", width), ("height", height)))
        return Camera._wrap(self._impl.resized(w, h))

    def rays(self, width: int | None = None, height: int | None = None, *,
             differentials: bool = True, threads: int = 0) -> dict[str, np.ndarray]:
        """The rays at every pixel center, as ``anamorph rays`` writes them: ``org`` and ``dir``
        (H, W, 3) float64 (unit directions), ``valid`` (H, W) bool (False: no ray there; its
        values are zero), and with ``differentials`` the derivatives ``dorg_du``, ``dorg_dv``,
        ``ddir_du``, ``ddir_dv`` (H, W, 3) with respect to u and v in [0, 1]."""
        cam = self._at(width, height)
        return cam._impl.rays(differentials, threads)

    def generate(self, u: Any, v: Any, *, lens: Any = None, time: Any = None,
                 differentials: bool = True, threads: int = 0) -> dict[str, np.ndarray]:
        """Rays at image positions (u, v) (arrays of one shape S, values in [0, 1]); optional
        ``lens`` positions, shape S + (2,) in [0, 1) (depth of field), and shutter ``time``,
        shape S. The same keys as ``rays``, each of shape S + (3,) (``valid``: S)."""
        u_arr, v_arr = np.broadcast_arrays(np.asarray(u, dtype=np.float64),
                                           np.asarray(v, dtype=np.float64))
        shape = u_arr.shape
        flat = lambda a: np.ascontiguousarray(a, dtype=np.float64).reshape(-1)
        lu = lv = t = None
        if lens is not None:
            lens_arr = np.broadcast_to(np.asarray(lens, dtype=np.float64), shape + (2,))
            lu, lv = flat(lens_arr[..., 0]), flat(lens_arr[..., 1])
        if time is not None:
            t = flat(np.broadcast_to(np.asarray(time, dtype=np.float64), shape))
        out = self._impl.generate(flat(u_arr), flat(v_arr), lu, lv, t, differentials, threads)
        return {k: a.reshape(shape + a.shape[1:]) for k, a in out.items()}

    def project(self, points: Any, *, threads: int = 0) -> Projection:
        """The inverse map: every image position where each of the (N, 3) world points appears
        (see Projection)."""
        pts = np.ascontiguousarray(np.asarray(points, dtype=np.float64).reshape(-1, 3))
        uv, offsets = self._impl.project(pts, threads)
        return Projection(uv, offsets, self.width, self.height)

    def stmap(self, source: str, *, width: int | None = None, height: int | None = None,
              inverse: bool = False, source_size: tuple[int, int] | None = None,
              threads: int = 0, depth: float | None = None) -> dict[str, np.ndarray]:
        """The camera as an STMap to a source projection (``"equirect"``, ``"cubemap[:3x2]"``,
        ``"fisheye:FOV[:ASPECT]"``, ``"perspective:FOV[:ASPECT]"``), what ``anamorph stmap``
        writes (docs/compositing.md): ``st`` (H, W, 2) float32, s left to right and t from the
        *bottom* of the source, pixel centers at (x + 0.5) / W; ``alpha`` (H, W) (1 where the
        pixel has a ray the source shows); ``direction`` (H, W, 3) unit world directions.
        ``inverse``: the map the other way, at ``source_size`` (W, H; default the camera's width
        and the projection's aspect). A camera whose rays leave different points raises
        ValueError unless ``depth`` is given: the map is then exact at that distance from the
        rays' mean origin (as ``stmap --depth``)."""
        cam = self._at(width, height)
        sw, sh = (0, 0) if source_size is None else (int(source_size[0]), int(source_size[1]))
        if source_size is not None and not (1 <= sw <= 65536 and 1 <= sh <= 65536):
            raise ValueError(f"source_size {source_size}: each in [1, 65536]")
        if depth is not None and not depth > 0:
            raise ValueError(f"depth {depth}: a distance > 0")
        return cam._impl.stmap(source, inverse, sw, sh, threads, float(depth or 0.0))

    def solve(self, constraints: Sequence[Mapping[str, Any]],
              free: Sequence[str | Mapping[str, Any]], *, check: bool = True,
              **options: Any) -> Solved:
        """Solves the ``free`` keys of this camera for ``constraints``, as ``anamorph solve``
        (docs/solve.md): each constraint a mapping of a ``[[camera.constraint]]`` entry
        (``{"kind": "pin", "point": [1, 0, 0], "uv": [0.6, 0.5]}``), each free key its dotted
        name (``"camera.fov"``, ``"camera.org.points.1.2.0"``) or a ``[[camera.free]]`` mapping
        (key, min, max); ``options`` are ``[camera.solve]``'s keys (loss, loss_scale,
        max_iterations). Points only: objects are the scene's (solve a scene file with
        ``anamorph solve``). With ``check``, a constraint not met raises ValueError naming it
        and what it conflicts with; otherwise see ``Solved.met``."""
        lines = ["[image]", f"width = {self.width}", f"height = {self.height}", "[camera]",
                 self.toml]
        for c in constraints:
            lines.append("[[camera.constraint]]")
            lines += [f"{_toml.key(k)} = {_toml.value(v)}" for k, v in c.items()]
        for f in free:
            lines.append("[[camera.free]]")
            entry = {"key": f} if isinstance(f, str) else f
            lines += [f"{_toml.key(k)} = {_toml.value(v)}" for k, v in entry.items()]
        if options:
            lines.append("[camera.solve]")
            lines += [f"{_toml.key(k)} = {_toml.value(v)}" for k, v in options.items()]
        r = _anamorph.solve_text("\n".join(lines) + "\n", "<anamorph.Camera.solve>")
        out = Solved(Camera._wrap(r["camera"]), r["values"], r["constraints"], r["iterations"],
                     r["termination"], r["met"])
        if check and not out.met:
            raise ValueError("constraints not met:\n" + "\n".join(
                f"  {c['where']} ({c['kind']}): residual {c['residual']:g} {c['unit']}"
                + (f", conflicts with {', '.join(c['conflicts'])}" if c["conflicts"] else
                   "" if c["met_alone"] else ", not met even alone")
                for c in out.constraints if not c["met"]))
        return out

    def describe(self) -> str:
        return self._impl.describe()

    def __repr__(self) -> str:
        return f"<anamorph.Camera {self.width}x{self.height}: {self.describe()}>"

    def _at(self, width: int | None, height: int | None) -> "Camera":
        if width is None and height is None:
            return self
        w = self.width if width is None else width
        h = self.height if height is None else height
        return self.resized(w, h)
