"""Exceptions raised by carl_spec (the native module raises these with the library's message)."""


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
