"""Compare carl_spec.compat's adapt_context (xml.etree) with carl-bench 1.1.1's (lxml).

For every domain's XML (dm_control's finger, fish, walker, point_mass and quadruped models, and
carl-bench's finger and point mass templates) and many random contexts (random subsets of the
features adapt_context reads, random values), both functions edit the XML; the results must parse
to the same tree (tags, attributes and their string values, children in order; comments and
whitespace ignored). Also checks that carl-spec's shipped XML texts equal dm_control's, and that
compat's get_finger_xml_string and the point mass's and quadruped's make_model equal carl-bench's.

Run in a venv with carl-bench's dm_control dependencies and carl-spec:

    pip install dm_control==1.0.50 'mujoco<4' lxml
    pip install --no-deps carl-bench==1.1.1
    pip install carl-spec   # or the wheel / PYTHONPATH=python with the built extension
    python scripts/compare_adapt_context.py [--contexts 300] [--seed 0]

carl-bench's package imports ConfigSpace at its top level; this script loads only its
`dmc_tasks/utils.py`, the finger and point mass templates and the quadruped's make_model (by file), so ConfigSpace is not needed.
"""

from __future__ import annotations

import argparse
import importlib.util
import random
import sys
import types
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

FEATURES = {
    "joint_damping": (0.0, 3.0),
    "joint_stiffness": (0.0, 3.0),
    "friction_tangential": (0.0, 3.0),
    "friction_torsional": (0.0, 3.0),
    "friction_rolling": (0.0, 3.0),
    "geom_density": (0.1, 3.0),
    "actuator_strength": (0.1, 3.0),
    "gravity": (0.1, 20.0),
    "wind_x": (-5.0, 5.0),
    "wind_y": (-5.0, 5.0),
    "wind_z": (-5.0, 5.0),
    "timestep": (0.001, 0.02),
    "density": (0.0, 5000.0),
    "viscosity": (0.0, 0.1),
}


def carl_bench_dir() -> Path:
    spec = importlib.util.find_spec("carl")  # finds the package without importing it
    if spec is None or not spec.submodule_search_locations:
        sys.exit("carl-bench is not installed: pip install --no-deps carl-bench==1.1.1")
    return Path(next(iter(spec.submodule_search_locations))) / "envs" / "dmc" / "dmc_tasks"


def load_carl_bench() -> tuple[Any, Any, Any, Any]:
    """carl-bench's adapt_context, get_finger_xml_string and the point mass's and quadruped's
    make_model, without importing `carl`."""
    here = carl_bench_dir()
    # utils.py imports `carl.utils.types.Context` only for a type annotation.
    for name in ("carl", "carl.utils", "carl.utils.types"):
        sys.modules.setdefault(name, types.ModuleType(name))
    sys.modules["carl.utils.types"].Context = dict  # type: ignore[attr-defined]
    ns: dict[str, Any] = {}
    exec(compile((here / "utils.py").read_text(), str(here / "utils.py"), "exec"), ns)
    finger = (here / "finger.py").read_text()
    start, end = finger.index("def check_constraints"), finger.index("@SUITE.add")
    fns: dict[str, Any] = {}
    exec(compile("from typing import Any\n" + finger[start:end], str(here / "finger.py"), "exec"), fns)
    pointmass = (here / "pointmass.py").read_text()
    start, end = pointmass.index("def check_constraints"), pointmass.index("def random_limited_quaternion")
    pns: dict[str, Any] = {}
    exec(compile("from typing import Any\n" + pointmass[start:end], str(here / "pointmass.py"), "exec"), pns)
    quad = (here / "quadruped.py").read_text()
    start, end = quad.index("def make_model"), quad.index("@SUITE.add()")
    qns: dict[str, Any] = {}
    prelude = (
        "from typing import Any, Optional\nfrom lxml import etree\nfrom dm_control.suite import common\n"
        "from dm_control.utils import xml_tools\n_WALLS = ['wall_px', 'wall_py', 'wall_nx', 'wall_ny']\n"
    )
    exec(compile(prelude + quad[start:end], str(here / "quadruped.py"), "exec"), qns)
    return ns["adapt_context"], fns["get_finger_xml_string"], pns["make_model"], qns["make_model"]


def tree(xml: bytes | str) -> Any:
    """(tag, attributes, children) with comments and whitespace dropped."""

    def walk(e: ET.Element) -> Any:
        return (e.tag, dict(sorted(e.attrib.items())), [walk(c) for c in e])

    return walk(ET.fromstring(xml))


def first_difference(a: Any, b: Any, path: str = "") -> str:
    if a[0] != b[0]:
        return f"{path}: tag {a[0]} != {b[0]}"
    here = f"{path}/{a[0]}"
    if a[1] != b[1]:
        return f"{here}: {a[1]} != {b[1]}"
    if len(a[2]) != len(b[2]):
        return f"{here}: {len(a[2])} children != {len(b[2])}"
    for i, (x, y) in enumerate(zip(a[2], b[2])):
        d = first_difference(x, y, f"{here}[{i}]")
        if d:
            return d
    return ""


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--contexts", type=int, default=300, help="random contexts per model")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()

    from dm_control.suite import common

    from carl_spec.compat.envs.dmc.dmc_tasks import _common_xml, finger, fish, pointmass, quadruped, walker
    from carl_spec.compat.envs.dmc.dmc_tasks.utils import adapt_context

    theirs, their_finger, their_point_mass, their_quadruped = load_carl_bench()
    failures = 0

    # The shipped texts are dm_control's.
    shipped = {
        "finger.xml": finger.get_model_and_assets()[0],
        "fish.xml": fish.get_model_and_assets()[0],
        "walker.xml": walker.get_model_and_assets()[0],
        "point_mass.xml": pointmass.get_model_and_assets()[0],
        "quadruped.xml": quadruped.QUADRUPED_XML.encode(),
    }
    for name, text in shipped.items():
        ok = text == common.read_model(name)
        failures += not ok
        print(f"shipped {name}: {'equal' if ok else 'DIFFERENT'} to dm_control's")
    ok = _common_xml.ASSETS == common.ASSETS
    failures += not ok
    print(f"shipped common ASSETS: {'equal' if ok else 'DIFFERENT'} to dm_control's")

    rng = random.Random(args.seed)
    finger_sizes = [{}] + [
        {"limb_length_0": rng.uniform(0.15, 0.2), "limb_length_1": rng.uniform(0.15, 0.2), "spinner_length": rng.uniform(0.25, 0.35),
         "spinner_radius": rng.uniform(0.02, 0.06)}
        for _ in range(20)
    ]
    same = sum(tree(finger.get_finger_xml_string(**s)) == tree(their_finger(**s)) for s in finger_sizes)
    failures += same != len(finger_sizes)
    print(f"get_finger_xml_string: {same}/{len(finger_sizes)} size sets give the same tree as carl-bench's")

    point_masses: list[dict[str, float]] = [{}]
    for _ in range(20):
        area = rng.uniform(0.4, 1.0)
        r = 0.9 * area / 4  # inside both carl-bench's rule (area_size / 4) and carl-spec's
        point_masses.append(
            {"mass": rng.uniform(0.1, 1.0), "area_size": area, "starting_x": rng.uniform(-r, r), "starting_y": rng.uniform(-r, r),
             "target_x": rng.uniform(-r, r), "target_y": rng.uniform(-r, r)}
        )
    same = sum(tree(pointmass.make_model(**p)) == tree(their_point_mass(**p)) for p in point_masses)
    failures += same != len(point_masses)
    print(f"point mass make_model: {same}/{len(point_masses)} value sets give the same tree as carl-bench's")

    quadrupeds: list[dict[str, Any]] = [
        {}, {"floor_size": 10}, {"floor_size": 100}, {"floor_size": 40, "terrain": True, "rangefinders": True},
        {"walls_and_ball": True},
    ]
    same = sum(tree(quadruped.make_model(**q)) == tree(their_quadruped(**q)) for q in quadrupeds)
    failures += same != len(quadrupeds)
    print(f"quadruped make_model: {same}/{len(quadrupeds)} task models give the same tree as carl-bench's")

    models = {
        **{f"dm_control {k}": v for k, v in shipped.items()},
        "quadruped make_model(floor_size=10)": quadruped.make_model(floor_size=10),
        "quadruped make_model(escape)": quadruped.make_model(floor_size=40, terrain=True, rangefinders=True),
        "carl-bench finger template": their_finger(),
        "carl-bench point mass make_model": their_point_mass(),
    }
    names = list(FEATURES)
    for label, xml in models.items():
        same = 0
        first = ""
        for i in range(args.contexts):
            if i == 0:
                context: dict[str, Any] = {}
            elif i == 1:
                context = {n: rng.uniform(*FEATURES[n]) for n in names}
            else:
                context = {n: rng.uniform(*FEATURES[n]) for n in rng.sample(names, rng.randint(1, len(names)))}
                if rng.random() < 0.2:  # integer values format differently (str(2) vs str(2.0))
                    context = {k: round(v) for k, v in context.items()}
            try:
                a: Any = tree(adapt_context(xml, dict(context)))
            except Exception as e:  # noqa: BLE001 - the same exception counts as agreement
                a = ("raised", type(e).__name__)
            try:
                b: Any = tree(theirs(xml, dict(context)))
            except Exception as e:  # noqa: BLE001
                b = ("raised", type(e).__name__)
            if a == b:
                same += 1
            elif not first:
                first = f"context {context}: " + (first_difference(a, b) if len(a) == 3 and len(b) == 3 else f"{a} != {b}")
        failures += same != args.contexts
        print(f"adapt_context on {label}: {same}/{args.contexts} contexts give the same tree" + (f"; first difference: {first}" if first else ""))

    print("OK: compat's adapt_context matches carl-bench's" if not failures else f"FAILED: {failures} check(s) differ")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
