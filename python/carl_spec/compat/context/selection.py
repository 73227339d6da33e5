"""carl-bench's context selectors (`carl.context.selection`), for `carl_spec.compat`.

The three built-in selectors are carried out by carl-spec's selection (the same rules as
`cs.make(..., selection=...)`): seeded by `env.reset(seed=s)`, never by NumPy's global RNG.
A `CustomSelector` (or any subclass implementing `_select`) is called as in carl-bench.
"""

from __future__ import annotations

from typing import Any, Callable

Context = dict[str, Any]
Contexts = dict[Any, Context]


class AbstractSelector:
    """Holds the context set; `context_id` is the position of the current context in
    `contexts_keys` (None before the first reset)."""

    #: carl-spec's selection mode carrying this selector out (None: call `_select`).
    mode: str | None = None

    def __init__(self, contexts: Contexts) -> None:
        self.contexts: Contexts = contexts
        self.context_ids: list[int] = list(range(len(contexts)))
        self.contexts_keys: list[Any] = list(contexts.keys())
        self.n_calls: int = 0
        self.context_id: int | None = None

    def _select(self) -> tuple[Context, int]:
        raise NotImplementedError(f"{type(self).__name__} must implement _select() -> (context, context_id)")

    def select(self) -> Context:
        context, context_id = self._select()
        self.context_id = int(context_id)
        self.n_calls += 1
        return context

    @property
    def context_key(self) -> Any | None:
        """The key (in the user's `contexts` dict) of the current context."""
        return None if self.context_id is None else self.contexts_keys[self.context_id]


class RoundRobinSelector(AbstractSelector):
    """Contexts in order, cyclically. `reset(seed=s)` starts at position `s mod n`, each unseeded
    reset takes the next one (so seeding once with 0 visits 0, 1, 2, … as in carl-bench)."""

    mode = "round_robin"


class RandomSelector(AbstractSelector):
    """A uniformly random context per reset, drawn from a stream seeded by `reset(seed=s)`
    (carl-bench draws from NumPy's global RNG and ignores the seed)."""

    mode = "random"


class StaticSelector(AbstractSelector):
    """Always the first context (or the one `env.context_id = i` switched to)."""

    mode = "static"


class CustomSelector(AbstractSelector):
    """`selector_function(selector) -> (context, context_id)` picks the context at every reset."""

    def __init__(self, contexts: Contexts, selector_function: Callable[[AbstractSelector], tuple[Context, int]]) -> None:
        super().__init__(contexts)
        self.selector_function = selector_function

    def _select(self) -> tuple[Context, int]:
        return self.selector_function(self)


__all__ = ["AbstractSelector", "CustomSelector", "RandomSelector", "RoundRobinSelector", "StaticSelector"]
