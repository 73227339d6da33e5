#!/usr/bin/env python3
"""MuJoCo's compiled bodies of dm_control's finger at other sizes: the fixture of dmc_finger's sizes.

carl-bench's `CARLDmcFingerEnv` regenerates finger.xml from `limb_length_0`, `limb_length_1`,
`spinner_radius` and `spinner_length` and MuJoCo recompiles the masses and inertias. carl-spec's
`dmc_finger` puts the sizes into dm_control's geometry (carl-bench's generator misplaces the
fingertip and tilts the spinner's capsules, so its default model is not dm_control's; see
crates/carl-envs-dmc/src/finger.rs) and recomputes the bodies as MuJoCo's compiler does. This
script edits dm_control's own finger.xml the same way, lets MuJoCo compile it, and writes each
body's mass, centre of mass and inertia tensor (world-aligned, from `body_iquat` and
`body_inertia`) to crates/carl-envs-dmc/tests/fixtures/finger_sizes.json, which
`finger::tests` compares with the Rust recomputation.

Run from the repository root with dm_control 1.0.50 (mujoco < 4): `python scripts/dmc_finger_sizes.py`
(`--check` compares with the committed file).
"""
import argparse
import json
import os
import sys
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from articulated_mujoco_fixtures import write_or_check  # noqa: E402

OUT = "crates/carl-envs-dmc/tests/fixtures/finger_sizes.json"
SIZES = [
    dict(limb_length_0=0.17, limb_length_1=0.16, spinner_radius=0.04, spinner_length=0.18),
    dict(limb_length_0=0.2, limb_length_1=0.12, spinner_radius=0.025, spinner_length=0.3),
    dict(limb_length_0=0.12, limb_length_1=0.2, spinner_radius=0.05, spinner_length=0.16),
]


def sized_xml(xml, s):
    """dm_control's finger.xml with the sizes `s` (the geometry dmc_finger uses)."""
    root = ET.fromstring(xml)
    l0, l1, r, ls = s["limb_length_0"], s["limb_length_1"], s["spinner_radius"], s["spinner_length"]
    for e in root.iter("geom"):
        n = e.get("name")
        if n == "proximal":
            e.set("fromto", f"0 0 0 0 0 {-l0}")
        elif n == "distal":
            e.set("fromto", f"0 0 0 0 0 {-l1}")
        elif n == "fingertip":
            e.set("fromto", f"0 0 {-(l1 - 0.03)} 0 0 {-(l1 + 0.001)}")
        elif n in ("cap1", "cap2"):
            e.set("size", f"{r} {ls / 2}")
            e.set("pos", f"{r / 2 if n == 'cap1' else -r / 2} 0 0")
        elif n == "spinner_decoration":
            e.set("size", f"{r / 2}")
    for e in root.iter("body"):
        if e.get("name") == "distal":
            e.set("pos", f"0 0 {-(l0 + 0.01)}")
    return ET.tostring(root, encoding="unicode")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true")
    args = ap.parse_args()
    import mujoco
    import numpy as np
    from dm_control.suite import finger

    xml, assets = finger.get_model_and_assets()
    cases = []
    for s in SIZES:
        m = mujoco.MjModel.from_xml_string(sized_xml(xml, s), assets)
        bodies = {}
        for b in range(1, m.nbody):
            rot = np.zeros(9)
            mujoco.mju_quat2Mat(rot, m.body_iquat[b])
            rot = rot.reshape(3, 3)
            tensor = rot @ np.diag(m.body_inertia[b]) @ rot.T
            bodies[mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b)] = dict(
                mass=float(m.body_mass[b]), ipos=[float(x) for x in m.body_ipos[b]],
                inertia=[[float(x) for x in row] for row in tensor])
        cases.append(dict(sizes=s, bodies=bodies))
    text = json.dumps(dict(source=f"dm_control 1.0.50 finger.xml resized, compiled by MuJoCo {mujoco.__version__} "
                           "(scripts/dmc_finger_sizes.py)", cases=cases), indent=1) + "\n"
    sys.exit(0 if write_or_check(OUT, text, args.check) else 1)


if __name__ == "__main__":
    main()
