"""Python values as TOML text, so keyword arguments and ``set=`` overrides reach the scene reader
exactly as a scene file would (the same checks and messages)."""

from __future__ import annotations

import json
import math
import operator
import re
from typing import Any, Mapping

from . import _anamorph

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")
_MAX_FLOAT = int(1.7976931348623157e308)  # the largest double, as an int


def key(k: str) -> str:
    """A TOML key: bare when it can be, else quoted."""
    if not isinstance(k, str):
        raise TypeError(f"keys must be strings, not {type(k).__name__}")
    return k if _BARE_KEY.match(k) else _string(k)


def _string(s: str) -> str:
    # JSON's escapes are TOML's, except that TOML forbids a raw DEL and has no surrogate pairs.
    return json.dumps(s, ensure_ascii=False).replace("\x7f", "\\u007f")


def value(v: Any) -> str:
    """TOML text of a bool, int, float, str, sequence (list, tuple, NumPy array), mapping or
    anything with ``_toml_table()`` (the package's Coin and function objects)."""
    if hasattr(v, "_toml_table"):
        v = v._toml_table()
    if hasattr(v, "tolist") and not isinstance(v, (str, bytes)):  # NumPy arrays and scalars
        v = v.tolist()
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        # TOML integers have 64 bits; a larger one goes as a number, so that the key's reader
        # says it is out of the key's range (not a syntax error, or "got a string").
        if -2**63 <= v < 2**63:
            return str(v)
        return repr(float(max(-_MAX_FLOAT, min(v, _MAX_FLOAT))))
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        text = repr(v)  # the shortest text that reads back as the same double
        return text if any(c in text for c in ".en") else text + ".0"
    if isinstance(v, str):
        return _string(v)
    if isinstance(v, Mapping):
        return "{" + ", ".join(f"{key(k)} = {value(x)}" for k, x in v.items()) + "}"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(value(x) for x in v) + "]"
    raise TypeError(f"cannot pass a {type(v).__name__} as a scene value")


def overrides(values: Mapping[str, Any] | None) -> list[str]:
    """``{"camera.fov": 90}`` as ``["camera.fov=90"]``, the form of the CLI's ``--set``."""
    if not values:
        return []
    out = []
    for k, v in values.items():
        if not isinstance(k, str) or not k:
            raise TypeError("set= keys must be dotted key strings such as 'camera.fov'")
        out.append(f"{k}={value(v)}")
    return out


def scene_error(key: str, message: str) -> ValueError:
    """A SceneError as the C++ reader raises it for a keyword (no file): "key: message"."""
    e = _anamorph.SceneError(f"{key}: {message}")
    e.key, e.message, e.file, e.line, e.column = key, message, None, 0, 0
    return e


def integer(key: str, v: Any, lo: int, hi: int) -> int:
    """``v`` as an int for an integer argument the C++ side takes directly (not through the scene
    reader): a TypeError if it is no integer, a SceneError naming ``key`` and its range if it is
    out of [lo, hi] (Python ints have no size limit; C++ ones do)."""
    if isinstance(v, bool) or not hasattr(v, "__index__"):
        raise TypeError(f"{key}: expected an integer, got {type(v).__name__}")
    v = operator.index(v)
    if not lo <= v <= hi:
        raise scene_error(key, f"value {v} is out of range (must be [{lo}, {hi}])")
    return v
