#!/usr/bin/env python3
"""Convert dm_control's suite models into crates/carl-envs-dmc/models/<domain>.json.

dm_control's own XML (`dm_control.suite.<domain>.get_model_and_assets()`) is compiled by
MuJoCo, so every number is MuJoCo's: body masses and inertias (from the geoms' densities or
masses), joint anchors, axes, ranges, damping, armature and springs, geom shapes, poses and
contact parameters, fixed tendons and tendon equalities, sites, actuator gears, transmissions and control ranges, and the
options (time step, integrator, gravity, medium density, viscosity and wind). The fields are
those of scripts/articulated_mujoco_fixtures.py (`model_json`, which carl-articulated's parity
tests read) plus the names of bodies, joints, geoms, actuators and tendons and the option flags
the engine reads from the model (`contact` false: `<flag contact="disable"/>`; `constraint`
false: `<flag constraint="disable"/>`, no contacts and no joint limits; gravity is
written as MuJoCo holds it, zero when disabled), and which bodies take their mass from their
geoms' density (`body_mass_from_density`: no geom of theirs states a mass). The Rust loader
(crates/carl-envs-dmc/src/mjcf.rs) builds carl-articulated's model from them and applies the
context.

Run from the repository root with dm_control 1.0.50 (which needs mujoco < 4) installed, e.g. in
a venv outside the repository: `python scripts/dmc_models.py` (all domains) or `... point_mass`;
`--check` compares with the committed files instead of writing.
"""
import argparse
import importlib
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from articulated_mujoco_fixtures import model_json, write_or_check  # noqa: E402

OUT = "crates/carl-envs-dmc/models"
DOMAINS = ["finger", "fish", "point_mass", "quadruped", "walker"]


def names(mujoco, m, obj, n):
    return [mujoco.mj_id2name(m, obj, i) or "" for i in range(n)]


def bodies_with_given_mass(xml):
    """Names of the bodies one of whose geoms states a non-zero mass (the others' masses come from
    their geoms' densities, which carl-bench's geom_density scales; fish.xml's torso has massless
    decorations and a box of the default density)."""
    import xml.etree.ElementTree as ET

    root = ET.fromstring(xml)
    return {b.get("name") for b in root.iter("body")
            if any(g.get("mass") is not None and float(g.get("mass")) != 0 for g in b.findall("geom"))}


def convert(domain):
    import dm_control
    import mujoco
    module = importlib.import_module(f"dm_control.suite.{domain}")
    if domain == "quadruped":
        # walk's model: make_model strips the walls, ball, target, terrain and rangefinders (the
        # floor's size does not matter to an infinite plane, so run's model is the same).
        from dm_control.suite import common
        xml, assets = module.make_model(floor_size=module._DEFAULT_TIME_LIMIT * module._WALK_SPEED), common.ASSETS
    else:
        xml, assets = module.get_model_and_assets()
    m = mujoco.MjModel.from_xml_string(xml, assets)
    out = model_json(mujoco, m)
    out["opt"]["density"] = float(m.opt.density)
    out["opt"]["wind"] = [float(x) for x in m.opt.wind]
    out["opt"]["contact"] = not (m.opt.disableflags & int(mujoco.mjtDisableBit.mjDSBL_CONTACT))
    out["opt"]["constraint"] = not (m.opt.disableflags & int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT))
    out["opt"]["gravity_disabled"] = bool(m.opt.disableflags & int(mujoco.mjtDisableBit.mjDSBL_GRAVITY))
    o = mujoco.mjtObj
    out["names"] = dict(bodies=names(mujoco, m, o.mjOBJ_BODY, m.nbody), joints=names(mujoco, m, o.mjOBJ_JOINT, m.njnt),
                        geoms=names(mujoco, m, o.mjOBJ_GEOM, m.ngeom),
                        actuators=names(mujoco, m, o.mjOBJ_ACTUATOR, m.nu),
                        tendons=names(mujoco, m, o.mjOBJ_TENDON, m.ntendon))
    if m.nsite:
        kind = {int(mujoco.mjtGeom.mjGEOM_SPHERE): "sphere", int(mujoco.mjtGeom.mjGEOM_ELLIPSOID): "ellipsoid",
                int(mujoco.mjtGeom.mjGEOM_BOX): "box", int(mujoco.mjtGeom.mjGEOM_CAPSULE): "capsule",
                int(mujoco.mjtGeom.mjGEOM_CYLINDER): "cylinder"}
        out["sites"] = [dict(name=mujoco.mj_id2name(m, o.mjOBJ_SITE, s), body=int(m.site_bodyid[s]),
                             shape=kind[int(m.site_type[s])], size=[float(x) for x in m.site_size[s]],
                             pos=[float(x) for x in m.site_pos[s]], quat=[float(x) for x in m.site_quat[s]])
                        for s in range(m.nsite)]
    given = bodies_with_given_mass(xml)
    out["body_mass_from_density"] = [i > 0 and out["names"]["bodies"][i] not in given for i in range(m.nbody)]
    if m.ntendon and "tendons" not in out:
        out["tendons"] = [[[int(m.wrap_objid[w]), float(m.wrap_prm[w])]
                           for w in range(m.tendon_adr[t], m.tendon_adr[t] + m.tendon_num[t])]
                          for t in range(m.ntendon)]
    if m.neq:
        assert all(int(t) == int(mujoco.mjtEq.mjEQ_TENDON) for t in m.eq_type), "only tendon equalities"
        out["tendon_equalities"] = [dict(tendon1=int(m.eq_obj1id[e]),
                                         tendon2=int(m.eq_obj2id[e]) if m.eq_obj2id[e] >= 0 else None,
                                         polycoef=[float(x) for x in m.eq_data[e][:5]],
                                         solref=[float(x) for x in m.eq_solref[e]],
                                         solimp=[float(x) for x in m.eq_solimp[e]]) for e in range(m.neq)]
    if m.nsite:
        out["sites"] = [dict(name=mujoco.mj_id2name(m, o.mjOBJ_SITE, s) or "", body=int(m.site_bodyid[s]),
                             pos=[float(x) for x in m.site_pos[s]], quat=[float(x) for x in m.site_quat[s]])
                        for s in range(m.nsite)]
    source = (f"dm_control {dm_control.__version__ if hasattr(dm_control, '__version__') else '1.0.50'} "
              f"suite/{domain}.xml compiled by MuJoCo {mujoco.__version__} (scripts/dmc_models.py)")
    return dict(source=source, model=out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("domains", nargs="*", default=DOMAINS)
    ap.add_argument("--check", action="store_true", help="compare with the committed files")
    args = ap.parse_args()
    bad = 0
    for domain in args.domains:
        path = os.path.join(OUT, f"{domain}.json")
        text = json.dumps(convert(domain), indent=1) + "\n"
        bad += not write_or_check(path, text, args.check)
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
