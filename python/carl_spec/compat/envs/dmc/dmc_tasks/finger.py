"""carl-bench's `carl.envs.dmc.dmc_tasks.finger`, over carl-spec's `dmc_finger`.

`check_constraints` is carl-bench's geometry check (the finger must reach the spinner, the
spinner must clear the finger's hinge), with its signature and its `ValueError`s; `dmc_finger`
refuses the same geometries when built. `get_model_and_assets` is dm_control's finger.xml and its
common assets (shipped with carl-spec, no dm_control needed); `get_finger_xml_string` is
carl-bench's finger XML under the given limb and spinner sizes. At the default sizes it is not
dm_control's finger: carl-bench's fingertip capsule reaches from 0.19 (dm_control: 0.13) and its
spinner's caps are slanted (`fromto`), which carl-bench's dm_control finger tasks ran with.

The task functions (`spin_context`, `turn_easy_context`, `turn_hard_context`) return dm_control
environments, built as carl-bench's were (this XML, `adapt_context`, dm_control's finger tasks);
they need dm_control and without it raise `DmControlMissingError` naming
`CARLDmcFingerEnv(task=...)`, carl-spec's own runtime.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from typing import Any

from . import _dm_control
from ._common_xml import ASSETS
from ._finger_xml import FINGER_XML
from .utils import adapt_context

# dm_control's finger.py
_DEFAULT_TIME_LIMIT = 20
_CONTROL_TIMESTEP = 0.02
_EASY_TARGET_SIZE = 0.07
_HARD_TARGET_SIZE = 0.03


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


def get_model_and_assets() -> tuple[bytes, dict[str, bytes]]:
    """dm_control's finger.xml and its common assets (`common.ASSETS`), as dm_control's."""
    return FINGER_XML.encode(), dict(ASSETS)


def _num(*values: float) -> str:
    return " ".join(str(v) for v in values)


def get_finger_xml_string(
    limb_length_0: float = 0.17,
    limb_length_1: float = 0.16,
    spinner_radius: float = 0.04,
    spinner_length: float = 0.18,
    **kwargs: Any,
) -> bytes:
    """carl-bench's finger XML: dm_control's finger.xml with the finger's limbs and the spinner
    sized from these values (after `check_constraints`, raising its `ValueError`)."""
    x_finger, y_finger, x_spinner, y_spinner, y_target = -0.2, 0.4, 0.2, 0.4, 0.4
    half = spinner_length / 2
    tip_radius = 0.02
    check_constraints(
        limb_length_0=limb_length_0,
        limb_length_1=limb_length_1,
        x_spinner=x_spinner,
        x_finger=x_finger,
        spinner_length=spinner_length,
        raise_error=True,
    )
    proximal_to = -limb_length_0
    root = ET.fromstring(FINGER_XML)
    named = {(e.tag, e.get("name")): e for e in root.iter() if e.get("name")}
    attrs: dict[tuple[str, str], dict[str, str]] = {
        ("body", "proximal"): {"pos": _num(x_finger, 0, y_finger)},
        ("geom", "proximal"): {"fromto": _num(0, 0, 0, 0, 0, proximal_to)},
        ("body", "distal"): {"pos": _num(0, 0, proximal_to - 0.01)},
        ("geom", "distal"): {"fromto": _num(0, 0, 0, 0, 0, -limb_length_1)},
        ("geom", "fingertip"): {"fromto": _num(0, 0, -limb_length_1 - 0.03, 0, 0, -limb_length_1 - 0.001)},
        ("body", "spinner"): {"pos": _num(x_spinner, 0, y_spinner)},
        ("geom", "cap1"): {
            "size": str(spinner_radius),
            "fromto": _num(spinner_radius / 2, 0, -half, spinner_radius, 0, half),
        },
        ("geom", "cap2"): {
            "size": str(spinner_radius),
            "fromto": _num(-spinner_radius / 2, 0, -half, 0, 0, half),
        },
        ("site", "tip"): {"size": str(tip_radius), "pos": _num(0, 0, half + 0.06 - tip_radius)},
        ("geom", "spinner_decoration"): {"size": str(spinner_radius / 2)},
        ("site", "target"): {"pos": _num(0, 0, y_target)},
    }
    for key, values in attrs.items():
        element = named[key]
        if key[1] in ("cap1", "cap2"):
            element.attrib.pop("pos", None)  # carl-bench's caps are placed by `fromto`
        for name, value in values.items():
            element.set(name, value)
    return ET.tostring(root)


def _model(context: dict[str, Any]) -> tuple[bytes, dict[str, bytes]]:
    xml = get_finger_xml_string(**context)
    return (adapt_context(xml_string=xml, context=context) if context else xml), dict(ASSETS)


def _task(name: str, target_radius: float | None) -> Any:
    def task(suite: Any, random: Any) -> Any:
        if target_radius is None:
            return suite.Spin(random=random)
        return suite.Turn(target_radius=target_radius, random=random)

    return _dm_control.task_function(
        "finger",
        name,
        "CARLDmcFingerEnv(task=...)",
        _model,
        task,
        _DEFAULT_TIME_LIMIT,
        _CONTROL_TIMESTEP,
        f"carl-bench's {name}: dm_control's finger {'Spin' if target_radius is None else 'Turn'} task on "
        "`get_finger_xml_string(**context)` adapted to `context` (needs dm_control).",
    )


spin_context = _task("spin_context", None)
turn_easy_context = _task("turn_easy_context", _EASY_TARGET_SIZE)
turn_hard_context = _task("turn_hard_context", _HARD_TARGET_SIZE)

__all__ = ["check_constraints", "get_finger_xml_string", "get_model_and_assets", "spin_context", "turn_easy_context", "turn_hard_context"]
