"""carl-bench's `carl.envs.dmc.dmc_tasks.quadruped`, over carl-spec's `dmc_quadruped`.

carl-spec builds its quadruped from dm_control's compiled model (no MuJoCo XML is read), so
`make_model` returns the XML text dm_control's (and carl-bench's) `make_model` would: quadruped.xml
with the floor's size set and the walls, ball, target, terrain and rangefinders removed unless
asked for. carl-bench's task functions return dm_control environments, built as carl-bench's were
(this XML, `adapt_context`, dm_control's quadruped tasks); they need dm_control and without it
raise `DmControlMissingError` naming carl-spec's own runtime (walk and run are
`CARLDmcQuadrupedEnv`'s tasks; escape and fetch, with their terrain and ball, are not in carl-spec).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from typing import Any

from . import _dm_control
from ._common_xml import ASSETS
from ._quadruped_xml import QUADRUPED_XML
from .utils import adapt_context

# dm_control's quadruped.py
_DEFAULT_TIME_LIMIT = 20
_CONTROL_TIMESTEP = 0.02
_RUN_SPEED = 5
_WALK_SPEED = 0.5

_WALLS = ["wall_px", "wall_py", "wall_nx", "wall_ny"]


def _remove(root: ET.Element, tag: str, name: str) -> None:
    for parent in root.iter():
        for child in list(parent):
            if child.tag == tag and child.get("name") == name:
                parent.remove(child)
                return


def make_model(
    floor_size: float | None = None,
    terrain: bool = False,
    rangefinders: bool = False,
    walls_and_ball: bool = False,
) -> bytes:
    """dm_control's quadruped XML as its `make_model` edits it."""
    root = ET.fromstring(QUADRUPED_XML)
    if floor_size is not None:
        for g in root.iter("geom"):
            if g.get("name") == "floor":
                g.set("size", f"{floor_size} {floor_size} .5")
    if not walls_and_ball:
        for wall in _WALLS:
            _remove(root, "geom", wall)
        _remove(root, "body", "ball")
        _remove(root, "site", "target")
    if not terrain:
        _remove(root, "geom", "terrain")
    if not rangefinders:
        for parent in root.iter():
            for child in list(parent):
                if child.tag == "rangefinder":
                    parent.remove(child)
    return ET.tostring(root)


def _task(name: str, model: dict[str, Any], task_class: str, task_kwargs: dict[str, Any], instead: str) -> Any:
    def xml_and_assets(context: dict[str, Any]) -> tuple[bytes, dict[str, bytes]]:
        xml = make_model(**model)
        return (adapt_context(xml_string=xml, context=context) if context else xml), dict(ASSETS)

    return _dm_control.task_function(
        "quadruped",
        name,
        instead,
        xml_and_assets,
        lambda suite, random: getattr(suite, task_class)(random=random, **task_kwargs),
        _DEFAULT_TIME_LIMIT,
        _CONTROL_TIMESTEP,
        f"carl-bench's {name}: dm_control's quadruped {task_class} task on `make_model({model})` adapted to "
        "`context` (needs dm_control).",
    )


_USE = "CARLDmcQuadrupedEnv(task=...) or carl_spec.make('dmc_quadruped')"
_NO_TASK = "(carl-spec has no quadruped {} task: its {})"
walk_context = _task("walk_context", {"floor_size": _DEFAULT_TIME_LIMIT * _WALK_SPEED}, "Move", {"desired_speed": _WALK_SPEED}, _USE)
run_context = _task("run_context", {"floor_size": _DEFAULT_TIME_LIMIT * _RUN_SPEED}, "Move", {"desired_speed": _RUN_SPEED}, _USE)
escape_context = _task(
    "escape_context",
    {"floor_size": 40, "terrain": True, "rangefinders": True},
    "Escape",
    {},
    f"{_USE} {_NO_TASK.format('escape', 'terrain')}",
)
fetch_context = _task("fetch_context", {"walls_and_ball": True}, "Fetch", {}, f"{_USE} {_NO_TASK.format('fetch', 'ball')}")

__all__ = ["make_model", "walk_context", "run_context", "escape_context", "fetch_context"]
