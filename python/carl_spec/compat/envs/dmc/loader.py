"""carl-bench's `carl.envs.dmc.loader`: `load_dmc_env` over carl-spec's dm_control family.

carl-bench returned a dm_control environment (`dm_env`); carl-spec has its own runtimes, so this
returns the carl-bench class of the domain (a Gymnasium environment) with the task and context.
Domains carl-spec does not have yet raise `PendingEnvironmentError`; unknown domains and tasks
raise `ValueError`, as carl-bench's.
"""

from __future__ import annotations

from typing import Any

from ..._pending import PENDING, PendingEnvironmentError, reason

#: carl-bench's domain name -> (its class, dm_control's plain task name -> carl-bench's task)
_DOMAINS: dict[str, tuple[str, dict[str, str]]] = {
    "walker": ("CARLDmcWalkerEnv", {"stand": "stand_context", "walk": "walk_context", "run": "run_context"}),
    "pointmass": ("CARLDmcPointMassEnv", {"easy": "easy_pointmass", "hard": "hard_pointmass"}),
    "finger": ("CARLDmcFingerEnv", {"spin": "spin_context", "turn_easy": "turn_easy_context", "turn_hard": "turn_hard_context"}),
    "fish": ("CARLDmcFishEnv", {"swim": "swim_context", "upright": "upright_context"}),
    "quadruped": (
        "CARLDmcQuadrupedEnv",
        {"walk": "walk_context", "run": "run_context", "escape": "escape_context", "fetch": "fetch_context"},
    ),
}


def load_dmc_env(
    domain_name: str,
    task_name: str,
    context: dict[str, Any] | None = None,
    task_kwargs: Any = None,
    environment_kwargs: dict[str, bool] | None = None,
    visualize_reward: bool = False,
) -> Any:
    """carl-bench's loader: the domain's environment for `task_name` (a carl-bench `*_context`
    task or dm_control's plain task name) under `context`."""
    if domain_name not in _DOMAINS:
        raise ValueError("Domain {!r} does not exist.".format(domain_name))
    cls_name, tasks = _DOMAINS[domain_name]
    task = tasks.get(task_name, task_name)
    if task not in tasks.values():
        raise ValueError("Task {!r} does not exist in domain {!r}.".format(task_name, domain_name))
    if cls_name in PENDING:
        raise PendingEnvironmentError(reason(cls_name))
    from .. import _classes

    cls = getattr(_classes, cls_name)
    return cls(contexts={0: dict(context)} if context else None, task=task)


__all__ = ["load_dmc_env"]
