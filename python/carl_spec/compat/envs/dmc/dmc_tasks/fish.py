"""carl-bench's `carl.envs.dmc.dmc_tasks.fish`, over carl-spec's `dmc_fish`.

carl-bench's functions returned dm_control's XML (`get_model_and_assets`) and dm_control
environments (`*_context`); carl-spec builds its fish from dm_control's compiled model and has
its own runtime: they raise, naming the class to use.
"""

from __future__ import annotations

from typing import Any, NoReturn


def _no_dm_control(name: str) -> Any:
    def refuse(*_: Any, **__: Any) -> NoReturn:
        raise NotImplementedError(
            f"carl_spec.compat: carl-bench's {name} returned dm_control objects, which carl-spec has not; "
            "use CARLDmcFishEnv(task=...) or carl_spec.make('dmc_fish')"
        )

    refuse.__name__ = refuse.__qualname__ = name
    return refuse


get_model_and_assets = _no_dm_control("get_model_and_assets")
upright_context = _no_dm_control("upright_context")
swim_context = _no_dm_control("swim_context")

__all__ = ["get_model_and_assets", "upright_context", "swim_context"]
