"""carl-bench's `ContextSampler` (`carl.context.sampler`): contexts drawn from per-feature
distributions, every other feature at its default.

The distributions are compat's context features, ConfigSpace hyperparameters (carl-bench's
context features are ConfigSpace's), or a search space (a path to a ConfigSpace JSON file or a
hydra `DictConfig`, read by `carl.context.search_space_encoding`; ConfigSpace and omegaconf are the
optional `carl-spec[compat]` extra). The draws come from `numpy.random.default_rng(seed)`
(carl-bench draws through ConfigSpace), so the same seed gives the same contexts here on every
run, though not carl-bench's values.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .context_space import (
    CategoricalContextFeature,
    ContextFeature,
    ContextSpace,
    NormalFloatContextFeature,
    UniformFloatContextFeature,
    UniformIntegerContextFeature,
)

Contexts = dict[Any, dict[str, Any]]


class ContextSampler:
    def __init__(
        self,
        context_distributions: list[ContextFeature] | dict[str, ContextFeature],
        context_space: ContextSpace,
        seed: int,
        name: str | None = None,
    ) -> None:
        if isinstance(context_distributions, str) or type(context_distributions).__name__ == "DictConfig":
            from .search_space_encoding import search_space_to_config_space

            context_distributions = list(search_space_to_config_space(context_distributions).values())
        if isinstance(context_distributions, dict):
            context_distributions = list(context_distributions.values())
        if not isinstance(context_distributions, list):
            raise ValueError(
                "context_distributions must be a list or dict of context features, a path to a search space or a "
                f"DictConfig, got {type(context_distributions).__name__}"
            )
        context_distributions = [from_hyperparameter(f) for f in context_distributions]
        unknown = [f.name for f in context_distributions if f.name not in context_space.context_space]
        if unknown:
            raise ValueError(
                f"unknown context feature(s) {unknown}; features: {', '.join(context_space.context_feature_names)}"
            )
        self.context_distributions = context_distributions
        self.context_feature_names = [f.name for f in context_distributions]
        self.context_space = context_space
        self.name = name
        self.rng = np.random.default_rng(seed)

    def get_context_features(self) -> list[ContextFeature]:
        return list(self.context_distributions)

    def sample_contexts(self, n_contexts: int) -> Contexts:
        """`{0: context, 1: …}`: each context is the defaults with the sampled features drawn."""
        defaults = self.context_space.get_default_context()
        return {
            i: {**defaults, **{f.name: f.sample(self.rng) for f in self.context_distributions}}
            for i in range(n_contexts)
        }


def from_hyperparameter(hp: Any) -> ContextFeature:
    """A compat context feature from a ConfigSpace hyperparameter (returned as is when it already
    is one): uniform float / integer, normal float, categorical, ordinal and constant."""
    if isinstance(hp, ContextFeature):
        return hp
    kind = type(hp).__name__
    name = str(getattr(hp, "name", ""))
    if kind in ("UniformFloatHyperparameter", "UniformIntegerHyperparameter"):
        cls = UniformFloatContextFeature if kind == "UniformFloatHyperparameter" else UniformIntegerContextFeature
        return cls(name, hp.lower, hp.upper, default_value=hp.default_value, log=bool(hp.log))
    if kind == "NormalFloatHyperparameter" and not hp.log:
        return NormalFloatContextFeature(name, mu=hp.mu, sigma=hp.sigma, default_value=hp.default_value, lower=hp.lower, upper=hp.upper)
    if kind == "CategoricalHyperparameter" and getattr(hp, "weights", None) is None:
        return CategoricalContextFeature(name, list(hp.choices), default_value=hp.default_value)
    if kind == "OrdinalHyperparameter":
        return CategoricalContextFeature(name, list(hp.sequence), default_value=hp.default_value)
    if kind == "Constant":
        return CategoricalContextFeature(name, [hp.value], default_value=hp.value)
    raise ValueError(
        f"{name or repr(hp)}: {kind} is not a distribution carl_spec.compat samples (uniform float / integer, normal "
        "float without log, categorical without weights, ordinal, constant); use compat's context features"
    )


__all__ = ["ContextSampler", "from_hyperparameter"]
