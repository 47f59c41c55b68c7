"""Python values as TOML text, so keyword arguments and ``set=`` overrides reach the scene reader
exactly as a scene file would (the same checks and messages)."""

from __future__ import annotations

import json
import math
import re
from typing import Any, Mapping

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


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
        return str(v)
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
