"""carl-bench's `carl.envs.dmc.loader`: `load_dmc_env` over carl-spec's dm_control family.

carl-bench returned a dm_control environment (`dm_env`); carl-spec has its own runtimes, so this
returns the carl-bench class of the domain (a Gymnasium environment) with the task and context;
unknown domains and tasks raise `ValueError`, as carl-bench's. `load_dm_control_env` is carl-bench's
loader itself (a dm_control environment, over `dmc_tasks`' task functions; needs dm_control), which
`CARLDmcEnv` runs.
"""

from __future__ import annotations

from typing import Any

from .dmc_tasks import _dm_control, finger, fish, pointmass, quadruped, walker

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
    from .. import _classes

    cls = getattr(_classes, cls_name)
    return cls(contexts={0: dict(context)} if context else None, task=task)


_MODULES: dict[str, Any] = {"walker": walker, "pointmass": pointmass, "finger": finger, "fish": fish, "quadruped": quadruped}


def load_dm_control_env(
    domain_name: str,
    task_name: str,
    context: dict[str, Any] | None = None,
    task_kwargs: Any = None,
    environment_kwargs: dict[str, bool] | None = None,
    visualize_reward: bool = False,
) -> Any:
    """carl-bench's `load_dmc_env` as it was: the dm_control environment of a carl-bench task
    (`walk_context`, ...) under `context`, or of any dm_control suite task (`suite.load`).
    Needs dm_control."""
    _dm_control.require("carl_spec.compat.envs.dmc.loader.load_dm_control_env", "load_dmc_env (carl-spec's runtimes)")
    from dm_control import suite

    if domain_name in _DOMAINS:
        tasks = _DOMAINS[domain_name][1]
        if task_name in tasks.values():
            kwargs = dict(task_kwargs or {})
            if environment_kwargs is not None:
                kwargs["environment_kwargs"] = environment_kwargs
            env = getattr(_MODULES[domain_name], task_name)(context=context or {}, **kwargs)
            env.task.visualize_reward = visualize_reward
            return env
    elif domain_name not in suite._DOMAINS:
        raise ValueError("Domain {!r} does not exist.".format(domain_name))
    if (domain_name, task_name) in suite.ALL_TASKS:
        return suite.load(
            domain_name=domain_name,
            task_name=task_name,
            task_kwargs=task_kwargs,
            environment_kwargs=environment_kwargs,
            visualize_reward=visualize_reward,
        )
    raise ValueError("Task {!r} does not exist in domain {!r}.".format(task_name, domain_name))


__all__ = ["load_dm_control_env", "load_dmc_env"]
