"""Gymnasium spaces from the native module's JSON descriptions."""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import spaces


def _bounds(values: list[float | None], fill: float, dtype: Any) -> np.ndarray:
    return np.array([fill if v is None else v for v in values], dtype=dtype)


def space_from_json(d: dict[str, Any]) -> spaces.Space[Any]:
    """`{"type": "box", "shape", "dtype", "low", "high"}` (None = infinite) or
    `{"type": "discrete", "n", "start"}` or `{"type": "dict", "spaces": {name: space}}`."""
    if d["type"] == "dict":
        return spaces.Dict({k: space_from_json(v) for k, v in d["spaces"].items()})
    if d["type"] == "discrete":
        return spaces.Discrete(int(d["n"]), start=int(d["start"]))
    dtype = np.dtype(d["dtype"])
    shape = tuple(int(s) for s in d["shape"])
    if dtype == np.uint8:
        low = _bounds(d["low"], 0, np.float64).astype(np.uint8).reshape(shape)
        high = _bounds(d["high"], 255, np.float64).astype(np.uint8).reshape(shape)
    else:
        # The native bounds are float32 values; float64 spaces hold them exactly.
        low = _bounds(d["low"], -np.inf, np.float32).astype(dtype).reshape(shape)
        high = _bounds(d["high"], np.inf, np.float32).astype(dtype).reshape(shape)
    return spaces.Box(low=low, high=high, shape=shape, dtype=dtype)
