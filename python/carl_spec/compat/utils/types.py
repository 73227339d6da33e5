"""carl-bench's type aliases (`carl.utils.types`)."""

from __future__ import annotations

from typing import Any, Dict, List, TypeVar, Union

import numpy as np

Context = Dict[str, Any]
Contexts = Dict[Any, Context]
Vector = Union[List[Any], np.ndarray]
ObsType = TypeVar("ObsType")

__all__ = ["Context", "Contexts", "ObsType", "Vector"]
