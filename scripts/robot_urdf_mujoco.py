#!/usr/bin/env python3
"""Convert Gymnasium's MuJoCo v5 XML of a robot (Hopper, Walker2d, Ant, Humanoid: `convert`; InvertedPendulum,
InvertedDoublePendulum, Reacher: `convert_fixed`; Pusher: `convert_arm`) into
crates/carl-envs-brax/robots/<name>.urdf and <name>.actuators.json.

MuJoCo itself compiles the XML (`mujoco.MjModel.from_xml_path`), so every number is MuJoCo's
own: body masses and inertias (`inertiafromgeom`, density 1000), centres of mass, joint anchors,
axes and ranges, per-joint damping and armature, capsule sizes and poses, actuator gears and
control ranges, the time step and the contact parameters (MuJoCo's mix of the floor's and the
robot's `solref`, `solimp`, `margin`, `friction`: the per-pair maximum). The planar root (the
XML's `rootx`, `rootz`, `rooty` joints on the torso) becomes two prismatic joints on massless
carrier links and a continuous pitch hinge, as HalfCheetah's; each link's frame sits at the
anchor of the joint that moves it (URDF's convention), MuJoCo's body frame shifted accordingly.
`rootz` keeps MuJoCo's reference position: its coordinate is the torso's height (qpos0 1.25).

A robot with a free root (Ant, Humanoid) keeps MuJoCo's bodies one for one: the free body is
the URDF's root link (the side file's `"root": "free"`), bodies without joints are links on
fixed joints (the articulated engine welds them, as MuJoCo does), unnamed bodies are named after
their joint, a body's rotation becomes its joint origin's `rpy`. A body with several hinges at
one anchor (Humanoid's abdomen, hips, shoulders) becomes a chain of massless, shapeless carrier
links named `<joint>_link` joined at the anchor, which the articulated engine folds back into
one body with the hinges in MuJoCo's order. It runs on the articulated engine (`"engine":
"articulated"`) with the XML's integrator; its contact margin is the robot–floor pair's (MuJoCo
adds the two geoms' margins; `floor_margin` is the floor's share). The features the robot's spec
keeps (damping, joint-limit stiffness, gear, friction, gravity, torso mass) are left to the
context: the side file does not fix them (the spec's `mujoco_v5` instance set has the XML's).
Where the XML's joints differ in damping (Humanoid), the side file keeps the pattern and
`joint_angular_damping` scales it (`damping_reference` is the XML's largest damping); where its
motors differ in gear, the side file keeps the gears (Humanoid has no `actuator_strength`
feature); joint springs, condim and the soft-limit parameters are the XML's.

Run from the repository root with Gymnasium 1.4 and mujoco installed (e.g. in a venv outside the
repository): `python scripts/robot_urdf_mujoco.py` (all robots) or `... hopper`; the output is
committed, the build embeds it. `--check` compares instead of writing.
"""
import argparse
import json
import math
import os
import sys

ROBOTS_DIR = "crates/carl-envs-brax/robots"

# name -> (Gymnasium XML file, Gymnasium frame_skip, Gymnasium id)
ROBOTS = {
    "hopper": ("hopper.xml", 4, "Hopper-v5"),
    "walker2d": ("walker2d_v5.xml", 4, "Walker2d-v5"),
    "ant": ("ant.xml", 5, "Ant-v5"),
    "humanoid": ("humanoid.xml", 5, "Humanoid-v5"),
    "humanoid_standup": ("humanoidstandup.xml", 5, "HumanoidStandup-v5"),
}
# Free robots whose joint dampings are the XML's, not scaled by a joint_angular_damping feature
# (their specs have none), and whose mass_<link> features are Brax's links (with the bodies welded
# to them, `welded_masses`): HumanoidStandup (the humanoid lying on its back: body frames, the feet
# and the left hip's range differ from humanoid.xml, so it is a robot of its own).
ABSOLUTE_DAMPING = {"humanoid_standup"}

# Arms welded to the world on the articulated engine (3-D, `convert_arm`): name -> (XML file,
# frame_skip, Gymnasium id, options). `skip`: bodies that are task state (Pusher's goal, which
# no force moves); `contact`: the bodies whose geoms collide in the XML (contype/conaffinity),
# `ground`: those of them that touch the table (the XML's plane, the floor here at its height).
ARMS = {
    "pusher": ("pusher_v5.xml", 5, "Pusher-v5", {"skip": ["goal"], "contact": ["r_wrist_roll_link", "object"],
                                                 "ground": ["r_wrist_roll_link"]}),
}
ROOT_JOINTS = ["rootx", "rootz", "rooty"]

# Robots welded to the world (a cart on its rail, an arm on its table): name -> (XML file,
# frame_skip, Gymnasium id, options). `plane` "xy": the robot moves in MuJoCo's horizontal x-y
# plane (hinges about z); the URDF is MuJoCo's model turned by +90 deg about x (MuJoCo (x, y, z)
# -> URDF (x, -z, y)), so that it moves in the x-z plane as the other planar robots (the task and
# its renders read x and z), and the side file says that gravity is normal to that plane. `skip`: bodies that are task state, not robot (Reacher's
# target, which never moves: no force acts on its slides). `fuse`: joint-less bodies welded into
# their parent (the parent's mass and inertia include them; their origin becomes a site).
# `rail`: slides whose dry friction is the context's friction times the weight they carry;
# `bounce`: joints whose limits restitute with the context's elasticity.
FIXED = {
    "inverted_pendulum": (
        "inverted_pendulum.xml",
        2,
        "InvertedPendulum-v5",
        {"plane": "xz", "skip": [], "fuse": [], "rail": ["slider"], "bounce": ["slider"]},
    ),
    "inverted_double_pendulum": (
        "inverted_double_pendulum.xml",
        5,
        "InvertedDoublePendulum-v5",
        {"plane": "xz", "skip": [], "fuse": [], "rail": ["slider"], "bounce": ["slider"]},
    ),
    "reacher": (
        "reacher.xml",
        2,
        "Reacher-v5",
        {"plane": "xy", "skip": ["target"], "fuse": ["fingertip"], "rail": [], "bounce": ["joint1"]},
    ),
}


def fmt(x):
    s = f"{x:.9g}"
    return "0" if s in ("-0", "0") else s


def vec(v):
    return " ".join(fmt(float(x)) for x in v)


def quat_mat(q):
    w, x, y, z = (float(c) for c in q)
    return [
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ]


def capsule_rpy(d):
    """rpy turning the URDF capsule's z axis onto unit direction d."""
    return (0.0, math.acos(max(-1.0, min(1.0, d[2]))), math.atan2(d[1], d[0]))


def convert(name):
    import gymnasium
    import mujoco

    xml_file, frame_skip, gym_id = ROBOTS[name]
    path = os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets", xml_file)
    m = mujoco.MjModel.from_xml_path(path)
    floor = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, "floor")
    assert floor >= 0, "the model needs a geom named floor"

    def jname(j):
        return mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j)

    def bname(b):
        n = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b)
        if n:
            return n
        js = [j for j in range(m.njnt) if m.jnt_bodyid[j] == b]
        assert len(js) == 1, f"unnamed body {b} needs one joint to be named after"
        return f"{jname(js[0])}_link"

    free = [j for j in range(m.njnt) if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE]
    if free:
        return convert_free(name, m, mujoco, floor, jname, bname, free[0])

    # Each body's joints and the anchor of the joint that moves it (its URDF frame origin).
    anchor = {0: [0.0, 0.0, 0.0]}
    joints_of = {}
    for b in range(1, m.nbody):
        assert list(m.body_quat[b]) == [1, 0, 0, 0], f"body {bname(b)} is rotated"
        js = [j for j in range(m.njnt) if m.jnt_bodyid[j] == b]
        joints_of[b] = js
        hinges = [j for j in js if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE]
        assert len(hinges) == 1, f"body {bname(b)} needs one hinge"
        anchor[b] = [float(x) for x in m.jnt_pos[hinges[0]]]

    links, joints = [], []

    def link_xml(lname, mass, com, inertia, shapes):
        out = [f'  <link name="{lname}">', "    <inertial>"]
        out.append(f'      <origin xyz="{vec(com)}" rpy="0 0 0"/>')
        out.append(f'      <mass value="{fmt(mass)}"/>')
        I = inertia
        out.append(
            f'      <inertia ixx="{fmt(I[0][0])}" ixy="{fmt(I[0][1])}" ixz="{fmt(I[0][2])}" '
            f'iyy="{fmt(I[1][1])}" iyz="{fmt(I[1][2])}" izz="{fmt(I[2][2])}"/>'
        )
        out.append("    </inertial>")
        for c, rpy, r, length in shapes:
            out.append("    <collision>")
            out.append(f'      <origin xyz="{vec(c)}" rpy="{vec(rpy)}"/>')
            out.append(f'      <geometry><capsule radius="{fmt(r)}" length="{fmt(length)}"/></geometry>')
            out.append("    </collision>")
        out.append("  </link>")
        links.append("\n".join(out))

    def joint_xml(jn, kind, parent, child, xyz, axis, limit=None):
        lim = ""
        if limit is not None:
            lim = f'\n    <limit lower="{fmt(limit[0])}" upper="{fmt(limit[1])}" effort="0" velocity="0"/>'
        joints.append(
            f'  <joint name="{jn}" type="{kind}">\n    <parent link="{parent}"/>\n    <child link="{child}"/>\n'
            f'    <origin xyz="{vec(xyz)}" rpy="0 0 0"/>\n    <axis xyz="{vec(axis)}"/>{lim}\n  </joint>'
        )

    eye = [[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]]
    link_xml("world", 1.0, [0, 0, 0], eye, [])
    tiny = [[1e-6, 0, 0], [0, 1e-6, 0], [0, 0, 1e-6]]
    link_xml("slider_x", 1e-4, [0, 0, 0], tiny, [])
    link_xml("slider_z", 1e-4, [0, 0, 0], tiny, [])

    for b in range(1, m.nbody):
        a = anchor[b]
        R = quat_mat(m.body_iquat[b])
        d = m.body_inertia[b]
        inertia = [[sum(R[i][k] * d[k] * R[j][k] for k in range(3)) for j in range(3)] for i in range(3)]
        com = [float(m.body_ipos[b][i]) - a[i] for i in range(3)]
        shapes = []
        for g in range(m.ngeom):
            if m.geom_bodyid[g] != b:
                continue
            assert m.geom_type[g] == mujoco.mjtGeom.mjGEOM_CAPSULE, "capsules only"
            G = quat_mat(m.geom_quat[g])
            axis = [G[0][2], G[1][2], G[2][2]]
            c = [float(m.geom_pos[g][i]) - a[i] for i in range(3)]
            shapes.append((c, capsule_rpy(axis), float(m.geom_size[g][0]), 2 * float(m.geom_size[g][1])))
        link_xml(bname(b), float(m.body_mass[b]), com, inertia, shapes)

        parent = int(m.body_parentid[b])
        for j in joints_of[b]:
            jn = jname(j)
            if parent == 0:
                # The planar root: slides on carrier links, then the pitch hinge at the torso.
                assert jn in ROOT_JOINTS, f"root joint {jn}"
                continue
            pa = anchor[parent]
            xyz = [float(m.body_pos[b][i]) + a[i] - pa[i] for i in range(3)]
            lim = [float(x) for x in m.jnt_range[j]] if m.jnt_limited[j] else None
            joint_xml(jn, "revolute" if lim else "continuous", bname(parent), bname(b), xyz, m.jnt_axis[j], lim)
        if parent == 0:
            torso = bname(b)
            joint_xml("rootx", "prismatic", "world", "slider_x", [0, 0, 0], [1, 0, 0], (-1000, 1000))
            joint_xml("rootz", "prismatic", "slider_x", "slider_z", [0, 0, 0], [0, 0, 1], (-1000, 1000))
            joint_xml("rooty", "continuous", "slider_z", torso, [0, 0, 0], [0, 1, 0])

    # Joint order of the URDF: the root's, then the robot's in MuJoCo order (= qpos order).
    order = {jname(j): j for j in range(m.njnt)}
    qpos_names = [jname(j) for j in range(m.njnt)]
    root_block = [s for s in joints if s.split('"')[1] in ROOT_JOINTS]
    rest = [s for s in joints if s.split('"')[1] not in ROOT_JOINTS]
    rest.sort(key=lambda s: order[s.split('"')[1]])
    joints = root_block + rest
    assert [s.split('"')[1] for s in joints] == qpos_names, qpos_names

    # Contacts: MuJoCo mixes the pair's solref/solimp (equal solmix: the mean), adds the two
    # margins (the floor's share is `floor_margin`) and takes the larger friction and condim.
    def mix(a, b):
        return [(float(x) + float(y)) / 2 for x, y in zip(a, b)]

    robot_geoms = [g for g in range(m.ngeom) if g != floor]
    solrefs = {tuple(mix(m.geom_solref[g], m.geom_solref[floor])) for g in robot_geoms}
    solimps = {tuple(mix(m.geom_solimp[g], m.geom_solimp[floor])) for g in robot_geoms}
    margins = {float(m.geom_margin[g]) + float(m.geom_margin[floor]) for g in robot_geoms}
    condims = {int(m.geom_condim[g]) for g in robot_geoms}
    assert len(solrefs) == len(solimps) == len(margins) == len(condims) == 1, "one contact model for all geoms"
    # Robot geoms collide with each other where contype and conaffinity allow it (Hopper; the
    # engine applies MuJoCo's parent-child filter).
    self_collide = any(m.geom_contype[a] & m.geom_conaffinity[b] for a in robot_geoms for b in robot_geoms if a != b)
    frictions = {
        bname(m.geom_bodyid[g]): max(float(m.geom_friction[g][0]), float(m.geom_friction[floor][0]))
        for g in robot_geoms
    }
    lim_j = [j for j in range(m.njnt) if m.jnt_limited[j]]
    assert len({tuple(m.jnt_solref[j]) for j in lim_j}) == 1 and len({tuple(m.jnt_solimp[j]) for j in lim_j}) == 1

    acts = []
    for k in range(m.nu):
        acts.append({"joint": jname(int(m.actuator_trnid[k][0])), "gear": float(m.actuator_gear[k][0])})
    ranges = {tuple(float(x) for x in r) for r in m.actuator_ctrlrange}
    assert len(ranges) == 1
    robot_joints = [jname(j) for j in range(m.njnt) if jname(j) not in ROOT_JOINTS]
    dof = lambda jn: int(m.jnt_dofadr[order[jn]])
    rootz = order["rootz"]
    integrator = {0: "Euler", 1: "RK4", 2: "implicit", 3: "implicitfast"}[int(m.opt.integrator)]
    side = {
        "robot": name,
        "source": (
            f"Gymnasium {gym_id} ({xml_file}), compiled by MuJoCo {mujoco.__version__} and converted by "
            f"scripts/robot_urdf_mujoco.py: masses, inertias, joint anchors, axes, ranges, damping and armature, "
            f"capsules, gears, control range, time step ({float(m.opt.timestep)} s) and integrator (the XML's "
            f"{integrator}), frame_skip {frame_skip} (Gymnasium's), contact solref/solimp/margin/condim as MuJoCo "
            f"mixes the floor's and the robot's{', self-collisions' if self_collide else ''}; contact friction per body "
            f"(MuJoCo's pair maximum) {json.dumps(frictions)} is one context feature here (friction). "
            f"rootz keeps the XML's ref: its coordinate is the torso height."
        ),
        "engine": "articulated",
        "integrator": "rk4" if integrator == "RK4" else "euler",
        "timestep": float(m.opt.timestep),
        "frame_skip": frame_skip,
        "solver_iterations": 1,
        "root": "fixed",
        "root_joints": ROOT_JOINTS,
        "torso_link": bname(1),
        "root_height": float(m.qpos0[m.jnt_qposadr[rootz]]),
        "initial_joints": [{"joint": "rootz", "value": float(m.qpos0[m.jnt_qposadr[rootz]])}],
        "ctrl_range": list(ranges.pop()),
        "strength_reference": 1.0,
        "actuators": acts,
        "joint_armatures": [{"joint": jn, "armature": float(m.dof_armature[dof(jn)])} for jn in robot_joints],
        "joint_dampings": [{"joint": jn, "damping": float(m.dof_damping[dof(jn)])} for jn in robot_joints],
        "contact_model": {
            "solref": list(solrefs.pop()),
            "solimp": list(solimps.pop()),
            "margin": margins.pop(),
        },
        "floor_margin": float(m.geom_margin[floor]),
        "limit_model": {
            "solref": [float(x) for x in m.jnt_solref[lim_j[0]]],
            "solimp": [float(x) for x in m.jnt_solimp[lim_j[0]]],
            "margin": float(m.jnt_margin[lim_j[0]]),
        },
        "limit_reference_inertia": 1.0,
        "limit_damping_ratio": 1.0,
        "restitution": 0.0,
        "self_collisions": bool(self_collide),
        "max_speed": 1000.0,
    }
    if condims != {3}:
        side["contact_condim"] = condims.pop()
    doc = (
        f"carl-spec robot description, generated by scripts/robot_urdf_mujoco.py from Gymnasium {gym_id}'s "
        f"{xml_file} as compiled by MuJoCo {mujoco.__version__}: links are the XML's bodies (masses and inertias "
        f"from its geoms at density 1000), each link frame at the anchor of its joint; a planar root of two "
        f"slides (x, z) and a pitch hinge on massless carrier links."
    )
    urdf = (
        f'<?xml version="1.0"?>\n<!-- {doc} -->\n<robot name="{name}">\n'
        + "\n".join(links)
        + "\n"
        + "\n".join(joints)
        + "\n</robot>\n"
    )
    return urdf, json.dumps(side, indent=2) + "\n"


def convert_fixed(name):
    """A robot whose first body hangs from the world by its joints (no planar root)."""
    import gymnasium
    import mujoco

    xml_file, frame_skip, gym_id, opt = FIXED[name]
    path = os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets", xml_file)
    m = mujoco.MjModel.from_xml_path(path)
    xy = opt["plane"] == "xy"
    # MuJoCo (x, y, z) -> URDF coordinates.
    P = [[1.0, 0, 0], [0, 0, -1.0], [0, 1.0, 0]] if xy else [[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]]

    def tr(v):
        return [sum(P[i][k] * float(v[k]) for k in range(3)) for i in range(3)]

    def tr_mat(A):
        return [[sum(P[i][a] * A[a][b] * P[j][b] for a in range(3) for b in range(3)) for j in range(3)] for i in range(3)]

    def jname(j):
        return mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j)

    def bname(b):
        return mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b)

    def flat(v):
        # The planar model lies in its plane: the offset along the hinge axes (Reacher's arm
        # 1 cm above its table) moves nothing and is dropped.
        return [float(v[0]), 0.0 if xy else float(v[1]), float(v[2])] if not xy else [float(v[0]), float(v[1]), 0.0]

    bodies = [b for b in range(1, m.nbody) if bname(b) not in opt["skip"] and bname(b) not in opt["fuse"]]
    joints_of = {b: [j for j in range(m.njnt) if m.jnt_bodyid[j] == b] for b in bodies}
    anchor = {0: [0.0, 0.0, 0.0]}
    for b in bodies:
        assert list(m.body_quat[b]) == [1, 0, 0, 0], f"body {bname(b)} is rotated"
        assert len(joints_of[b]) == 1, f"body {bname(b)} needs one joint"
        anchor[b] = flat(m.jnt_pos[joints_of[b][0]])
    links, joints, sites = [], [], []

    def link_xml(lname, mass, com, inertia, shapes):
        out = [f'  <link name="{lname}">', "    <inertial>"]
        out.append(f'      <origin xyz="{vec(tr(com))}" rpy="0 0 0"/>')
        out.append(f'      <mass value="{fmt(mass)}"/>')
        I = tr_mat(inertia)
        out.append(
            f'      <inertia ixx="{fmt(I[0][0])}" ixy="{fmt(I[0][1])}" ixz="{fmt(I[0][2])}" '
            f'iyy="{fmt(I[1][1])}" iyz="{fmt(I[1][2])}" izz="{fmt(I[2][2])}"/>'
        )
        out.append("    </inertial>")
        for c, axis, r, length in shapes:
            out.append("    <collision>")
            rpy = capsule_rpy(tr(axis)) if length > 0 else (0.0, 0.0, 0.0)
            out.append(f'      <origin xyz="{vec(tr(c))}" rpy="{vec(rpy)}"/>')
            geo = f'<capsule radius="{fmt(r)}" length="{fmt(length)}"/>' if length > 0 else f'<sphere radius="{fmt(r)}"/>'
            out.append(f"      <geometry>{geo}</geometry>")
            out.append("    </collision>")
        out.append("  </link>")
        links.append("\n".join(out))

    def shapes_of(b, a, extra=(0.0, 0.0, 0.0)):
        out = []
        for g in range(m.ngeom):
            if m.geom_bodyid[g] != b:
                continue
            G = quat_mat(m.geom_quat[g])
            axis = [G[0][2], G[1][2], G[2][2]]
            c = [float(m.geom_pos[g][i]) + extra[i] - a[i] for i in range(3)]
            c = flat(c)
            if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_CAPSULE:
                out.append((c, axis, float(m.geom_size[g][0]), 2 * float(m.geom_size[g][1])))
            elif m.geom_type[g] == mujoco.mjtGeom.mjGEOM_SPHERE:
                out.append((c, axis, float(m.geom_size[g][0]), 0.0))
        return out

    def body_inertia(b):
        R = quat_mat(m.body_iquat[b])
        d = m.body_inertia[b]
        return [[sum(R[i][k] * d[k] * R[j][k] for k in range(3)) for j in range(3)] for i in range(3)]

    # The world link carries the fixed geoms (the rail, the arena) for drawing; it never moves.
    world_shapes = [s for s in shapes_of(0, [0.0, 0.0, 0.0])]
    eye = [[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]]
    link_xml("world", 1.0, [0, 0, 0], eye, world_shapes)
    for b in bodies:
        a = anchor[b]
        mass = float(m.body_mass[b])
        com = [float(m.body_ipos[b][i]) for i in range(3)]
        inertia = body_inertia(b)
        shapes = shapes_of(b, a)
        for f in range(1, m.nbody):
            if bname(f) in opt["fuse"] and int(m.body_parentid[f]) == b:
                assert not any(m.jnt_bodyid[j] == f for j in range(m.njnt)), f"fused body {bname(f)} has a joint"
                # Parallel-axis sum of the two bodies about their joint centre of mass.
                mf = float(m.body_mass[f])
                cf = [float(m.body_pos[f][i]) + float(m.body_ipos[f][i]) for i in range(3)]
                If = body_inertia(f)
                total = mass + mf
                c = [(mass * com[i] + mf * cf[i]) / total for i in range(3)]

                def shifted(I, mm, p):
                    d = [p[i] - c[i] for i in range(3)]
                    dd = sum(x * x for x in d)
                    return [[I[i][j] + mm * ((dd if i == j else 0.0) - d[i] * d[j]) for j in range(3)] for i in range(3)]

                Ia, Ib = shifted(inertia, mass, com), shifted(If, mf, cf)
                inertia = [[Ia[i][j] + Ib[i][j] for j in range(3)] for i in range(3)]
                mass, com = total, c
                shapes += shapes_of(f, a, [float(x) for x in m.body_pos[f]])
                pos = flat([float(m.body_pos[f][i]) - a[i] for i in range(3)])
                sites.append({"name": bname(f), "link": bname(b), "pos": tr(pos)})
        com = flat([com[i] - a[i] for i in range(3)])
        link_xml(bname(b), mass, com, inertia, shapes)
        parent = int(m.body_parentid[b])
        j = joints_of[b][0]
        pa = anchor[parent]
        xyz = flat([float(m.body_pos[b][i]) + a[i] - pa[i] for i in range(3)])
        lim = [float(x) for x in m.jnt_range[j]] if m.jnt_limited[j] else None
        if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_SLIDE:
            kind = "prismatic"
            lim = lim or (-1000, 1000)
        else:
            kind = "revolute" if lim else "continuous"
        pname = bname(parent) if parent != 0 else "world"
        lim_xml = ""
        if lim is not None:
            lim_xml = f'\n    <limit lower="{fmt(lim[0])}" upper="{fmt(lim[1])}" effort="0" velocity="0"/>'
        joints.append(
            f'  <joint name="{jname(j)}" type="{kind}">\n    <parent link="{pname}"/>\n    <child link="{bname(b)}"/>\n'
            f'    <origin xyz="{vec(tr(xyz))}" rpy="0 0 0"/>\n    <axis xyz="{vec(tr(m.jnt_axis[j]))}"/>{lim_xml}\n  </joint>'
        )
    for s_id in range(m.nsite):
        b = int(m.site_bodyid[s_id])
        sites.append({
            "name": mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_SITE, s_id),
            "link": bname(b),
            "pos": tr(flat([float(m.site_pos[s_id][i]) - anchor[b][i] for i in range(3)])),
        })
    robot_joints = [jname(j) for j in range(m.njnt) if int(m.jnt_bodyid[j]) in bodies]
    jid = {jname(j): j for j in range(m.njnt)}
    dof = lambda jn: int(m.jnt_dofadr[jid[jn]])
    lim_j = [jid[jn] for jn in robot_joints if m.jnt_limited[jid[jn]]]
    assert len({tuple(m.jnt_solref[j]) for j in lim_j}) == 1 and len({tuple(m.jnt_solimp[j]) for j in lim_j}) == 1
    assert len({float(m.jnt_margin[j]) for j in lim_j}) == 1, "one limit margin"
    acts = [{"joint": jname(int(m.actuator_trnid[k][0])), "gear": float(m.actuator_gear[k][0])} for k in range(m.nu)]
    ranges = {tuple(float(x) for x in r) for r in m.actuator_ctrlrange}
    assert len(ranges) == 1
    for jn in robot_joints:
        assert float(m.jnt_stiffness[jid[jn]]) == 0.0 and float(m.dof_frictionloss[dof(jn)]) == 0.0
        assert float(m.qpos0[m.jnt_qposadr[jid[jn]]]) == 0.0
    integrator = {0: "Euler", 1: "RK4", 2: "implicit", 3: "implicitfast"}[int(m.opt.integrator)]
    g = [float(x) for x in m.opt.gravity]
    side = {
        "robot": name,
        "source": (
            f"Gymnasium {gym_id} ({xml_file}), compiled by MuJoCo {mujoco.__version__} and converted by "
            f"scripts/robot_urdf_mujoco.py: masses, inertias, joint anchors, axes, ranges, damping and armature, "
            f"capsules, sites, gears, control range, time step ({float(m.opt.timestep)} s) and integrator (the XML's {integrator}), "
            f"frame_skip {frame_skip} (Gymnasium's), "
            f"joint-limit solref/solimp/margin; gravity {g} (the context's gravity feature). "
            + (
                "The XML's arm moves in the horizontal x-y plane: this URDF is it turned by +90 deg about x "
                "(MuJoCo (x, y, z) is URDF (x, -z, y)), its 1 cm height above the table dropped; gravity is "
                "normal to the plane of motion (along the URDF's y). "
                if xy
                else ""
            )
            + (f"Bodies {opt['fuse']} are welded into their parents (sites here). " if opt["fuse"] else "")
            + (f"Bodies {opt['skip']} are task state, not robot. " if opt["skip"] else "")
            + "No geom of the XML collides (contype 0)."
        ),
        "engine": "articulated",
        "timestep": float(m.opt.timestep),
        "frame_skip": frame_skip,
        "solver_iterations": 1,
        "root": "fixed",
        "torso_link": bname(bodies[0]),
        "root_height": 0.0,
        "ctrl_range": list(ranges.pop()),
        "strength_reference": 1.0,
        "actuators": acts,
        "joint_armatures": [{"joint": jn, "armature": float(m.dof_armature[dof(jn)])} for jn in robot_joints],
        "joint_dampings": [{"joint": jn, "damping": float(m.dof_damping[dof(jn)])} for jn in robot_joints],
        "limit_model": {
            "solref": [float(x) for x in m.jnt_solref[lim_j[0]]],
            "solimp": [float(x) for x in m.jnt_solimp[lim_j[0]]],
            "margin": float(m.jnt_margin[lim_j[0]]),
        },
        "limit_reference_inertia": 1.0,
        "limit_damping_ratio": 1.0,
        "restitution": 0.0,
        "self_collisions": False,
        "ground_contacts": False,
        "gravity_normal_to_plane": xy,
        "rail_joints": opt["rail"],
        "bouncing_limits": opt["bounce"],
        "sites": sites,
        "integrator": "rk4" if integrator == "RK4" else "euler",
        "max_speed": 1000.0,
    }
    doc = (
        f"carl-spec robot description, generated by scripts/robot_urdf_mujoco.py from Gymnasium {gym_id}'s "
        f"{xml_file} as compiled by MuJoCo {mujoco.__version__}: links are the XML's bodies (masses and inertias "
        f"from its geoms at density 1000), each link frame at the anchor of its joint, the first welded to the world"
        + (" (the model turned by +90 deg about x: MuJoCo's x-y plane of motion is the x-z plane here)" if xy else "")
        + "."
    )
    urdf = (
        f'<?xml version="1.0"?>\n<!-- {doc} -->\n<robot name="{name}">\n'
        + "\n".join(links)
        + "\n"
        + "\n".join(joints)
        + "\n</robot>\n"
    )
    return urdf, json.dumps(side, indent=2) + "\n"


def rpy_of(R):
    """URDF rpy (R = Rz(yaw) Ry(pitch) Rx(roll)) of rotation matrix R."""
    pitch = math.asin(max(-1.0, min(1.0, -R[2][0])))
    return (math.atan2(R[2][1], R[2][2]), pitch, math.atan2(R[1][0], R[0][0]))


def convert_free(name, m, mujoco, floor, jname, bname, root):
    """A robot with a free root on the articulated engine (see the module docs)."""
    xml_file, frame_skip, gym_id = ROBOTS[name]
    assert m.jnt_bodyid[root] == 1 and m.body_parentid[1] == 0, "the free joint must be the first body's"
    assert list(m.body_quat[1]) == [1, 0, 0, 0], "the free body is rotated"
    anchor, hinges_of = {}, {}
    for b in range(1, m.nbody):
        js = [j for j in range(m.njnt) if m.jnt_bodyid[j] == b]
        hinges = [j for j in js if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE]
        assert len(js) == len(hinges) or b == 1, f"body {bname(b)}: hinges only"
        anchor[b] = [float(x) for x in m.jnt_pos[hinges[0]]] if hinges else [0.0, 0.0, 0.0]
        assert all(list(m.jnt_pos[j]) == list(m.jnt_pos[hinges[0]]) for j in hinges), \
            f"body {bname(b)}: its hinges need one anchor"
        hinges_of[b] = hinges
    tendons_inert = all(m.tendon_stiffness[t] == 0 and m.tendon_damping[t] == 0 and not m.tendon_limited[t]
                        for t in range(m.ntendon))
    assert tendons_inert, "tendons that act are not converted"
    links, joints = [], []

    def carrier(jn):
        return (f'  <link name="{jn}_link">\n    <inertial>\n      <origin xyz="0 0 0" rpy="0 0 0"/>\n'
                f'      <mass value="0"/>\n      <inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/>\n'
                f'    </inertial>\n  </link>')

    def joint_xml(j, parent, child, xyz, rpy):
        lim = ""
        kind = "continuous"
        if m.jnt_limited[j]:
            kind = "revolute"
            lim = (f'\n    <limit lower="{fmt(float(m.jnt_range[j][0]))}" upper="{fmt(float(m.jnt_range[j][1]))}" '
                   f'effort="0" velocity="0"/>')
        return (f'  <joint name="{jname(j)}" type="{kind}">\n    <parent link="{parent}"/>\n'
                f'    <child link="{child}"/>\n    <origin xyz="{vec(xyz)}" rpy="{vec(rpy)}"/>\n'
                f'    <axis xyz="{vec(m.jnt_axis[j])}"/>{lim}\n  </joint>')

    for b in range(1, m.nbody):
        a = anchor[b]
        R = quat_mat(m.body_iquat[b])
        d = m.body_inertia[b]
        inertia = [[sum(R[i][k] * d[k] * R[j][k] for k in range(3)) for j in range(3)] for i in range(3)]
        com = [float(m.body_ipos[b][i]) - a[i] for i in range(3)]
        out = [f'  <link name="{bname(b)}">', "    <inertial>",
               f'      <origin xyz="{vec(com)}" rpy="0 0 0"/>', f'      <mass value="{fmt(float(m.body_mass[b]))}"/>',
               f'      <inertia ixx="{fmt(inertia[0][0])}" ixy="{fmt(inertia[0][1])}" ixz="{fmt(inertia[0][2])}" '
               f'iyy="{fmt(inertia[1][1])}" iyz="{fmt(inertia[1][2])}" izz="{fmt(inertia[2][2])}"/>', "    </inertial>"]
        for g in range(m.ngeom):
            if m.geom_bodyid[g] != b:
                continue
            c = [float(m.geom_pos[g][i]) - a[i] for i in range(3)]
            if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_SPHERE:
                geom, rpy = f'<sphere radius="{fmt(float(m.geom_size[g][0]))}"/>', (0.0, 0.0, 0.0)
            else:
                assert m.geom_type[g] == mujoco.mjtGeom.mjGEOM_CAPSULE, "spheres and capsules only"
                G = quat_mat(m.geom_quat[g])
                rpy = capsule_rpy([G[0][2], G[1][2], G[2][2]])
                geom = f'<capsule radius="{fmt(float(m.geom_size[g][0]))}" length="{fmt(2 * float(m.geom_size[g][1]))}"/>'
            out += ["    <collision>", f'      <origin xyz="{vec(c)}" rpy="{vec(rpy)}"/>',
                    f"      <geometry>{geom}</geometry>", "    </collision>"]
        out.append("  </link>")
        parent = int(m.body_parentid[b])
        if parent == 0:
            links.append("\n".join(out))
            continue
        pa = anchor[parent]
        Rb = quat_mat(m.body_quat[b])
        xyz = [float(m.body_pos[b][i]) + sum(Rb[i][k] * a[k] for k in range(3)) - pa[i] for i in range(3)]
        rpy = rpy_of(Rb) if list(m.body_quat[b]) != [1, 0, 0, 0] else (0.0, 0.0, 0.0)
        hs = hinges_of[b]
        if not hs:
            links.append("\n".join(out))
            joints.append(f'  <joint name="{bname(b)}_weld" type="fixed">\n    <parent link="{bname(parent)}"/>\n'
                          f'    <child link="{bname(b)}"/>\n    <origin xyz="{vec(xyz)}" rpy="{vec(rpy)}"/>\n  </joint>')
            continue
        up = bname(parent)
        for j in hs[:-1]:
            links.append(carrier(jname(j)))
            joints.append(joint_xml(j, up, f"{jname(j)}_link", xyz, rpy))
            up, xyz, rpy = f"{jname(j)}_link", [0.0, 0.0, 0.0], (0.0, 0.0, 0.0)
        links.append("\n".join(out))
        joints.append(joint_xml(hs[-1], up, bname(b), xyz, rpy))
    movable = [s.split('"')[1] for s in joints if 'type="fixed"' not in s]
    assert movable == [jname(j) for j in range(m.njnt) if j != root], "URDF joint order must be MuJoCo's qpos order"
    robot_geoms = [g for g in range(m.ngeom) if g != floor]

    def mix(a, b):
        return [(float(x) + float(y)) / 2 for x, y in zip(a, b)]

    solrefs = {tuple(mix(m.geom_solref[g], m.geom_solref[floor])) for g in robot_geoms}
    solimps = {tuple(mix(m.geom_solimp[g], m.geom_solimp[floor])) for g in robot_geoms}
    margins = {float(m.geom_margin[g]) + float(m.geom_margin[floor]) for g in robot_geoms}
    assert len(solrefs) == len(solimps) == len(margins) == 1, "one contact model for all geoms"
    assert all(tuple(m.geom_solref[g]) == tuple(m.geom_solref[floor]) and
               tuple(m.geom_solimp[g]) == tuple(m.geom_solimp[floor]) for g in robot_geoms), \
        "robot and floor geoms need one solref and solimp (self-contacts mix robot geoms only)"
    frictions = {max(float(m.geom_friction[g][0]), float(m.geom_friction[floor][0])) for g in robot_geoms}
    condims = {int(m.geom_condim[g]) for g in robot_geoms}
    assert len(condims) == 1 and int(m.geom_condim[floor]) == 3, "one robot condim, floor condim 3"
    gears = [float(m.actuator_gear[k][0]) for k in range(m.nu)]
    lim_j = [j for j in range(m.njnt) if m.jnt_limited[j]]
    solreflimit = {tuple(float(x) for x in m.jnt_solref[j]) for j in lim_j}
    hinge_j = [j for j in range(m.njnt) if j != root]
    dampings = [float(m.dof_damping[m.jnt_dofadr[j]]) for j in hinge_j]
    springs = [(j, float(m.jnt_stiffness[j])) for j in hinge_j if m.jnt_stiffness[j] != 0]
    assert all(m.qpos_spring[m.jnt_qposadr[j]] == m.qpos0[m.jnt_qposadr[j]] == 0 for j, _ in springs)
    self_coll = m.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_FILTERPARENT == 0 and all(
        m.geom_contype[g] & m.geom_conaffinity[h] or m.geom_contype[h] & m.geom_conaffinity[g]
        for g in robot_geoms for h in robot_geoms)
    assert self_coll or all(not (m.geom_contype[g] & m.geom_conaffinity[h] or m.geom_contype[h] & m.geom_conaffinity[g])
                            for g in robot_geoms for h in robot_geoms), "all robot geoms collide or none"
    ranges = {tuple(float(x) for x in r) for r in m.actuator_ctrlrange}
    assert len(ranges) == 1 and len(frictions) == 1
    assert solreflimit == {(0.02, 1.0)}, "joint_stiffness 2500 on inertia 1 stands for solreflimit (0.02, 1)"
    assert all(tuple(m.jnt_solimp[j]) == (0.9, 0.95, 0.001, 0.5, 2.0) and m.jnt_margin[j] == 0 for j in lim_j)
    integrator = {0: "euler", 1: "rk4"}[int(m.opt.integrator)]
    uniform = len(set(gears)) == 1 and len(set(dampings)) == 1 and not springs and condims == {3} and not self_coll
    floor_margin = float(m.geom_margin[floor])
    if uniform:
        left = (f"Left to the context (the spec's mujoco_v5 instance set has the XML's values): gear {gears[0]} "
                f"(actuator_strength; torque = control x gear x actuator_strength / strength_reference), joint "
                f"damping {dampings[0]} (joint_angular_damping), friction {frictions.pop()}, gravity, torso mass "
                f"{float(m.body_mass[1]):.6g} kg, and the joint limits' solreflimit (0.02, 1) (joint_stiffness 2500 "
                f"on limit_reference_inertia 1).")
    else:
        left = ("Kept from the XML: each motor's gear, "
                + (f"each joint's damping pattern (joint_angular_damping scales it: a joint's damping is its XML "
                   f"damping x joint_angular_damping / damping_reference {max(dampings)})"
                   if name not in ABSOLUTE_DAMPING else "each joint's damping")
                + f", joint springs, condim {condims.copy().pop()} on the robot's geoms (the floor's 3 "
                f"wins robot-floor pairs), self-collisions with MuJoCo's parent-child filter, and the joint limits "
                f"(solreflimit (0.02, 1), limit_model). Left to the context (the spec's mujoco_v5 instance set has "
                f"the XML's values): friction {frictions.pop()}, gravity"
                + (", joint damping" if name not in ABSOLUTE_DAMPING else "") + f", torso mass "
                f"{float(m.body_mass[1]):.6g} kg and the other link masses. Its fixed tendons exert nothing and are "
                f"not converted.")
    side = {
        "robot": name,
        "source": (
            f"Gymnasium {gym_id} ({xml_file}), compiled by MuJoCo {mujoco.__version__} and converted by "
            f"scripts/robot_urdf_mujoco.py: bodies one for one (masses and inertias from the geoms at the XML's "
            f"density), joint anchors, axes and ranges, armature, spheres and capsules, control range, time step "
            f"({float(m.opt.timestep)} s) and integrator ({integrator}), frame_skip {frame_skip} (Gymnasium's), "
            f"contact solref/solimp and the pair's margin. " + left
        ),
        "engine": "articulated",
        "integrator": integrator,
        "timestep": float(m.opt.timestep),
        "frame_skip": frame_skip,
        "solver_iterations": 1,
        "root": "free",
        "torso_link": bname(1),
        "root_height": float(m.body_pos[1][2]),
        "ctrl_range": list(ranges.pop()),
        "strength_reference": 1.0,
        "actuators": [{"joint": jname(int(m.actuator_trnid[k][0])), "gear": 1.0 if uniform else gears[k]}
                      for k in range(m.nu)],
        "joint_armatures": [
            {"joint": jname(j), "armature": float(m.dof_armature[m.jnt_dofadr[j]])} for j in range(m.njnt) if j != root
        ],
        "contact_model": {"solref": list(solrefs.pop()), "solimp": list(solimps.pop()), "margin": margins.pop()},
        "limit_reference_inertia": 1.0,
        "limit_damping_ratio": 1.0,
        "restitution": 0.0,
        "self_collisions": bool(self_coll),
        "max_speed": 1000.0,
    }
    if name in ABSOLUTE_DAMPING:
        # Its spec's mass features are carl-bench's (Brax's links: a shin with its foot).
        side["welded_masses"] = True
    if not uniform:
        side["bodies"] = [bname(b) for b in range(1, m.nbody)]
        side["joint_dampings"] = [{"joint": jname(j), "damping": dmp} for j, dmp in zip(hinge_j, dampings)]
        if name not in ABSOLUTE_DAMPING:
            side["damping_reference"] = max(dampings)
        side["joint_springs"] = [{"joint": jname(j), "stiffness": k} for j, k in springs]
        side["contact_condim"] = condims.pop()
        side["floor_margin"] = floor_margin
        side["limit_model"] = {"solref": [0.02, 1.0], "solimp": [0.9, 0.95, 0.001, 0.5, 2.0], "margin": 0.0}
    doc = (
        f"carl-spec robot description, generated by scripts/robot_urdf_mujoco.py from Gymnasium {gym_id}'s "
        f"{xml_file} as compiled by MuJoCo {mujoco.__version__}: links are the XML's bodies (free root: the first "
        f"link; bodies without joints on fixed joints"
        + ("; a body's several hinges through massless carrier links" if any(len(h) > 1 for h in hinges_of.values())
           else "")
        + "), each link frame at the anchor of its joint."
    )
    urdf = (f'<?xml version="1.0"?>\n<!-- {doc} -->\n<robot name="{name}">\n' + "\n".join(links) + "\n"
            + "\n".join(joints) + "\n</robot>\n")
    return urdf, json.dumps(side, indent=2) + "\n"


def convert_arm(name):
    """A 3-D arm welded to the world (Pusher) on the articulated engine: MuJoCo's bodies under a
    `world` link welded at the origin; bodies without joints welded into their parent link, a body's
    several slides (Pusher's object) through massless carrier links; spheres, capsules and cylinders;
    the XML's plane (the table) is the floor at its height (`floor_height`). Only the geoms whose
    contype/conaffinity let them collide in the XML collide here (`contact_links`, `ground_links`)."""
    import gymnasium
    import mujoco

    xml_file, frame_skip, gym_id, opt = ARMS[name]
    path = os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets", xml_file)
    m = mujoco.MjModel.from_xml_path(path)

    def jname(j):
        return mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j)

    def bname(b):
        return mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b)

    GT = mujoco.mjtGeom
    planes = [g for g in range(m.ngeom) if m.geom_type[g] == GT.mjGEOM_PLANE]
    assert len(planes) == 1 and m.geom_bodyid[planes[0]] == 0, "one plane on the world body (the table)"
    table = planes[0]
    assert list(m.geom_quat[table]) == [1, 0, 0, 0], "the table is horizontal"
    skip = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, n) for n in opt["skip"]]
    bodies = [b for b in range(1, m.nbody) if b not in skip and int(m.body_parentid[b]) not in skip]

    # Which geoms collide in the XML: check that the side file's contact and ground links say the same.
    def collide(g, h):
        return bool(m.geom_contype[g] & m.geom_conaffinity[h] or m.geom_contype[h] & m.geom_conaffinity[g])

    live = [g for g in range(m.ngeom) if m.geom_bodyid[g] in bodies]
    for g in live:
        b = bname(m.geom_bodyid[g])
        assert collide(g, table) == (b in opt["ground"]) or (b not in opt["ground"] and b in opt["contact"]), \
            f"geom {g} of {b}: table contact"
    pairs = {(bname(m.geom_bodyid[g]), bname(m.geom_bodyid[h])) for g in live for h in live
             if m.geom_bodyid[g] != m.geom_bodyid[h] and collide(g, h)}
    assert pairs == {(a, b) for a in opt["contact"] for b in opt["contact"] if a != b}, pairs
    # Geoms of a contact link that collide with nothing (drawn only) are not allowed: every geom of
    # the link collides.
    for g in live:
        b = bname(m.geom_bodyid[g])
        if b in opt["contact"]:
            assert m.geom_contype[g] or m.geom_conaffinity[g], f"{b} has a geom that collides with nothing"

    links, joints = [], []

    def carrier(jn):
        return (f'  <link name="{jn}_link">\n    <inertial>\n      <origin xyz="0 0 0" rpy="0 0 0"/>\n'
                f'      <mass value="0"/>\n      <inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/>\n'
                f'    </inertial>\n  </link>')

    def joint_xml(j, parent, child, xyz):
        kind = "prismatic" if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_SLIDE else "revolute"
        assert m.jnt_limited[j], f"joint {jname(j)} is not limited"
        lim = (f'\n    <limit lower="{fmt(float(m.jnt_range[j][0]))}" upper="{fmt(float(m.jnt_range[j][1]))}" '
               f'effort="0" velocity="0"/>')
        return (f'  <joint name="{jname(j)}" type="{kind}">\n    <parent link="{parent}"/>\n'
                f'    <child link="{child}"/>\n    <origin xyz="{vec(xyz)}" rpy="0 0 0"/>\n'
                f'    <axis xyz="{vec(m.jnt_axis[j])}"/>{lim}\n  </joint>')

    links.append('  <link name="world">\n    <inertial>\n      <origin xyz="0 0 0" rpy="0 0 0"/>\n'
                 '      <mass value="1"/>\n      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>\n'
                 '    </inertial>\n  </link>')
    # Joint-less bodies are welded into their parent link (as Brax, whose link masses carl-bench's
    # mass_<link> features name): `offset` is a body's origin in its link's frame.
    has_joint = {b: any(m.jnt_bodyid[j] == b for j in range(m.njnt)) for b in bodies}
    link_of, offset = {}, {}
    for b in bodies:
        assert list(m.body_quat[b]) == [1, 0, 0, 0], f"body {bname(b)} is rotated"
        p = int(m.body_parentid[b])
        if has_joint[b] or p == 0:
            link_of[b], offset[b] = b, [0.0, 0.0, 0.0]
        else:
            link_of[b] = link_of[p]
            offset[b] = [offset[p][i] + float(m.body_pos[b][i]) for i in range(3)]
    sites = []
    for b in bodies:
        if link_of[b] != b:
            continue
        js = [j for j in range(m.njnt) if m.jnt_bodyid[j] == b]
        assert all(list(m.jnt_pos[j]) == [0, 0, 0] for j in js), f"body {bname(b)}: joints at the body origin"
        members = [f for f in bodies if link_of[f] == b]
        mass = sum(float(m.body_mass[f]) for f in members)
        coms = {f: [offset[f][i] + float(m.body_ipos[f][i]) for i in range(3)] for f in members}
        c = [sum(float(m.body_mass[f]) * coms[f][i] for f in members) / mass for i in range(3)]
        inertia = [[0.0] * 3 for _ in range(3)]
        for f in members:
            R = quat_mat(m.body_iquat[f])
            d = m.body_inertia[f]
            mf = float(m.body_mass[f])
            r = [coms[f][i] - c[i] for i in range(3)]
            rr = sum(x * x for x in r)
            for i in range(3):
                for j in range(3):
                    inertia[i][j] += sum(R[i][k] * d[k] * R[j][k] for k in range(3)) + mf * (
                        (rr if i == j else 0.0) - r[i] * r[j])
            if f != b or bname(f) in ("object",):
                # Gymnasium's get_body_com reads a body's xpos: its frame's origin.
                sites.append({"name": bname(f), "link": bname(b), "pos": offset[f]})
        out = [f'  <link name="{bname(b)}">', "    <inertial>",
               f'      <origin xyz="{vec(c)}" rpy="0 0 0"/>',
               f'      <mass value="{fmt(mass)}"/>',
               f'      <inertia ixx="{fmt(inertia[0][0])}" ixy="{fmt(inertia[0][1])}" ixz="{fmt(inertia[0][2])}" '
               f'iyy="{fmt(inertia[1][1])}" iyz="{fmt(inertia[1][2])}" izz="{fmt(inertia[2][2])}"/>', "    </inertial>"]
        for g in range(m.ngeom):
            f = int(m.geom_bodyid[g])
            if f not in members:
                continue
            if bname(b) in opt["contact"] and not (m.geom_contype[g] or m.geom_conaffinity[g]):
                # A drawn-only geom welded into a colliding link: Pusher's fingertip spheres, each
                # inside the end cap of a colliding capsule (checked), so nothing is lost.
                assert any(m.geom_bodyid[h] in members and m.geom_type[h] == GT.mjGEOM_CAPSULE and
                           (m.geom_contype[h] or m.geom_conaffinity[h]) for h in range(m.ngeom))
                continue
            G = quat_mat(m.geom_quat[g])
            rpy = capsule_rpy([G[0][2], G[1][2], G[2][2]])
            size = [float(x) for x in m.geom_size[g]]
            pos = [offset[f][i] + float(m.geom_pos[g][i]) for i in range(3)]
            if m.geom_type[g] == GT.mjGEOM_SPHERE:
                geom, rpy = f'<sphere radius="{fmt(size[0])}"/>', (0.0, 0.0, 0.0)
            elif m.geom_type[g] == GT.mjGEOM_CAPSULE:
                geom = f'<capsule radius="{fmt(size[0])}" length="{fmt(2 * size[1])}"/>'
            else:
                assert m.geom_type[g] == GT.mjGEOM_CYLINDER, "spheres, capsules and cylinders only"
                geom = f'<cylinder radius="{fmt(size[0])}" length="{fmt(2 * size[1])}"/>'
            out += ["    <collision>", f'      <origin xyz="{vec(pos)}" rpy="{vec(rpy)}"/>',
                    f"      <geometry>{geom}</geometry>", "    </collision>"]
        out.append("  </link>")
        parent = int(m.body_parentid[b])
        up = "world" if parent == 0 else bname(link_of[parent])
        xyz = [float(m.body_pos[b][i]) + (offset[parent][i] if parent else 0.0) for i in range(3)]
        assert js, f"body {bname(b)} on the world without a joint"
        for j in js[:-1]:
            links.append(carrier(jname(j)))
            joints.append(joint_xml(j, up, f"{jname(j)}_link", xyz))
            up, xyz = f"{jname(j)}_link", [0.0, 0.0, 0.0]
        links.append("\n".join(out))
        joints.append(joint_xml(js[-1], up, bname(b), xyz))
    movable = [jname(j) for j in range(m.njnt) if m.jnt_bodyid[j] in bodies]
    assert [s.split('"')[1] for s in joints if 'type="fixed"' not in s] == movable, "URDF joint order = qpos order"
    # Contacts: one solref/solimp for all geoms, margins add up (MuJoCo's pair margin), condim 1.
    geoms = live + [table]
    assert len({tuple(m.geom_solref[g]) for g in geoms}) == 1 and len({tuple(m.geom_solimp[g]) for g in geoms}) == 1
    assert len({float(m.geom_margin[g]) for g in geoms}) == 1 and len({int(m.geom_condim[g]) for g in geoms}) == 1
    margin = float(m.geom_margin[table])
    condim = int(m.geom_condim[table])
    assert condim == 1, "frictionless contacts (friction 0 in the mujoco_v5 instance set)"
    lim_j = [j for j in range(m.njnt) if m.jnt_limited[j]]
    assert len({tuple(m.jnt_solref[j]) for j in lim_j}) == 1 and len({tuple(m.jnt_solimp[j]) for j in lim_j}) == 1
    ranges = {tuple(float(x) for x in r) for r in m.actuator_ctrlrange}
    assert len(ranges) == 1
    gears = {float(m.actuator_gear[k][0]) for k in range(m.nu)}
    assert gears == {1.0}, "motors of gear 1"
    integrator = {0: "euler", 1: "rk4"}[int(m.opt.integrator)]
    side = {
        "robot": name,
        "source": (
            f"Gymnasium {gym_id} ({xml_file}), compiled by MuJoCo {mujoco.__version__} and converted by "
            f"scripts/robot_urdf_mujoco.py: bodies under a world link (masses and inertias from the "
            f"geoms at the XML's densities), joint anchors, axes, ranges, damping and armature, spheres, capsules "
            f"and cylinders, gears {sorted(gears)}, control range, time step ({float(m.opt.timestep)} s) and "
            f"integrator ({integrator}), frame_skip {frame_skip} (Gymnasium's), the joint limits' and contacts' "
            f"solref/solimp, the pair margin {2 * margin} (each geom's {margin}). The XML's condim {condim} "
            f"(frictionless contacts) is friction 0 here (the articulated engine's contacts are frictionless, condim "
            f"1, at friction 0); the side file's condim 3 lets the context's friction act otherwise. "
            f"The table (the XML's plane at z = {float(m.geom_pos[table][2])}) is the floor at that height. "
            f"Colliding as in the XML (contype/conaffinity): {opt['ground']} with the table, "
            f"{' and '.join(opt['contact'])} with each other; every other geom is drawn only. "
            f"Bodies without joints are welded into their parent link (as Brax; sites mark their frames' "
            f"origins, which Gymnasium's get_body_com reads): {[bname(b) for b in bodies if link_of[b] != b]}; the fingertip spheres, drawn only and inside "
            f"the end caps of the wrist's colliding capsules, are left out. "
            f"Bodies {opt['skip']} are task state, not robot (no force moves them). The XML's gravity "
            f"{[float(x) for x in m.opt.gravity]} and the geoms' friction {float(m.geom_friction[table][0])} "
            f"(which condim 1 ignores) are the context's gravity and friction features."
        ),
        "engine": "articulated",
        "integrator": integrator,
        "timestep": float(m.opt.timestep),
        "frame_skip": frame_skip,
        "solver_iterations": 1,
        "root": "fixed",
        "torso_link": bname(bodies[0]),
        "root_height": 0.0,
        "floor_height": float(m.geom_pos[table][2]),
        "ctrl_range": list(ranges.pop()),
        "strength_reference": 1.0,
        "actuators": [{"joint": jname(int(m.actuator_trnid[k][0])), "gear": 1.0} for k in range(m.nu)],
        "joint_armatures": [{"joint": jn, "armature": float(m.dof_armature[m.jnt_dofadr[j]])}
                            for j, jn in ((j, jname(j)) for j in range(m.njnt)) if jn in movable],
        "joint_dampings": [{"joint": jn, "damping": float(m.dof_damping[m.jnt_dofadr[j]])}
                           for j, jn in ((j, jname(j)) for j in range(m.njnt)) if jn in movable],
        "contact_model": {"solref": [float(x) for x in m.geom_solref[table]],
                          "solimp": [float(x) for x in m.geom_solimp[table]], "margin": 2 * margin},
        "floor_margin": margin,
        "contact_condim": 3,
        "limit_model": {"solref": [float(x) for x in m.jnt_solref[lim_j[0]]],
                        "solimp": [float(x) for x in m.jnt_solimp[lim_j[0]]], "margin": float(m.jnt_margin[lim_j[0]])},
        "limit_reference_inertia": 1.0,
        "limit_damping_ratio": 1.0,
        "restitution": 0.0,
        "self_collisions": True,
        "contact_links": opt["contact"],
        "ground_links": opt["ground"],
        "sites": sites,
        "max_speed": 1000.0,
    }
    doc = (
        f"carl-spec robot description, generated by scripts/robot_urdf_mujoco.py from Gymnasium {gym_id}'s "
        f"{xml_file} as compiled by MuJoCo {mujoco.__version__}: links are the XML's bodies under a world link "
        f"(bodies without joints welded into their parent; a body's several slides through massless carrier "
        f"links), each link frame at its body's frame."
    )
    urdf = (f'<?xml version="1.0"?>\n<!-- {doc} -->\n<robot name="{name}">\n' + "\n".join(links) + "\n"
            + "\n".join(joints) + "\n</robot>\n")
    return urdf, json.dumps(side, indent=2) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("robots", nargs="*", default=list(ROBOTS) + list(FIXED) + list(ARMS))
    ap.add_argument("--check", action="store_true", help="compare with the committed files instead of writing")
    args = ap.parse_args()
    stale = []
    for name in args.robots:
        if name not in ROBOTS and name not in FIXED and name not in ARMS:
            sys.exit(f"unknown robot {name!r}; choose from {', '.join(list(ROBOTS) + list(FIXED) + list(ARMS))}")
        convert_fn = convert if name in ROBOTS else convert_fixed if name in FIXED else convert_arm
        urdf, side = convert_fn(name)
        for ext, text in (("urdf", urdf), ("actuators.json", side)):
            path = os.path.join(ROBOTS_DIR, f"{name}.{ext}")
            if args.check:
                old = open(path).read() if os.path.exists(path) else None
                if old != text:
                    stale.append(path)
            else:
                with open(path, "w") as f:
                    f.write(text)
                print(f"wrote {path}")
    if stale:
        sys.exit("stale: " + ", ".join(stale))


if __name__ == "__main__":
    main()
