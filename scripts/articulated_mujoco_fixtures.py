#!/usr/bin/env python3
"""Parity fixtures of carl-articulated against the real MuJoCo.

Runs small MJCF models in MuJoCo and writes, per model, one JSON file under
crates/carl-articulated/tests/fixtures/: the compiled model as MuJoCo holds it (`mjModel`'s
body, joint, geom and actuator fields, options, `body_invweight0`, `dof_invweight0`), the
quantities of the first forward pass (mass matrix, bias forces, unconstrained and constrained
acceleration) and a trajectory (`qpos`, `qvel`, and `act` when the model has activations, every
`every` steps) under a fixed control
sequence. The Rust tests build the same model from these fields, so the comparison is of the
dynamics alone.

Models: MuJoCo's general actuators (position servos, a filtered servo with affine bias on a
fixed tendon, a filterexact motor with a force range) and a stiff, damped tendon (Euler and RK4),
a tumbling body and a tendon-driven point mass in a medium with density, viscosity and
wind (MuJoCo's inertia-box fluid model, fixed tendons), a damped double pendulum with armature and joint limits (Euler and RK4), a free box
and a free capsule dropped on the floor (Euler), a pile of two capsules and a sphere falling on
each other and the floor (capsule–capsule, sphere–capsule contacts), a claw pushing a cylinder on
two slides (capsule–cylinder, sphere–cylinder contacts, as Pusher's), and Gymnasium's ant.xml
and humanoid.xml (RK4, their own options) under a fixed open-loop control. The humanoid has
multi-hinge bodies, joint springs, frictionless (condim 1) contacts and capsule self-collisions;
its two fixed tendons carry no stiffness, damping or limit, so they exert nothing and are not
written.

Needs mujoco 4.0.0 and gymnasium 1.4.0 (for ant.xml and humanoid.xml), e.g. in a venv outside the repository:
    python3 -m venv ~/venvs/mujoco && ~/venvs/mujoco/bin/pip install mujoco==4.0.0 gymnasium==1.4.0
Run from the repository root: `~/venvs/mujoco/bin/python scripts/articulated_mujoco_fixtures.py`
(`--check` compares with the committed fixtures instead of writing).
"""
import argparse
import json
import math
import os
import sys

OUT = "crates/carl-articulated/tests/fixtures"

DOUBLE_PENDULUM = """
<mujoco model="double_pendulum">
  <option timestep="0.002" integrator="{integrator}" gravity="0 0 -9.81"/>
  <worldbody>
    <body name="upper" pos="0 0 1">
      <joint name="shoulder" type="hinge" axis="0 1 0" damping="{damping}" armature="0.01" limited="true" range="-100 100"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 -0.3" size="0.04" density="1000" contype="0" conaffinity="0"/>
      <body name="lower" pos="0.3 0 -0.3">
        <joint name="elbow" type="hinge" axis="0.2 1 0.1" damping="{damping}" armature="0.02" limited="true" range="-40 40"
               stiffness="{stiffness}" springref="10"/>
        <geom type="capsule" fromto="0 0 0 0 0.1 -0.35" size="0.03" density="1000" contype="0" conaffinity="0"/>
        <geom type="sphere" pos="0 0.1 -0.35" size="0.06" density="500" contype="0" conaffinity="0"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <motor joint="shoulder" gear="2" ctrllimited="true" ctrlrange="-1 1"/>
    <motor joint="elbow" gear="1" ctrllimited="true" ctrlrange="-1 1"/>
  </actuator>
</mujoco>
"""

DROP = """
<mujoco model="drop">
  <option timestep="0.002"/>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1" friction="0.8 0.005 0.0001"/>
    <body name="box" pos="0 0 0.5" euler="20 10 5">
      <freejoint/>
      <geom type="box" size="0.1 0.15 0.05" density="800"/>
    </body>
    <body name="capsule" pos="1 0 0.4" euler="0 80 0">
      <freejoint/>
      <geom type="capsule" size="0.05 0.2" density="600" margin="0.005"/>
    </body>
  </worldbody>
</mujoco>
"""


PILE = """
<mujoco model="pile">
  <option timestep="0.002"/>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1"/>
    <body name="bar" pos="0 0 0.3" euler="0 90 0">
      <freejoint/>
      <geom type="capsule" size="0.05 0.3" density="500"/>
    </body>
    <body name="cross" pos="0.05 0.02 0.5" euler="90 0 10">
      <freejoint/>
      <geom type="capsule" size="0.04 0.2" density="700"/>
    </body>
    <body name="ball" pos="-0.1 0.03 0.8">
      <freejoint/>
      <geom type="sphere" size="0.07" density="300"/>
    </body>
  </worldbody>
</mujoco>
"""

# MuJoCo's inertia-box fluid model (density, viscosity, wind) on a tumbling free body whose
# principal axes are not its frame's (two boxes), and a point mass on two slides driven through
# fixed tendons mixing both joints (dm_control's point_mass `hard` task), in the same medium.
FLUID = """
<mujoco model="fluid">
  <option timestep="0.002" density="1.3" viscosity="0.2" wind="1.5 -0.7 0.4"/>
  <worldbody>
    <body name="tumbler" pos="0 0 2" euler="10 20 30">
      <freejoint/>
      <geom type="box" size="0.3 0.1 0.05" density="300" contype="0" conaffinity="0"/>
      <geom type="box" pos="0.1 0.1 0" euler="0 0 40" size="0.1 0.2 0.04" density="600" contype="0" conaffinity="0"/>
    </body>
    <body name="pointmass" pos="0 0 0.01">
      <joint name="root_x" type="slide" axis="1 0 0" damping="1" limited="true" range="-0.29 0.29"/>
      <joint name="root_y" type="slide" axis="0 1 0" damping="1" limited="true" range="-0.29 0.29"/>
      <geom type="sphere" size="0.05" mass="0.3" contype="0" conaffinity="0"/>
    </body>
  </worldbody>
  <tendon>
    <fixed name="t1"><joint joint="root_x" coef="0.6"/><joint joint="root_y" coef="0.8"/></fixed>
    <fixed name="t2"><joint joint="root_x" coef="-0.28"/><joint joint="root_y" coef="0.96"/></fixed>
  </tendon>
  <actuator>
    <motor tendon="t1" gear="0.1" ctrllimited="true" ctrlrange="-1 1"/>
    <motor tendon="t2" gear="0.1" ctrllimited="true" ctrlrange="-1 1"/>
  </actuator>
</mujoco>
"""


# A cart on a rail with dry friction (MuJoCo's joint frictionloss) and a pole, RK4 and Euler.
RAIL = """
<mujoco model="rail">
  <option timestep="0.01" integrator="{integrator}" gravity="0 0 -9.81"/>
  <worldbody>
    <body name="cart">
      <joint name="slider" type="slide" axis="1 0 0" frictionloss="{frictionloss}" damping="0.05" limited="true"
             range="-1 1" margin="0.01"/>
      <geom type="capsule" fromto="-0.1 0 0 0.1 0 0" size="0.1" density="1000" contype="0" conaffinity="0"/>
      <body name="pole">
        <joint name="hinge" type="hinge" axis="0 1 0" frictionloss="0.02" damping="0.05"/>
        <geom type="capsule" fromto="0 0 0 0 0 0.6" size="0.045" density="1000" contype="0" conaffinity="0"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <motor joint="slider" gear="50" ctrllimited="true" ctrlrange="-1 1"/>
  </actuator>
</mujoco>
"""

# Gymnasium's MuJoCo robots whose fixtures check the planar roots (slide x, slide z, hinge y on
# one body), rails, RK4 and the control tasks' models.
GYM_ROBOTS = [("half_cheetah", "half_cheetah.xml", 300), ("hopper", "hopper.xml", 400),
              ("walker2d", "walker2d_v5.xml", 400), ("inverted_pendulum", "inverted_pendulum.xml", 100),
              ("inverted_double_pendulum", "inverted_double_pendulum.xml", 100), ("reacher", "reacher.xml", 200)]


# A claw (two capsules and a sphere on x, y, z slides and a tilt hinge) pushing a cylinder that
# rides on two horizontal slides, as Pusher's wrist and object: frictionless (condim 1)
# capsule–cylinder and sphere–cylinder contacts.
PUSH = """
<mujoco model="push">
  <option timestep="0.01" gravity="0 0 -9.81"/>
  <default>
    <joint armature="0.04" damping="0.5"/>
    <geom margin="0.002" condim="1" density="300"/>
  </default>
  <worldbody>
    <geom name="table" type="plane" size="1 1 0.1" pos="0 0 -0.05" contype="0" conaffinity="0"/>
    <body name="claw" pos="0 0 0.04">
      <joint name="cx" type="slide" axis="1 0 0"/>
      <joint name="cy" type="slide" axis="0 1 0"/>
      <joint name="cz" type="slide" axis="0 0 1" stiffness="40"/>
      <joint name="tilt" type="hinge" axis="0 1 0" stiffness="2"/>
      <geom type="capsule" fromto="0 -0.1 0 0 0.1 0" size="0.02" contype="1" conaffinity="1"/>
      <geom type="capsule" fromto="0 -0.1 0 0.1 -0.1 0" size="0.02" contype="1" conaffinity="1"/>
      <geom type="sphere" pos="0.1 0.1 0.03" size="0.025" contype="1" conaffinity="1"/>
    </body>
    <body name="object" pos="0.2 0.03 0">
      <joint name="oy" type="slide" axis="0 1 0"/>
      <joint name="ox" type="slide" axis="1 0 0"/>
      <geom type="cylinder" size="0.05 0.05" contype="1" conaffinity="0"/>
    </body>
  </worldbody>
  <actuator>
    <motor joint="cx" ctrllimited="true" ctrlrange="-1 1"/>
    <motor joint="cy" ctrllimited="true" ctrlrange="-1 1"/>
    <motor joint="cz" ctrllimited="true" ctrlrange="-1 1"/>
    <motor joint="tilt" gear="0.2" ctrllimited="true" ctrlrange="-1 1"/>
  </actuator>
</mujoco>
"""

# MuJoCo's general actuators and tendon springs: a position servo on a hinge, a filtered
# (`dyntype="filter"`) servo with affine bias on a fixed tendon (quadruped.xml's form), a
# `filterexact` motor with a force range on a slide, and a stiff, damped tendon with a spring
# dead band coupling two hinges (fish.xml's `fins_sym`), Euler and RK4, no gravity, no contacts.
ACTUATORS = """
<mujoco model="actuators">
  <option timestep="0.004" integrator="{integrator}" gravity="0 0 -3"/>
  <default>
    <joint damping="0.01"/>
    <geom contype="0" conaffinity="0" density="800"/>
  </default>
  <worldbody>
    <body name="base">
      <joint name="slider" type="slide" axis="1 0 0"/>
      <geom type="box" size="0.1 0.05 0.05"/>
      <body name="arm" pos="0.1 0 0">
        <joint name="shoulder" type="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
        <body name="fore" pos="0.3 0 0">
          <joint name="elbow" type="hinge" axis="0 1 0.3" springref="5"/>
          <geom type="capsule" fromto="0 0 0 0.25 0 0" size="0.025"/>
        </body>
      </body>
      <body name="fin" pos="-0.1 0 0">
        <joint name="fin" type="hinge" axis="1 0 0"/>
        <geom type="capsule" fromto="0 0 0 0 0.2 0" size="0.02"/>
      </body>
    </body>
  </worldbody>
  <tendon>
    <fixed name="lift"><joint joint="shoulder" coef="0.5"/><joint joint="elbow" coef="-0.7"/></fixed>
    <fixed name="stiff" stiffness="3" damping="0.02" springlength="-0.1 0.05">
      <joint joint="elbow" coef="0.6"/><joint joint="fin" coef="0.8"/>
    </fixed>
  </tendon>
  <actuator>
    <position name="servo" joint="shoulder" kp="4" kv="0.1" ctrllimited="true" ctrlrange="-1 1"/>
    <general name="filtered" tendon="lift" gear="1.5" gainprm="3" biastype="affine" biasprm="0.1 -3 -0.2"
             dyntype="filter" dynprm="0.1" ctrllimited="true" ctrlrange="-1 1"/>
    <general name="exact" joint="slider" gear="2" dyntype="filterexact" dynprm="0.05" forcelimited="true"
             forcerange="-0.4 0.5" ctrllimited="true" ctrlrange="-1 1"/>
    <position name="finservo" joint="fin" kp="0.5" ctrllimited="true" ctrlrange="-1 1"/>
  </actuator>
</mujoco>
"""


def gym_xml(name):
    import gymnasium
    return os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets", name)


def inert_tendons(m):
    """True when the model's tendons exert no force (no stiffness, damping or limit)."""
    return all(m.tendon_stiffness[t] == 0 and m.tendon_damping[t] == 0 and not m.tendon_limited[t]
               for t in range(m.ntendon))


def r(x):
    """Round to 12 significant digits (fixtures stay small and diffable)."""
    if hasattr(x, "tolist"):
        x = x.tolist()
    if isinstance(x, (list, tuple)):
        return [r(v) for v in x]
    x = float(x)
    return 0.0 if x == 0 else float(f"{x:.12g}")


def model_json(mujoco, m):
    shape = {int(mujoco.mjtGeom.mjGEOM_PLANE): "plane", int(mujoco.mjtGeom.mjGEOM_SPHERE): "sphere",
             int(mujoco.mjtGeom.mjGEOM_CAPSULE): "capsule", int(mujoco.mjtGeom.mjGEOM_BOX): "box",
             int(mujoco.mjtGeom.mjGEOM_CYLINDER): "cylinder", int(mujoco.mjtGeom.mjGEOM_ELLIPSOID): "ellipsoid"}
    kind = {int(mujoco.mjtJoint.mjJNT_FREE): "free", int(mujoco.mjtJoint.mjJNT_HINGE): "hinge",
            int(mujoco.mjtJoint.mjJNT_SLIDE): "slide"}
    integ = {int(mujoco.mjtIntegrator.mjINT_EULER): "euler", int(mujoco.mjtIntegrator.mjINT_RK4): "rk4"}
    assert m.opt.cone == mujoco.mjtCone.mjCONE_PYRAMIDAL
    bodies = [dict(parent=int(m.body_parentid[i]), pos=r(m.body_pos[i]), quat=r(m.body_quat[i]),
                   mass=r(m.body_mass[i]), ipos=r(m.body_ipos[i]), iquat=r(m.body_iquat[i]),
                   inertia=r(m.body_inertia[i])) for i in range(m.nbody)]
    joints = []
    for j in range(m.njnt):
        d = m.jnt_dofadr[j]
        joints.append(dict(kind=kind[int(m.jnt_type[j])], body=int(m.jnt_bodyid[j]), pos=r(m.jnt_pos[j]),
                           axis=r(m.jnt_axis[j]), armature=r(m.dof_armature[d]), damping=r(m.dof_damping[d]),
                           stiffness=r(m.jnt_stiffness[j]),
                           springref=r(m.qpos_spring[m.jnt_qposadr[j]]) if m.jnt_type[j] > 1 else 0.0,
                           qpos0=r(m.qpos0[m.jnt_qposadr[j]]) if m.jnt_type[j] > 1 else 0.0,
                           range=r(m.jnt_range[j]) if m.jnt_limited[j] else None, margin=r(m.jnt_margin[j]),
                           solref=r(m.jnt_solref[j]), solimp=r(m.jnt_solimp[j])))
        if m.dof_frictionloss[d] > 0:
            joints[-1].update(frictionloss=r(m.dof_frictionloss[d]), solreffriction=r(m.dof_solref[d]),
                              solimpfriction=r(m.dof_solimp[d]))
    # Geoms of shapes the engine lacks that collide with nothing (Reacher's cylinder) are left out.
    geoms = [dict(body=int(m.geom_bodyid[g]), shape=shape[int(m.geom_type[g])], size=r(m.geom_size[g]),
                  pos=r(m.geom_pos[g]), quat=r(m.geom_quat[g]), contype=int(m.geom_contype[g]),
                  conaffinity=int(m.geom_conaffinity[g]), condim=int(m.geom_condim[g]),
                  friction=r(m.geom_friction[g]), solmix=r(m.geom_solmix[g]), solref=r(m.geom_solref[g]),
                  solimp=r(m.geom_solimp[g]), margin=r(m.geom_margin[g]), gap=r(m.geom_gap[g]))
             for g in range(m.ngeom)
             if int(m.geom_type[g]) in shape or m.geom_contype[g] or m.geom_conaffinity[g]]
    tendon_trn = int(mujoco.mjtTrn.mjTRN_TENDON)
    actuators = []
    for a in range(m.nu):
        act = dict(joint=int(m.actuator_trnid[a][0]), gear=r(m.actuator_gear[a][0]),
                   ctrlrange=r(m.actuator_ctrlrange[a]) if m.actuator_ctrllimited[a] else None)
        if m.actuator_trntype[a] == tendon_trn:
            # the engine's Actuator names a joint even when a tendon drives: its tendon's first
            t = int(m.actuator_trnid[a][0])
            act.update(joint=int(m.wrap_objid[m.tendon_adr[t]]), tendon=t)
        actuators.append(act)
    opt = dict(timestep=r(m.opt.timestep), gravity=r(m.opt.gravity), integrator=integ[int(m.opt.integrator)],
               impratio=r(m.opt.impratio), viscosity=r(m.opt.viscosity))
    names = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j) for j in range(m.njnt)]
    out = dict(opt=opt, joint_names=names, bodies=bodies, joints=joints, geoms=geoms, actuators=actuators,
               body_invweight0=r(m.body_invweight0), dof_invweight0=r(m.dof_invweight0), qpos0=r(m.qpos0))
    if m.opt.density > 0 or any(m.opt.wind):
        opt.update(density=r(m.opt.density), wind=r(m.opt.wind))
    for a, act in enumerate(actuators):
        gaintype, biastype = int(m.actuator_gaintype[a]), int(m.actuator_biastype[a])
        general = (gaintype != int(mujoco.mjtGain.mjGAIN_FIXED) or m.actuator_gainprm[a][0] != 1
                   or biastype != int(mujoco.mjtBias.mjBIAS_NONE) or m.actuator_dyntype[a] != 0
                   or m.actuator_forcelimited[a] or m.actuator_actlimited[a])
        if not general:
            continue
        assert gaintype == int(mujoco.mjtGain.mjGAIN_FIXED), "gain type must be fixed"
        assert biastype in (int(mujoco.mjtBias.mjBIAS_NONE), int(mujoco.mjtBias.mjBIAS_AFFINE)), \
            f"bias type {biastype} must be none or affine"
        dyn = {int(mujoco.mjtDyn.mjDYN_NONE): "none", int(mujoco.mjtDyn.mjDYN_FILTER): "filter",
               int(mujoco.mjtDyn.mjDYN_FILTEREXACT): "filterexact"}[int(m.actuator_dyntype[a])]
        act.update(gain=r(m.actuator_gainprm[a][0]), bias=r(m.actuator_biasprm[a][:3]), dyntype=dyn)
        if dyn != "none":
            act.update(tau=r(m.actuator_dynprm[a][0]))
        if m.actuator_forcelimited[a]:
            act.update(forcerange=r(m.actuator_forcerange[a]))
        if m.actuator_actlimited[a]:
            act.update(actrange=r(m.actuator_actrange[a]))
    passive = any(m.tendon_stiffness[t] or m.tendon_damping[t] for t in range(m.ntendon))
    if passive:
        out["tendon_passive"] = [dict(stiffness=r(m.tendon_stiffness[t]), damping=r(m.tendon_damping[t]),
                                      lengthspring=r(m.tendon_lengthspring[t])) for t in range(m.ntendon)]
    if passive or any(m.actuator_trntype[a] == tendon_trn for a in range(m.nu)):
        out["tendons"] = [[[int(m.wrap_objid[w]), r(m.wrap_prm[w])]
                           for w in range(m.tendon_adr[t], m.tendon_adr[t] + m.tendon_num[t])]
                          for t in range(m.ntendon)]
    return out


def control(t, nu):
    """The fixed open-loop control: phase-shifted sines, clipped by the model's ctrlrange."""
    return [math.sin(2.0 * math.pi * 1.3 * t + 0.7 * a) * (0.6 + 0.1 * a) for a in range(nu)]


def run(mujoco, m, steps, every, qvel0=None):
    d = mujoco.MjData(m)
    if qvel0 is not None:
        d.qvel[:] = qvel0
    d.ctrl[:] = control(0.0, m.nu)
    mujoco.mj_forward(m, d)
    import numpy as np
    mm = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, mm)
    first = dict(qM=r(mm.tolist()), qfrc_bias=r(d.qfrc_bias), qfrc_passive=r(d.qfrc_passive),
                 qacc_smooth=r(d.qacc_smooth), qacc=r(d.qacc), ncon=int(d.ncon), nefc=int(d.nefc))
    def point(s):
        p = dict(step=s, time=r(d.time), qpos=r(d.qpos), qvel=r(d.qvel))
        if m.na:
            p.update(act=r(d.act))
        return p
    if m.na:
        first.update(act_dot=r(d.act_dot), actuator_force=r(d.actuator_force), qfrc_actuator=r(d.qfrc_actuator))
    traj = [point(0)]
    for s in range(1, steps + 1):
        d.ctrl[:] = control(d.time, m.nu)
        mujoco.mj_step(m, d)
        if s % every == 0:
            traj.append(point(s))
    return dict(qvel0=r(list(qvel0)) if qvel0 is not None else None, first=first, trajectory=traj)


def fixtures(only=None):
    """The fixtures by name (`only`: just these)."""
    import mujoco
    out = {}

    def want(name):
        return not only or name in only

    for name, integ, damping, stiffness in [("double_pendulum_euler", "Euler", 0.05, 0.3),
                                            ("double_pendulum_rk4", "RK4", 0.0, 0.0)]:
        if not want(name):
            continue
        m = mujoco.MjModel.from_xml_string(DOUBLE_PENDULUM.format(integrator=integ, damping=damping,
                                                                  stiffness=stiffness))
        out[name] = dict(model=model_json(mujoco, m), **run(mujoco, m, 1000, 20, qvel0=[3.0, -2.0]))
    if want("drop"):
        m = mujoco.MjModel.from_xml_string(DROP)
        out["drop"] = dict(model=model_json(mujoco, m),
                           **run(mujoco, m, 600, 10, qvel0=[0.5, 0, 0, 1.0, -2.0, 0.5, 0, 0.3, 0, 0, 0, 0]))
    if want("pile"):
        m = mujoco.MjModel.from_xml_string(PILE)
        out["pile"] = dict(model=model_json(mujoco, m), **run(mujoco, m, 500, 10))
    if want("fluid"):
        m = mujoco.MjModel.from_xml_string(FLUID)
        out["fluid"] = dict(model=model_json(mujoco, m),
                            **run(mujoco, m, 500, 10, qvel0=[0.5, -1.0, 2.0, 3.0, -2.0, 1.0, 0.4, -0.2]))
    if want("push"):
        m = mujoco.MjModel.from_xml_string(PUSH)
        out["push"] = dict(model=model_json(mujoco, m), **run(mujoco, m, 300, 1, qvel0=[0.6, 0.05, 0, 0, 0, 0]))
    if want("ant"):
        m = mujoco.MjModel.from_xml_path(gym_xml("ant.xml"))
        out["ant"] = dict(model=model_json(mujoco, m), **run(mujoco, m, 300, 5))
    if want("humanoid"):
        m = mujoco.MjModel.from_xml_path(gym_xml("humanoid.xml"))
        assert inert_tendons(m), "humanoid.xml's tendons act"
        out["humanoid"] = dict(model=model_json(mujoco, m), **run(mujoco, m, 400, 5))
    for integ in ("RK4", "Euler"):
        if not want(f"rail_{integ.lower()}"):
            continue
        m = mujoco.MjModel.from_xml_string(RAIL.format(integrator=integ, frictionloss=3.0))
        out[f"rail_{integ.lower()}"] = dict(model=model_json(mujoco, m), **run(mujoco, m, 300, 5, qvel0=[0.8, -1.0]))
    for integ in ("Euler", "RK4"):
        if not want(f"actuators_{integ.lower()}"):
            continue
        m = mujoco.MjModel.from_xml_string(ACTUATORS.format(integrator=integ))
        out[f"actuators_{integ.lower()}"] = dict(model=model_json(mujoco, m),
                                                 **run(mujoco, m, 500, 5, qvel0=[0.3, -1.0, 2.0, 1.5]))
    for name, xml, steps in GYM_ROBOTS:
        if not want(name):
            continue
        m = mujoco.MjModel.from_xml_path(gym_xml(xml))
        out[name] = dict(model=model_json(mujoco, m), **run(mujoco, m, steps, 5))
    return out


def write_or_check(path, text, check):
    """Write `text` to `path`, or with `check` compare it with the file; False if it differs."""
    if check:
        with open(path) as f:
            if f.read() != text:
                print(f"{path}: differs")
                return False
        return True
    with open(path, "w") as f:
        f.write(text)
    print(f"wrote {path} ({len(text)} bytes)")
    return True


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true", help="compare with the committed fixtures")
    ap.add_argument("--only", nargs="*", help="only these fixtures (e.g. actuators_euler)")
    args = ap.parse_args()
    import mujoco
    if mujoco.__version__ != "4.0.0":
        sys.exit(f"needs mujoco 4.0.0, found {mujoco.__version__}")
    bad = 0
    for name, data in fixtures(args.only).items():
        path = os.path.join(OUT, f"mujoco_{name}.json")
        text = json.dumps(dict(source="MuJoCo 4.0.0 via scripts/articulated_mujoco_fixtures.py", **data),
                          separators=(",", ":")) + "\n"
        bad += not write_or_check(path, text, args.check)
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
