"""dm_control, for carl-bench's helpers that returned dm_control objects (optional).

carl-spec runs its dm_control family on its own engine; carl-bench's task functions (`*_context`,
`easy_pointmass`, ...), `CARLDmcEnv` and `MujocoToGymWrapper` return or wrap dm_control
environments, so they need dm_control itself. Without it they raise `DmControlMissingError`
(an `ImportError`) naming the install command and carl-spec's class to use instead.
"""

from __future__ import annotations

import importlib
import importlib.util
from collections.abc import Callable
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


def task_function(
    domain: str,
    name: str,
    instead: str,
    model: Callable[[dict[str, Any]], tuple[bytes, dict[str, bytes]]],
    task: Callable[[Any, Any], Any],
    time_limit: float,
    control_timestep: float | None,
    doc: str,
    context_mask: bool = False,
) -> Callable[..., Any]:
    """One of carl-bench's task functions (`walker.walk_context`, ...), with its signature:
    `make(context=None, [context_mask=None,] time_limit=..., random=None, environment_kwargs=None)`.

    `model(context)` gives the XML (adapted to the context) and its assets, `task(suite, random)`
    dm_control's task, `suite` being `dm_control.suite.<domain>`; the environment is dm_control's
    `control.Environment` as carl-bench built it. Without dm_control, `DmControlMissingError`
    naming `instead`."""
    default_time_limit = time_limit

    def build(context: dict[str, Any] | None, time_limit: float, random: Any, environment_kwargs: dict[str, Any] | None) -> Any:
        require(f"carl.envs.dmc.dmc_tasks.{domain}.{name}", instead)
        suite = importlib.import_module(f"dm_control.suite.{domain}")
        xml, assets = model(context or {})
        physics = suite.Physics.from_xml_string(xml, assets)
        return environment(physics, task(suite, random), time_limit, control_timestep, environment_kwargs)

    make: Callable[..., Any]
    if context_mask:

        def make_with_mask(
            context: dict[str, Any] | None = None,
            context_mask: list[str] | None = None,
            time_limit: float = default_time_limit,
            random: Any = None,
            environment_kwargs: dict[str, Any] | None = None,
        ) -> Any:
            return build(context, time_limit, random, environment_kwargs)

        make = make_with_mask
    else:

        def make_plain(
            context: dict[str, Any] | None = None,
            time_limit: float = default_time_limit,
            random: Any = None,
            environment_kwargs: dict[str, Any] | None = None,
        ) -> Any:
            return build(context, time_limit, random, environment_kwargs)

        make = make_plain
    make.__name__ = make.__qualname__ = name
    make.__doc__ = doc
    return make
