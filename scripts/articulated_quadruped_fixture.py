#!/usr/bin/env python3
"""Write crates/carl-articulated/tests/fixtures/mujoco_quadruped.json: carl-articulated's parity
fixture for the ellipsoid, tendon equalities and site sensors, on dm_control's quadruped.

dm_control 1.0.50's quadruped.xml as `quadruped.make_model` strips it for the walk task, its
actuators removed (the engine's general actuators have their own fixture): the torso (an
ellipsoid) dropped upside down and tilted onto the floor, its legs moving, their pitch, knee
and ankle coupled by the tendon equalities. Every 10 steps: MuJoCo's state and, after
`mj_forward` of that state, its sensors (accelerometer, gyro, velocimeter at the torso; force
and torque at the four toes; the torso's subtree centre of mass) and contact count. Sites are
written with the model (`sites`: body, position, orientation).

Run from the repository root with dm_control 1.0.50 and MuJoCo 3 (a venv outside the repository):
`python scripts/articulated_quadruped_fixture.py` (`--check` compares instead of writing).
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from articulated_mujoco_fixtures import model_json, r, write_or_check  # noqa: E402

OUT = "crates/carl-articulated/tests/fixtures/mujoco_quadruped.json"


def build():
    import mujoco
    import numpy as np
    from dm_control.suite import common, quadruped
    from lxml import etree

    xml = quadruped.make_model(floor_size=10)
    root = etree.XML(xml)
    act = root.find("actuator")
    act.getparent().remove(act)
    xml = etree.tostring(root)
    m = mujoco.MjModel.from_xml_string(xml, common.ASSETS)
    out = model_json(mujoco, m)
    out["tendons"] = [[[int(m.wrap_objid[w]), r(m.wrap_prm[w])]
                       for w in range(m.tendon_adr[t], m.tendon_adr[t] + m.tendon_num[t])]
                      for t in range(m.ntendon)]
    out["tendon_equalities"] = [dict(tendon1=int(m.eq_obj1id[e]), tendon2=None, polycoef=r(m.eq_data[e][:5]),
                                     solref=r(m.eq_solref[e]), solimp=r(m.eq_solimp[e])) for e in range(m.neq)]
    out["tendon_invweight0"] = r(m.tendon_invweight0)
    sensors = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_SENSOR, s) for s in range(m.nsensor)]
    sites = {}
    for s in range(m.nsensor):
        if m.sensor_objtype[s] == mujoco.mjtObj.mjOBJ_SITE:
            i = int(m.sensor_objid[s])
            sites[sensors[s]] = dict(body=int(m.site_bodyid[i]), pos=r(m.site_pos[i]), quat=r(m.site_quat[i]))
    kinds = {int(mujoco.mjtSensor.mjSENS_ACCELEROMETER): "accelerometer", int(mujoco.mjtSensor.mjSENS_GYRO): "gyro",
             int(mujoco.mjtSensor.mjSENS_VELOCIMETER): "velocimeter", int(mujoco.mjtSensor.mjSENS_FORCE): "force",
             int(mujoco.mjtSensor.mjSENS_TORQUE): "torque", int(mujoco.mjtSensor.mjSENS_SUBTREECOM): "subtreecom"}
    sensor_list = [dict(name=sensors[s], kind=kinds[int(m.sensor_type[s])], site=sites.get(sensors[s]),
                        body=int(m.sensor_objid[s]), adr=int(m.sensor_adr[s])) for s in range(m.nsensor)]
    d = mujoco.MjData(m)
    # Upside down, tilted, 0.5 m up; legs bent and swinging.
    q = np.array([0.0, 0.0, 0.5])
    quat = np.array([0.2, 0.9, 0.3, 0.1])
    d.qpos[:3] = q
    d.qpos[3:7] = quat / np.linalg.norm(quat)
    d.qpos[7:] = 0.3 * np.sin(np.arange(m.nq - 7))
    d.qvel[6:] = 2.0 * np.cos(np.arange(m.nv - 6))
    d.qvel[:6] = [0.3, -0.2, 0.0, 1.0, -0.5, 0.8]
    qpos0, qvel0 = d.qpos.copy(), d.qvel.copy()
    traj = []
    for s in range(0, 401):
        if s % 10 == 0:
            mujoco.mj_forward(m, d)
            traj.append(dict(step=s, time=r(d.time), qpos=r(d.qpos), qvel=r(d.qvel), ncon=int(d.ncon),
                             sensordata=r(d.sensordata)))
        mujoco.mj_step(m, d)
    return dict(source=f"dm_control 1.0.50 quadruped.xml without actuators, MuJoCo {mujoco.__version__} "
                       "(scripts/articulated_quadruped_fixture.py)",
                model=out, qpos0=r(qpos0), qvel0=r(qvel0), sensors=sensor_list, trajectory=traj)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true")
    args = ap.parse_args()
    text = json.dumps(build(), indent=1) + "\n"
    sys.exit(0 if write_or_check(OUT, text, args.check) else 1)


if __name__ == "__main__":
    main()
