"""carl-bench's `carl.envs.dmc.dmc_tasks.utils`: `adapt_context`, its MuJoCo XML editing.

Written with the standard library's `xml.etree` (carl-bench used lxml): the edited XML parses to
the same elements, attributes and values as carl-bench's (comments and whitespace aside), which
scripts/compare_adapt_context.py checks against carl-bench 1.1.1 on every domain's XML.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from typing import Any

#: MuJoCo's defaults as carl-bench assumed them where the XML sets none
_DEFAULT_JOINT_DAMPING = 0.1
_DEFAULT_FRICTION = (1.0, 0.005, 0.0001)
_DEFAULT_GEOM_DENSITY = 1000
_FRICTION = ("friction_tangential", "friction_torsional", "friction_rolling")
_WIND = ("wind_x", "wind_y", "wind_z")


def adapt_context(xml_string: bytes | str, context: dict[str, Any]) -> bytes:
    """The MuJoCo XML `xml_string` with `context` applied, as carl-bench 1.1.1 applied it.

    * `joint_damping`, `joint_stiffness`: every `<joint>` with a `damping` (`stiffness`) of its
      own, defaults included, has it multiplied by the factor.
    * `friction_tangential`, `friction_torsional`, `friction_rolling` (all three, or none is
      applied): every `<geom>` with a `friction` has its values multiplied component-wise.
    * `geom_density`: every `<geom>` with a `density` has it multiplied.
    * `actuator_strength`: every actuator's `gear` is multiplied (a missing `gear` counts as 1).
    * `gravity`: `<option gravity>`'s z component becomes `-gravity` (x and y are kept).
    * `wind_x`, `wind_y`, `wind_z` (all three), `timestep`, `density`, `viscosity`: set on
      `<option>`, which is added at the end of the model if it has none.

    When the model's top-level `<default>` has no `<joint>` (`<geom>`), one is added to it; its
    damping is `0.1 * joint_damping`, its stiffness `joint_stiffness`, its friction MuJoCo's
    `1 0.005 0.0001` times the three factors and its density `1000 * geom_density`.

    carl-bench's edits kept as they were, although they are bugs (docs/guides/migration.md):

    * `joint_stiffness` multiplies the stiffness a joint sets but is the added default joint's
      stiffness itself (not MuJoCo's default 0 times it). carl-bench's default, 0, so zeroes
      dm_control's own stiffnesses (the fish's tail); a factor of 1 (carl-spec's default) gives
      every joint that sets none stiffness 1 in a model whose top-level `<default>` has no
      `<joint>` (dm_control's fish, which then blows up, and quadruped);
    * the added default joint's damping is 0.1 times the factor where MuJoCo's default is 0;
    * an actuator without a `gear` of its own gets `gear = actuator_strength`, replacing the gear
      its default class gives it (point mass: `.1`, so carl-bench's point mass pushes 10 times
      harder than dm_control's at the default context); a gear of several values raises
      `ValueError`;
    * friction and gear strings are split on single spaces;
    * a model without a non-empty top-level `<default>` raises `TypeError` (lxml refuses
      carl-bench's attempt to add one next to the root); every dm_control model has one.
    """
    root = ET.fromstring(xml_string)
    # carl-bench's "./default/": the first element of the first non-empty top-level <default>;
    # the defaults it adds go right after that element.
    parent = next((d for d in root.findall("./default") if len(d)), None)
    if parent is None:
        raise TypeError(
            "adapt_context: the model has no non-empty top-level <default> (carl-bench's adapt_context fails the "
            "same way: lxml refuses to add one as a sibling of the root element)"
        )

    def add_default(tag: str) -> ET.Element:
        element = ET.Element(tag)
        parent.insert(1, element)
        return element

    if "joint_damping" in context:
        for joint in root.findall(".//joint[@damping]"):
            joint.set("damping", str(float(joint.get("damping", "")) * context["joint_damping"]))
    if "joint_stiffness" in context:
        for joint in root.findall(".//joint[@stiffness]"):
            joint.set("stiffness", str(float(joint.get("stiffness", "")) * context["joint_stiffness"]))
    if root.find("./default/joint") is None:
        joint = add_default("joint")
        if "joint_damping" in context:
            joint.set("damping", str(float(_DEFAULT_JOINT_DAMPING) * context["joint_damping"]))
        if "joint_stiffness" in context:
            joint.set("stiffness", str(context["joint_stiffness"]))

    friction = all(k in context for k in _FRICTION)
    if friction:
        for geom in root.findall(".//geom[@friction]"):
            values = geom.get("friction", "").split(" ")
            geom.set("friction", " ".join(str(float(v) * context[k]) for v, k in zip(values, _FRICTION)))
    if "geom_density" in context:
        for geom in root.findall(".//geom[@density]"):
            geom.set("density", str(float(geom.get("density", "")) * context["geom_density"]))
    default_geom = root.find("./default/geom")
    if default_geom is None:
        default_geom = add_default("geom")
    if friction and default_geom.get("friction") is None:
        default_geom.set("friction", " ".join(str(d * context[k]) for d, k in zip(_DEFAULT_FRICTION, _FRICTION)))
    if "geom_density" in context and default_geom.get("density") is None:
        default_geom.set("density", str(float(_DEFAULT_GEOM_DENSITY) * context["geom_density"]))

    if "actuator_strength" in context:
        for actuator in root.findall("./actuator/*"):
            actuator.set("gear", str(float(actuator.get("gear", 1)) * context["actuator_strength"]))

    option = root.find(".//option")
    if option is None:
        option = ET.SubElement(root, "option")
    if "gravity" in context:
        gravity = option.get("gravity")
        g = gravity.split(" ") if gravity is not None else ["0", "0"]
        option.set("gravity", " ".join([g[0], g[1], str(-context["gravity"])]))
    if all(k in context for k in _WIND):
        option.set("wind", " ".join(str(context[k]) for k in _WIND))
    for name in ("timestep", "density", "viscosity"):
        if name in context:
            option.set(name, str(context[name]))
    return ET.tostring(root)


__all__ = ["adapt_context"]
