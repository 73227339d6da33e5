"""carl-bench's `carl.envs.dmc.dmc_tasks.pointmass`, over carl-spec's `dmc_point_mass`.

carl-spec builds its model from dm_control's compiled point_mass.xml (no MuJoCo XML is read);
`make_model` returns carl-bench's XML (dm_control's with its values), and `check_constraints`
applies carl-spec's rule: start and target must lie in the arena the ball moves in, within
`area_size / 2 - 0.01` of the centre (carl-bench's rule, `area_size / 4`, did not match its
model). `get_model_and_assets` is dm_control's point_mass.xml and its common assets (shipped with
carl-spec, no dm_control needed).

carl-bench's task functions (`easy_pointmass`, `hard_pointmass`) return dm_control environments:
`make_model(**context)` adapted to the context, with dm_control's PointMass task changed as
carl-bench's `ContextualPointMass` changed it: the slides start at 0.2 whatever the context
(carl-bench's `starting_x`/`starting_y` class attributes, never set) while the context's start
moves the body, so the ball starts at the start + 0.2. They need dm_control and without it raise `DmControlMissingError`
naming `CARLDmcPointMassEnv(task=...)`, carl-spec's own runtime.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from typing import Any

from . import _dm_control
from ._common_xml import ASSETS
from ._point_mass_xml import POINT_MASS_XML
from .utils import adapt_context

# dm_control's point_mass.py
_DEFAULT_TIME_LIMIT = 20

#: the ball's radius (point_mass.xml): the arena's slides stop it this far inside the walls
BALL_RADIUS = 0.01


def check_constraints(
    mass: float,
    starting_x: float,
    starting_y: float,
    target_x: float,
    target_y: float,
    area_size: float,
) -> None:
    """Raise `ValueError` unless start and target lie in the arena."""
    r = area_size / 2 - BALL_RADIUS
    for what, x, y in (("starting", starting_x, starting_y), ("target", target_x, target_y)):
        if abs(x) > r or abs(y) > r:
            raise ValueError(
                f"The {what} point ({x}, {y}) lies outside the arena of area_size {area_size}: "
                f"|x| and |y| must be at most {r}."
            )


def make_model(
    mass: float = 0.3,
    starting_x: float = 0.0,
    starting_y: float = 0.0,
    target_x: float = 0.0,
    target_y: float = 0.0,
    area_size: float = 0.6,
    **kwargs: Any,
) -> bytes:
    """carl-bench's XML of the point mass under these values (after carl-spec's
    `check_constraints`): dm_control's point_mass.xml with the floor and walls at `area_size / 2`,
    the body and its slides at the start, the ball's mass and the target set as carl-bench set
    them."""
    check_constraints(mass, starting_x, starting_y, target_x, target_y, area_size)
    h = area_size / 2
    attrs = {
        ("geom", "ground"): {"size": f"{h} {h} .1"},
        ("geom", "wall_x"): {"pos": f"{-h} 0 .02"},
        ("geom", "wall_y"): {"pos": f"0 {-h} .02"},
        ("geom", "wall_neg_x"): {"pos": f"{h} 0 .02"},
        ("geom", "wall_neg_y"): {"pos": f"0 {h} .02"},
        ("body", "pointmass"): {"pos": f"{starting_x} {starting_y} .01"},
        ("joint", "root_x"): {"pos": f"{starting_x} {starting_y} 0"},
        ("joint", "root_y"): {"pos": f"{starting_x} {starting_y} 0"},
        ("geom", "pointmass"): {"mass": f"{mass}"},
        ("geom", "target"): {"pos": f"{target_x} {target_y} .01"},
    }
    root = ET.fromstring(POINT_MASS_XML)
    for e in root.iter():
        for name, value in attrs.get((e.tag, e.get("name", "")), {}).items():
            e.set(name, value)
    return ET.tostring(root)


def get_model_and_assets() -> tuple[bytes, dict[str, bytes]]:
    """dm_control's point_mass.xml and its common assets (`common.ASSETS`), as dm_control's."""
    return POINT_MASS_XML.encode(), dict(ASSETS)


def _contextual_point_mass(randomize_gains: bool, random: Any) -> Any:
    """dm_control's PointMass task as carl-bench's `ContextualPointMass` ran it."""
    import numpy as np
    from dm_control.suite import point_mass

    class ContextualPointMass(point_mass.PointMass):  # type: ignore[misc]
        starting_x: float = 0.2
        starting_y: float = 0.2

        def initialize_episode(self, physics: Any) -> None:
            # carl-bench drew the gains' directions here, then dm_control's PointMass drew its own
            # (both from the task's stream), then the start was set.
            if self._randomize_gains:
                dir1 = self.random.randn(2)
                dir1 /= np.linalg.norm(dir1)
                parallel = True
                while parallel:
                    dir2 = self.random.randn(2)
                    dir2 /= np.linalg.norm(dir2)
                    parallel = abs(np.dot(dir1, dir2)) > 0.9
                physics.model.wrap_prm[[0, 1]] = dir1
                physics.model.wrap_prm[[2, 3]] = dir2
            super().initialize_episode(physics)
            physics.named.data.qpos["root_x"] = self.starting_x
            physics.named.data.qpos["root_y"] = self.starting_y

    return ContextualPointMass(randomize_gains=randomize_gains, random=random)


def _model(context: dict[str, Any]) -> tuple[bytes, dict[str, bytes]]:
    xml = make_model(**context)
    return (adapt_context(xml_string=xml, context=context) if context else xml), dict(ASSETS)


def _task(name: str, randomize_gains: bool) -> Any:
    return _dm_control.task_function(
        "point_mass",
        name,
        f"CARLDmcPointMassEnv(task={name!r})",
        _model,
        lambda suite, random: _contextual_point_mass(randomize_gains, random),
        _DEFAULT_TIME_LIMIT,
        None,
        f"carl-bench's {name}: dm_control's PointMass task ({'randomized' if randomize_gains else 'fixed'} gains) "
        "on `make_model(**context)` adapted to `context` (needs dm_control).",
        context_mask=True,
    )


easy_pointmass = _task("easy_pointmass", False)
hard_pointmass = _task("hard_pointmass", True)

__all__ = ["check_constraints", "get_model_and_assets", "make_model", "easy_pointmass", "hard_pointmass"]
