"""``anamorph.org`` and ``anamorph.dir``: one function per origin / direction function type the
C++ registry declares, with its keyword arguments, defaults and documentation taken from the
declarations (a parameter added in C++ appears here with no Python code)."""

from __future__ import annotations

import inspect
import tomllib
import types
from typing import Any, Iterator, Mapping

from . import _anamorph, _toml

_DECLARATIONS = _anamorph.declarations()


def default_value(spec: Mapping[str, Any]) -> Any:
    """A declared default (TOML text) as a Python value; inspect.Parameter.empty when none."""
    if spec["required"]:
        return inspect.Parameter.empty
    if spec["default"] is None:  # optional, no default (or one that depends on other keys)
        return None
    return tomllib.loads("v = " + spec["default"])["v"]


def describe_param(spec: Mapping[str, Any]) -> str:
    """One line of a docstring: name (type, unit, range): doc."""
    facts = [spec["type"].lower()]
    if spec["unit"]:
        facts.append(spec["unit"])
    lo, hi = spec["min"], spec["max"]  # None: unbounded
    if lo is not None or hi is not None:
        lo = float("-inf") if lo is None else lo
        hi = float("inf") if hi is None else hi
        left = "(" if spec["min_exclusive"] else "["
        right = ")" if spec["max_exclusive"] else "]"
        facts.append(f"in {left}{lo:g}, {hi:g}{right}")
    if spec["choices"]:
        facts.append("one of " + ", ".join(spec["choices"]))
    if spec["required"]:
        facts.append("required")
    elif spec["default"] is not None:
        facts.append("default " + spec["default"])
    elif spec["default_note"]:
        facts.append("default: " + spec["default_note"])
    return f"{spec['name']} ({'; '.join(facts)}): {spec['doc']}"


def signature(specs: list[Mapping[str, Any]], extra: list[inspect.Parameter] = ()) -> inspect.Signature:
    params = list(extra)
    for s in specs:
        params.append(
            inspect.Parameter(s["name"], inspect.Parameter.KEYWORD_ONLY, default=default_value(s)))
    return inspect.Signature(params)


class Function(Mapping[str, Any]):
    """An origin or direction function: its ``type`` and the keys given (the rest take their
    declared defaults). Checked when made, by the same reader and messages as a scene's
    ``[camera.org]`` / ``[camera.dir]``; pass it as ``Camera(org=..., dir=...)``."""

    def __init__(self, kind: str, type_: str, values: Mapping[str, Any]):
        self.kind = kind
        self.type = type_
        self._values = dict(values)
        # Checked inside a camera, by the scene reader: the same messages as a scene file. The
        # other function is one that goes with any: a constant direction, a plane of origins.
        other = ('[camera.dir]\ntype = "constant"' if kind == "org" else
                 '[camera.org]\ntype = "plane"')
        text = f"[camera.{kind}]\n" + "".join(
            f"{_toml.key(k)} = {_toml.value(v)}\n" for k, v in self._toml_table().items())
        try:
            _anamorph.Camera.from_text(text + other + "\n", f"<anamorph.{kind}>")
        except _anamorph.SceneError as e:
            raise rename_key(e, f"camera.{kind}.", f"{kind}.") from None

    def _toml_table(self) -> dict[str, Any]:
        return {"type": self.type, **self._values}

    def __getitem__(self, k: str) -> Any:
        return self._toml_table()[k]

    def __iter__(self) -> Iterator[str]:
        return iter(self._toml_table())

    def __len__(self) -> int:
        return len(self._values) + 1

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self._values.items())
        return f"anamorph.{self.kind}.{self.type}({args})"


def rename_key(err: Any, old: str, new: str) -> Any:
    """A SceneError for a key read inside a made-up scene, named as the caller wrote it."""
    key = err.key.replace(old, new, 1) if err.key.startswith(old) else err.key
    out = _anamorph.SceneError(f"{key}: {err.message}" if key else err.message)
    out.key, out.message, out.file, out.line, out.column = key, err.message, None, 0, 0
    return out


def _factory(kind: str, type_: str, decl: Mapping[str, Any]):
    def make(**values: Any) -> Function:
        return Function(kind, type_, values)

    make.__name__ = make.__qualname__ = type_
    make.__signature__ = signature(decl["params"])
    make.__doc__ = decl["doc"] + "\n\nKeyword arguments:\n" + "\n".join(
        "  " + describe_param(p) for p in decl["params"])
    return make


def _namespace(kind: str, title: str) -> types.ModuleType:
    ns = types.ModuleType(f"anamorph.{kind}", title)
    for type_, decl in _DECLARATIONS[kind].items():
        setattr(ns, type_, _factory(kind, type_, decl))
    ns.__all__ = sorted(_DECLARATIONS[kind])
    return ns


org = _namespace("org", "Origin functions org(u, v): where each ray starts.")
dir = _namespace("dir", "Direction functions dir(u, v): where each ray goes.")
