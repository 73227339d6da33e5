"""carl-spec for Python: CARL's contextual environments, specs and frozen instance sets.

    import carl_spec as cs
    env = cs.make("cartpole", context={"masscart": 2.5})
    venv = cs.make_vec("lunar_lander", 64, instances="lunar_lander/landing_in_space_train")
    gymnasium.make("carl_spec/cartpole-v0")
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

import gymnasium

from . import _core
from ._errors import InvalidActionError, UnknownNameError
from .env import CarlEnv

if TYPE_CHECKING:
    from ._audit import AuditReport, audit
    from ._wrap import ContextualWrapper, wrap
    from .evaluation import EvaluationResult, Report, evaluate, report
    from .specs import Diagnostic, InstanceSet, Spec, ValidationReport, instances, list_envs, sample, spec, validate
    from .vector import CarlVectorEnv

# Loaded on first use (PEP 562 `__getattr__` below): `import carl_spec; cs.make(...)` needs none
# of them, and their classes (frozen dataclasses above all) cost as much to create as the rest of
# the package. The integrations (carl_spec.sb3, .rllib, .compat) are never imported from here.
# `wrap` and `audit` live in the private modules `_wrap` and `_audit`, so that no submodule
# shares a name with a public function (importing a submodule binds its name in the package).
_LAZY: dict[str, str] = {
    "AuditReport": "_audit",
    "audit": "_audit",
    "CarlVectorEnv": "vector",
    "ContextualWrapper": "_wrap",
    "wrap": "_wrap",
    **dict.fromkeys(["EvaluationResult", "Report", "evaluate", "report"], "evaluation"),
    **dict.fromkeys(
        ["Diagnostic", "InstanceSet", "Spec", "ValidationReport", "instances", "list_envs", "sample", "spec", "validate"],
        "specs",
    ),
}


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{module}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))


__version__: str = _core.VERSION
RUNTIMES: list[str] = list(_core.RUNTIMES)

__all__ = [
    "AuditReport",
    "CarlEnv",
    "CarlVectorEnv",
    "ContextualWrapper",
    "Diagnostic",
    "EvaluationResult",
    "InstanceSet",
    "InvalidActionError",
    "RUNTIMES",
    "Report",
    "Spec",
    "UnknownNameError",
    "audit",
    "ValidationReport",
    "evaluate",
    "gym_id",
    "instances",
    "list_envs",
    "make",
    "make_vec",
    "report",
    "sample",
    "spec",
    "validate",
    "wrap",
]


def make(env: str, **kwargs: Any) -> CarlEnv:
    """One environment; see `CarlEnv` for the keyword arguments."""
    return CarlEnv(env, **kwargs)


def make_vec(env: str, num_envs: int, **kwargs: Any) -> CarlVectorEnv:
    """`num_envs` environments stepped as one batch in Rust; see `CarlVectorEnv`."""
    from .vector import CarlVectorEnv

    return CarlVectorEnv(env, num_envs, **kwargs)


def gym_id(env: str) -> str:
    """The Gymnasium id of a runtime, `carl_spec/<id>-v<version>`, e.g. `carl_spec/cartpole-v0`.

    The version is the spec's: it is bumped whenever the environment's dynamics, observation,
    reward or termination change, so results reported under one id stay comparable."""
    version = _core.VERSIONS.get(env)
    if version is None:
        raise UnknownNameError(f"no runtime named {env!r}; runtimes: {', '.join(RUNTIMES)}")
    return f"carl_spec/{env}-v{version}"


def _register() -> None:
    # Gymnasium's registry is its own global; registering once per id at import is its convention.
    for env_id in RUNTIMES:
        name = gym_id(env_id)
        if name not in gymnasium.registry:
            gymnasium.register(
                id=name,
                entry_point="carl_spec.env:CarlEnv",
                vector_entry_point="carl_spec.vector:CarlVectorEnv",
                kwargs={"env": env_id},
                # The runtime truncates at the spec's episode limit itself: no TimeLimit on top.
                # `gymnasium.make(...).spec.max_episode_steps` states that limit (CarlEnv.spec).
                max_episode_steps=None,
            )


_register()
