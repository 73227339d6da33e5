"""carl-bench's `ContextSampler` (`carl.context.sampler`): contexts drawn from per-feature
distributions, every other feature at its default.

The draws come from `numpy.random.default_rng(seed)` (carl-bench draws through ConfigSpace), so
the same seed gives the same contexts here on every run, though not carl-bench's values.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .context_space import ContextFeature, ContextSpace

Contexts = dict[Any, dict[str, Any]]


class ContextSampler:
    def __init__(
        self,
        context_distributions: list[ContextFeature] | dict[str, ContextFeature],
        context_space: ContextSpace,
        seed: int,
        name: str | None = None,
    ) -> None:
        if isinstance(context_distributions, dict):
            context_distributions = list(context_distributions.values())
        if not isinstance(context_distributions, list):
            raise ValueError(
                f"context_distributions must be a list or dict of context features, got {type(context_distributions).__name__}"
            )
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


__all__ = ["ContextSampler"]
