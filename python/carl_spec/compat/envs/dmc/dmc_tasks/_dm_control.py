"""dm_control, for carl-bench's helpers that returned dm_control objects (optional).

carl-spec runs its dm_control family on its own engine; carl-bench's task functions (`*_context`,
`easy_pointmass`, ...), `CARLDmcEnv` and `MujocoToGymWrapper` return or wrap dm_control
environments, so they need dm_control itself. Without it they raise `DmControlMissingError`
(an `ImportError`) naming the install command and carl-spec's class to use instead.
"""

from __future__ import annotations

import importlib.util
from typing import Any

INSTALL = "pip install dm_control==1.0.50 'mujoco<4'"


class DmControlMissingError(ImportError):
    """A carl-bench helper that builds dm_control objects was called without dm_control."""


def available() -> bool:
    return importlib.util.find_spec("dm_control") is not None


def require(what: str, instead: str) -> None:
    """Raise `DmControlMissingError` for `what` unless dm_control is importable."""
    if not available():
        raise DmControlMissingError(
            f"carl_spec.compat: {what} builds dm_control objects, as carl-bench's did, and needs dm_control "
            f"({INSTALL}); carl-spec's own runtime needs no dm_control: use {instead}",
            name="dm_control",
        )


def environment(
    physics: Any,
    task: Any,
    time_limit: float,
    control_timestep: float | None,
    environment_kwargs: dict[str, Any] | None,
) -> Any:
    """dm_control's `control.Environment` as carl-bench's task functions built it."""
    from dm_control.rl import control

    kwargs = dict(environment_kwargs or {})
    if control_timestep is not None:
        kwargs["control_timestep"] = control_timestep
    return control.Environment(physics, task, time_limit=time_limit, **kwargs)
