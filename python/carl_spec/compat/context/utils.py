"""carl-bench's `carl.context.utils`."""

from __future__ import annotations

from typing import Any

import numpy as np


def get_context_bounds(
    context_keys: list[str], context_bounds: dict[str, tuple[float, float, type[Any]]]
) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds of `context_keys` as two float arrays, from
    `{name: (lower, upper, type)}` (carl-bench's signature; an unknown name raises KeyError)."""
    lower = np.empty(len(context_keys))
    upper = np.empty(len(context_keys))
    for i, key in enumerate(context_keys):
        lo, hi, _ = context_bounds[key]
        lower[i], upper[i] = lo, hi
    return lower, upper


__all__ = ["get_context_bounds"]
