"""carl-bench's `carl.envs.dmc.dmc_tasks.quadruped`, over carl-spec's `dmc_quadruped`.

carl-spec builds its quadruped from dm_control's compiled model (no MuJoCo XML is read), so
`make_model` returns the XML text dm_control's (and carl-bench's) `make_model` would: quadruped.xml
with the floor's size set and the walls, ball, target, terrain and rangefinders removed unless
asked for. carl-bench's task functions returned dm_control environments, which carl-spec has
not: they raise, naming the class to use (walk and run are `CARLDmcQuadrupedEnv`'s tasks; escape
and fetch, with their terrain and ball, are not in carl-spec).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from typing import Any, NoReturn

from ._quadruped_xml import QUADRUPED_XML

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


def _no_dm_control(name: str, hint: str) -> Any:
    def refuse(*_: Any, **__: Any) -> NoReturn:
        raise NotImplementedError(
            f"carl_spec.compat: carl-bench's {name} returned a dm_control environment, which carl-spec has not; {hint}"
        )

    refuse.__name__ = refuse.__qualname__ = name
    return refuse


_USE = "use CARLDmcQuadrupedEnv(task=...) or carl_spec.make('dmc_quadruped')"
walk_context = _no_dm_control("walk_context", _USE)
run_context = _no_dm_control("run_context", _USE)
escape_context = _no_dm_control("escape_context", "carl-spec has no quadruped escape task (its terrain); " + _USE)
fetch_context = _no_dm_control("fetch_context", "carl-spec has no quadruped fetch task (its ball); " + _USE)

__all__ = ["make_model", "walk_context", "run_context", "escape_context", "fetch_context"]
