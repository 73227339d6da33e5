"""carl-bench's `carl.envs.dmc.dmc_tasks.walker`, over carl-spec's `dmc_walker`.

carl-bench's functions returned dm_control's XML (`get_model_and_assets`) and dm_control
environments (`*_context`); carl-spec builds its walker from dm_control's compiled model and has
its own runtime: they raise, naming the class to use.
"""

from __future__ import annotations

from typing import Any, NoReturn


def _no_dm_control(name: str) -> Any:
    def refuse(*_: Any, **__: Any) -> NoReturn:
        raise NotImplementedError(
            f"carl_spec.compat: carl-bench's {name} returned dm_control objects, which carl-spec has not; "
            "use CARLDmcWalkerEnv(task=...) or carl_spec.make('dmc_walker')"
        )

    refuse.__name__ = refuse.__qualname__ = name
    return refuse


get_model_and_assets = _no_dm_control("get_model_and_assets")
stand_context = _no_dm_control("stand_context")
walk_context = _no_dm_control("walk_context")
run_context = _no_dm_control("run_context")

__all__ = ["get_model_and_assets", "stand_context", "walk_context", "run_context"]
