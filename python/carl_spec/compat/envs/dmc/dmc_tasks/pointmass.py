"""carl-bench's `carl.envs.dmc.dmc_tasks.pointmass`, over carl-spec's `dmc_point_mass`.

carl-spec builds its model from dm_control's compiled point_mass.xml (no MuJoCo XML is read), so
`make_model` returns carl-bench's XML text for code that inspects it, and `check_constraints`
applies carl-spec's rule: start and target must lie in the arena the ball moves in, within
`area_size / 2 - 0.01` of the centre (carl-bench's rule, `area_size / 4`, did not match its
model). carl-bench's task functions returned dm_control environments, which carl-spec has not:
they raise, naming the class to use.
"""

from __future__ import annotations

from typing import Any, NoReturn

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
    """carl-bench's XML of the point mass under these values (after `check_constraints`)."""
    check_constraints(mass, starting_x, starting_y, target_x, target_y, area_size)
    h = area_size / 2
    return f"""<mujoco model="planar point mass">
  <option timestep="0.02"><flag contact="disable"/></option>
  <default>
    <joint type="hinge" axis="0 0 1" limited="true" range="-.29 .29" damping="1"/>
    <motor gear=".1" ctrlrange="-1 1" ctrllimited="true"/>
  </default>
  <worldbody>
    <geom name="ground" type="plane" pos="0 0 0" size="{h} {h} .1"/>
    <body name="pointmass" pos="0 0 .01">
      <joint name="root_x" type="slide" pos="0 0 0" axis="1 0 0"/>
      <joint name="root_y" type="slide" pos="0 0 0" axis="0 1 0"/>
      <geom name="pointmass" type="sphere" size=".01" mass="{mass}"/>
    </body>
    <geom name="target" pos="{target_x} {target_y} .01" type="sphere" size=".015"/>
  </worldbody>
  <tendon>
    <fixed name="t1"><joint joint="root_x" coef="1"/><joint joint="root_y" coef="0"/></fixed>
    <fixed name="t2"><joint joint="root_x" coef="0"/><joint joint="root_y" coef="1"/></fixed>
  </tendon>
  <actuator><motor name="t1" tendon="t1"/><motor name="t2" tendon="t2"/></actuator>
</mujoco>
""".encode()


def _no_dm_control(name: str, cls_task: str) -> Any:
    def refuse(*_: Any, **__: Any) -> NoReturn:
        raise NotImplementedError(
            f"carl_spec.compat: carl-bench's {name} returned a dm_control Environment, which carl-spec has not; "
            f"use CARLDmcPointMassEnv(task={cls_task!r}) or carl_spec.make('dmc_point_mass')"
        )

    refuse.__name__ = refuse.__qualname__ = name
    return refuse


easy_pointmass = _no_dm_control("easy_pointmass", "easy_pointmass")
hard_pointmass = _no_dm_control("hard_pointmass", "hard_pointmass")

__all__ = ["check_constraints", "make_model", "easy_pointmass", "hard_pointmass"]
