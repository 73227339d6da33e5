"""Exceptions raised by carl_spec (the native module raises these with the library's message)."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

#: The native module's hint for a value outside its bounds (`cs.make`'s keyword).
OUT_OF_BOUNDS_HINT = "pass allow_out_of_bounds=True to run it anyway"


@contextmanager
def out_of_bounds_hint(hint: str) -> Iterator[None]:
    """For APIs without `allow_out_of_bounds=`: a bounds error names what works there instead."""
    try:
        yield
    except ValueError as e:
        text = str(e)
        if OUT_OF_BOUNDS_HINT not in text:
            raise
        raise type(e)(text.replace(OUT_OF_BOUNDS_HINT, hint)) from None


def curriculum_bounds_hint(curriculum: object) -> Any:
    """A curriculum's context outside a feature's bounds: the error names the curriculum that chose
    it (its `select` is what must change, or `allow_out_of_bounds=True` in `make` / `make_vec`)."""
    return out_of_bounds_hint(
        f"the curriculum {type(curriculum).__name__} chose this context: keep its contexts within the "
        "spec's bounds, or pass allow_out_of_bounds=True to carl_spec.make / make_vec to run them anyway"
    )


class UnknownNameError(KeyError, ValueError):
    """An unknown environment, feature, distribution or instance set; the message names the valid
    ones (and suggests the closest). Both a KeyError and a ValueError, so either `except` works."""

    def __str__(self) -> str:  # KeyError would print the message in quotes
        return str(self.args[0]) if self.args else ""


class InvalidActionError(ValueError, TypeError):
    """An action that is not an element of the action space's type: a bool, a float or an array
    for a Discrete space (Gymnasium's `Discrete.contains` refuses floats and arrays of shape other
    than `()`; carl-spec refuses bools too, so `True` never silently means action 1). Both a
    ValueError and a TypeError, so either `except` works."""
