"""carl-bench's `carl.envs.dmc.dmc_tasks.finger`, over carl-spec's `dmc_finger`.

`check_constraints` is carl-bench's geometry check (the finger must reach the spinner, the
spinner must clear the finger's hinge), with its signature and its `ValueError`s; `dmc_finger`
refuses the same geometries when built. carl-bench's other functions returned dm_control's XML
(`get_model_and_assets`, `get_finger_xml_string`) and dm_control environments (`*_context`);
carl-spec builds its finger from dm_control's compiled model and has its own runtime: they raise,
naming the class to use.
"""

from __future__ import annotations

from typing import Any, NoReturn


def check_constraints(
    spinner_length: float,
    limb_length_0: float,
    limb_length_1: float,
    x_spinner: float = 0.2,
    x_finger: float = -0.2,
    raise_error: bool = False,
    **kwargs: Any,
) -> bool:
    """carl-bench's check: whether the spinner clears the finger's hinge and the finger reaches the
    spinner; with `raise_error`, a `ValueError` saying which fails."""
    half = spinner_length / 2
    clearance = (x_spinner - x_finger) - half
    if clearance < 0:
        if raise_error:
            raise ValueError(
                f"Distance finger to spinner ({clearance}) not big enough, spinner can't spin. "
                f"Decrease spinner_length ({spinner_length})."
            )
        return False
    gap = (x_spinner - half) - (x_finger + limb_length_0 + limb_length_1)
    if gap > 0:
        if raise_error:
            raise ValueError(
                f"Finger cannot reach spinner ({gap}). Increase either limb_length_0, limb_length_1 or spinner_length."
            )
        return False
    return True


def _no_dm_control(name: str) -> Any:
    def refuse(*_: Any, **__: Any) -> NoReturn:
        raise NotImplementedError(
            f"carl_spec.compat: carl-bench's {name} returned dm_control objects, which carl-spec has not; "
            "use CARLDmcFingerEnv(task=...) or carl_spec.make('dmc_finger')"
        )

    refuse.__name__ = refuse.__qualname__ = name
    return refuse


get_finger_xml_string = _no_dm_control("get_finger_xml_string")
get_model_and_assets = _no_dm_control("get_model_and_assets")
spin_context = _no_dm_control("spin_context")
turn_easy_context = _no_dm_control("turn_easy_context")
turn_hard_context = _no_dm_control("turn_hard_context")

__all__ = ["check_constraints", "get_finger_xml_string", "get_model_and_assets", "spin_context", "turn_easy_context", "turn_hard_context"]
