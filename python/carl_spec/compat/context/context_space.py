"""carl-bench's context features and context space (`carl.context.context_space`).

carl-bench builds these on ConfigSpace's hyperparameters; here they are small plain classes with
the attributes carl-bench code reads (`name`, `default_value`, `lower`, `upper`, `choices`,
`mu`, `sigma`) and a `sample(rng)` drawing from a NumPy `Generator` the caller seeds.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import spaces

Context = dict[str, Any]


class ContextFeature:
    """A named feature with a default; numeric ones have `lower`/`upper` (infinite when open)."""

    def __init__(self, name: str, default_value: Any = None, lower: float = -np.inf, upper: float = np.inf) -> None:
        self.name = name
        self.default_value = default_value
        self.lower = float(lower)
        self.upper = float(upper)
        #: carl-spec's canonical name, type, unit and description (set for env features).
        self.canonical_name: str = name
        self.type: str = "float"
        self.unit: str | None = None
        self.description: str = ""

    def sample(self, rng: np.random.Generator) -> Any:
        raise NotImplementedError(f"{type(self).__name__} cannot be sampled")

    def __repr__(self) -> str:
        return f"{type(self).__name__}(name={self.name!r}, default_value={self.default_value!r}, lower={self.lower}, upper={self.upper})"


class NumericalContextFeature(ContextFeature):
    pass


def _finite(f: ContextFeature) -> None:
    if not (np.isfinite(f.lower) and np.isfinite(f.upper)):
        raise ValueError(
            f"{f.name}: cannot draw uniformly from [{f.lower}, {f.upper}] (carl-bench's ConfigSpace returns inf for "
            "every such draw); give the feature finite bounds, or sample it from a NormalFloatContextFeature "
            "with a ContextSampler"
        )


class UniformFloatContextFeature(NumericalContextFeature):
    def __init__(self, name: str, lower: float, upper: float, default_value: float | None = None, log: bool = False) -> None:
        if default_value is None:
            default_value = (float(lower) + float(upper)) / 2
        super().__init__(name, default_value, lower, upper)
        self.log = log

    def sample(self, rng: np.random.Generator) -> float:
        _finite(self)
        if self.log:
            return float(np.exp(rng.uniform(np.log(self.lower), np.log(self.upper))))
        return float(rng.uniform(self.lower, self.upper))


class UniformIntegerContextFeature(UniformFloatContextFeature):
    def __init__(self, name: str, lower: int, upper: int, default_value: int | None = None, log: bool = False) -> None:
        super().__init__(name, lower, upper, default_value if default_value is not None else (lower + upper) // 2, log)
        self.type = "int"

    def sample(self, rng: np.random.Generator) -> int:
        _finite(self)
        return int(rng.integers(int(self.lower), int(self.upper) + 1))


class NormalFloatContextFeature(NumericalContextFeature):
    """N(mu, sigma), truncated to [lower, upper] when given (redrawn until inside)."""

    def __init__(
        self,
        name: str,
        mu: float,
        sigma: float,
        default_value: float | None = None,
        lower: float | None = None,
        upper: float | None = None,
        log: bool = False,
    ) -> None:
        super().__init__(name, mu if default_value is None else default_value,
                         -np.inf if lower is None else lower, np.inf if upper is None else upper)
        self.mu, self.sigma, self.log = float(mu), float(sigma), log

    def sample(self, rng: np.random.Generator) -> float:
        for _ in range(10_000):
            x = float(rng.normal(self.mu, self.sigma))
            if self.log:
                x = float(np.exp(x))
            if self.lower <= x <= self.upper:
                return x
        raise ValueError(f"{self.name}: no draw of N({self.mu}, {self.sigma}) fell inside [{self.lower}, {self.upper}]")


class CategoricalContextFeature(ContextFeature):
    def __init__(self, name: str, choices: list[Any], default_value: Any = None) -> None:
        super().__init__(name, choices[0] if default_value is None else default_value)
        self.choices = list(choices)
        self.type = "categorical"

    def sample(self, rng: np.random.Generator) -> Any:
        return self.choices[int(rng.integers(len(self.choices)))]


class ContextSpace:
    """The features of an environment (`CARL<Name>.get_context_space()`)."""

    def __init__(self, context_space: dict[str, ContextFeature]) -> None:
        self.context_space = context_space

    @property
    def context_feature_names(self) -> list[str]:
        return list(self.context_space)

    def get_default_context(self) -> Context:
        return {n: f.default_value for n, f in self.context_space.items() if f.default_value is not None}

    def insert_defaults(self, context: Context, context_keys: list[str] | None = None) -> Context:
        defaults = self.get_default_context()
        if context_keys:
            defaults = {k: defaults[k] for k in context_keys}
        return {**defaults, **context}

    def verify_context(self, context: Context) -> bool:
        """Whether every name is a feature and every numeric value lies within its bounds."""
        for name, v in context.items():
            f = self.context_space.get(name)
            if f is None:
                return False
            if isinstance(f, NumericalContextFeature) and not f.lower <= v <= f.upper:
                return False
        return True

    def get_lower_and_upper_bound(self, context_feature_name: str) -> tuple[float, float]:
        f = self.context_space[context_feature_name]
        return f.lower, f.upper

    def to_gymnasium_space(self, context_feature_names: list[str] | None = None, as_dict: bool = False) -> spaces.Space[Any]:
        """The features as a Gymnasium space, as carl-bench's: `Dict` of `Box(1,)` per numeric
        feature and `Discrete(n)` per categorical one (`as_dict=True`), else one float32 `Box`
        (a categorical feature as its index, 0..n-1, where carl-bench fails)."""
        names = self.context_feature_names if context_feature_names is None else list(context_feature_names)
        for n in names:
            if n not in self.context_space:
                raise ValueError(f"unknown context feature {n!r}; features: {', '.join(self.context_feature_names)}")
        feats = [self.context_space[n] for n in names]
        if as_dict:
            return spaces.Dict(
                {
                    f.name: spaces.Discrete(len(f.choices))
                    if isinstance(f, CategoricalContextFeature)
                    else spaces.Box(low=f.lower, high=f.upper, shape=(1,), dtype=np.float32)
                    for f in feats
                }
            )

        def bounds(f: ContextFeature) -> tuple[float, float]:
            if isinstance(f, CategoricalContextFeature):
                return 0.0, float(len(f.choices) - 1)
            return f.lower, f.upper

        low = np.array([bounds(f)[0] for f in feats], dtype=np.float32)
        high = np.array([bounds(f)[1] for f in feats], dtype=np.float32)
        return spaces.Box(low=low, high=high, dtype=np.float32)

    def sample_contexts(
        self, context_keys: list[str] | None = None, size: int = 1, *, seed: int | None = None
    ) -> Context | list[Context]:
        """`size` contexts with the features `context_keys` (None: every feature) drawn from their
        distributions and the others at their defaults; one context when `size == 1`, else a list
        (carl-bench's shapes). `seed` seeds the draws (None: fresh entropy). carl-bench draws every
        feature whatever `context_keys` says; here only the named ones are drawn.

        Raises ValueError for a name that is not a feature, or for a uniform feature with an
        infinite bound (carl-bench returns inf for every such draw)."""
        if context_keys is None:
            keys = self.context_feature_names
        else:
            keys = list(context_keys)
            for key in keys:
                if key not in self.context_space:
                    raise ValueError(f"Invalid context feature name: {key}; features: {', '.join(self.context_feature_names)}")
        rng = np.random.default_rng(seed)
        defaults = self.get_default_context()
        contexts = [{**defaults, **{k: self.context_space[k].sample(rng) for k in keys}} for _ in range(size)]
        return contexts[0] if size == 1 else contexts


__all__ = [
    "CategoricalContextFeature",
    "ContextFeature",
    "ContextSpace",
    "NormalFloatContextFeature",
    "NumericalContextFeature",
    "UniformFloatContextFeature",
    "UniformIntegerContextFeature",
]
