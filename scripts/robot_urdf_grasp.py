#!/usr/bin/env python3
"""Write crates/carl-envs-brax/robots/grasp.urdf and robots/grasp.actuators.json from Brax's grasp system config.

Source: Brax v0.0.9 (identical in v0.0.8..v0.0.10, the versions CARL 2021 ran),
brax/envs/grasp.py `_SYSTEM_CONFIG`. Facts taken from it:

* every body has mass 1 and inertia diag(1, 1, 1), except the palm (mass 1, inertia
  diag(5000.035, 10000.7225, 10000.7225), frozen: Brax moves it kinematically);
* Brax capsules are given by their total length; a URDF capsule (rapier-urdf) by the length of
  its axis segment, so segment = length - 2 radius;
* palm: capsule radius 1.5, length 3.1, rotated 120 deg about x;
* four fingers of three phalanges (Proximal, Middle, Distal), each a capsule radius 0.5,
  length 2.0, rotated 90 deg about x (fingers 1, 2: along y) or about y (fingers 3, 4: along x);
* joints: palm -> proximal at parent offset (0, +-1.5, -0.5) / (-+1.5, 0, -0.5) with two angle
  limits [-45, 45] deg (a universal joint: rotation about the joint frame's x, then about the
  rotated y), proximal -> middle and middle -> distal one limit each ([-90, 0] deg for finger 1,
  [0, 90] for the others) with offsets +-0.75 from the body centres; joint frames rotated by
  `rotation` (z -90 deg for finger 3, z 90 deg for finger 4's middle and distal joints and
  x 180, z -90 deg for its proximal joint; Brax's Euler angles are intrinsic x-y'-z'');
* 12 `angle` actuators of strength 300 (one per joint, both axes of the universal joints);
* dt 0.02 s, 4 substeps; friction sqrt(0.6) (contacts multiply the two colliders' values);
* the object is a capsule radius 1, length 2.02 (a ball), mass 1, inertia 1; the target a
  frozen sphere radius 1.1; only the distal phalanges and the palm collide with the object,
  and the object with the ground.

The URDF is the hand only (the object is a free body the task adds to the world): a fixed
`world` link, three prismatic carriers (x, y, z) moving the palm as Brax's action moves it,
and the fingers with Brax's masses and inertias. A universal joint becomes two revolute joints
with a massless knuckle link between them. Link frames sit at the joint with the parent (URDF
convention), each body's centre of mass where Brax puts the body. Default pose as Brax's
`default_qp`: joint angles at the middle of their limits, the hand lifted until its lowest
point touches z = 0 (the palm height is written as `root_height`).

Run from the repository root: `python3 scripts/robot_urdf_grasp.py`.
"""
import json
import math

from robot_urdf import fmt, tiny_link, vec

# The Brax family's robot files, relative to the repository root (run from there).
ROBOTS = "crates/carl-envs-brax/robots"

PI = math.pi
DEG = PI / 180


def rot_x(a):
    c, s = math.cos(a), math.sin(a)
    return [[1, 0, 0], [0, c, -s], [0, s, c]]


def rot_axis(u, a):
    x, y, z = u
    c, s = math.cos(a), math.sin(a)
    t = 1 - c
    return [
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
    ]


def mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def apply(m, v):
    return [sum(m[i][k] * v[k] for k in range(3)) for i in range(3)]


def add(a, b):
    return [x + y for x, y in zip(a, b)]


def scale(v, k):
    return [x * k for x in v]


FINGER_R = 0.5
FINGER_SEG = 2.0 - 2 * FINGER_R
PALM_R = 1.5
PALM_SEG = 3.1 - 2 * PALM_R
PALM_AXIS = apply(rot_x(120 * DEG), [0, 0, 1])
OBJECT_R = 1.0
OBJECT_SEG = 2.02 - 2 * OBJECT_R
TARGET_R = 1.1

# (suffix, outward unit direction, proximal axes (x, rotated y), curl axis, curl limits in deg)
FINGERS = [
    ("", [0, 1, 0], ([1, 0, 0], [0, 1, 0]), [1, 0, 0], (-90, 0)),
    ("Two", [0, -1, 0], ([1, 0, 0], [0, 1, 0]), [1, 0, 0], (0, 90)),
    ("Three", [-1, 0, 0], ([0, -1, 0], [1, 0, 0]), [0, -1, 0], (0, 90)),
    ("Four", [1, 0, 0], ([0, 1, 0], [1, 0, 0]), [0, 1, 0], (0, 90)),
]


def link(name, mass, inertia, com, shapes):
    out = [f'  <link name="{name}">', "    <inertial>"]
    out.append(f'      <origin xyz="{vec(com)}" rpy="0 0 0"/>')
    out.append(f'      <mass value="{fmt(mass)}"/>')
    ix, iy, iz = inertia
    out.append(f'      <inertia ixx="{fmt(ix)}" ixy="0" ixz="0" iyy="{fmt(iy)}" iyz="0" izz="{fmt(iz)}"/>')
    out.append("    </inertial>")
    for centre, axis, seg, r in shapes:
        # rpy turning the capsule's z axis onto `axis` (unit).
        rpy = (0.0, math.acos(max(-1.0, min(1.0, axis[2]))), math.atan2(axis[1], axis[0]))
        out.append("    <collision>")
        out.append(f'      <origin xyz="{vec(centre)}" rpy="{vec(rpy)}"/>')
        out.append(f'      <geometry><capsule radius="{fmt(r)}" length="{fmt(seg)}"/></geometry>')
        out.append("    </collision>")
    out.append("  </link>")
    return "\n".join(out)


def joint(name, parent, child, xyz, axis, lo, hi, kind="revolute"):
    return (
        f'  <joint name="{name}" type="{kind}">\n'
        f'    <parent link="{parent}"/>\n    <child link="{child}"/>\n'
        f'    <origin xyz="{vec(xyz)}" rpy="0 0 0"/>\n    <axis xyz="{vec(axis)}"/>\n'
        f'    <limit lower="{fmt(lo)}" upper="{fmt(hi)}" effort="0" velocity="0"/>\n  </joint>'
    )


def build():
    links = [
        '  <link name="world">\n    <inertial>\n      <origin xyz="0 0 0" rpy="0 0 0"/>\n'
        '      <mass value="1"/>\n      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>\n'
        "    </inertial>\n  </link>",
        tiny_link("slider_x"),
        tiny_link("slider_y"),
        link(
            "HandPalm",
            1.0,
            (5000.0350000858306885, 10000.7224998474121094, 10000.7224998474121094),
            [0, 0, 0],
            [([0, 0, 0], PALM_AXIS, PALM_SEG, PALM_R)],
        ),
    ]
    joints = [
        joint("slide_x", "world", "slider_x", [0, 0, 0], [1, 0, 0], -1000.0, 1000.0, "prismatic"),
        joint("slide_y", "slider_x", "slider_y", [0, 0, 0], [0, 1, 0], -1000.0, 1000.0, "prismatic"),
        joint("slide_z", "slider_y", "HandPalm", [0, 0, 0], [0, 0, 1], -1000.0, 1000.0, "prismatic"),
    ]
    actuators = []
    # Lowest point of the hand in the default pose, relative to the palm centre.
    low = min(c[2] + s * 0.5 * PALM_SEG * PALM_AXIS[2] for c in ([0, 0, 0],) for s in (-1, 1)) - PALM_R
    for suffix, out, (a1, a2), curl, (lo, hi) in FINGERS:
        base = add(scale(out, 1.5), [0, 0, -0.5])
        centre = scale(out, 0.75)
        prox, mid, dist = (f"HandThumb{p}{suffix}" for p in ("Proximal", "Middle", "Distal"))
        knuckle = f"{prox}Knuckle"
        links.append(tiny_link(knuckle))
        for name in (prox, mid, dist):
            links.append(link(name, 1.0, (1.0, 1.0, 1.0), centre, [(centre, out, FINGER_SEG, FINGER_R)]))
        j_u = f"HandPalm_{prox}"
        j_m = f"{prox}_{mid}"
        j_d = f"{mid}_{dist}"
        joints.append(joint(f"{j_u}_1", "HandPalm", knuckle, base, a1, -45 * DEG, 45 * DEG))
        joints.append(joint(f"{j_u}_2", knuckle, prox, [0, 0, 0], a2, -45 * DEG, 45 * DEG))
        joints.append(joint(j_m, prox, mid, scale(out, 1.5), curl, lo * DEG, hi * DEG))
        joints.append(joint(j_d, mid, dist, scale(out, 1.5), curl, lo * DEG, hi * DEG))
        # Brax's action order: joints in config order (distal, middle, proximal's two axes).
        actuators += [j_d, j_m, f"{j_u}_1", f"{j_u}_2"]
        # Default pose (mid-limit angles): lowest capsule point of each phalanx.
        mid_angle = (lo + hi) / 2 * DEG
        rot = mul(rot_axis(a1, 0.0), rot_axis(a2, 0.0))
        p = base
        for k in range(3):
            if k > 0:
                rot = mul(rot, rot_axis(curl, mid_angle))
            c = add(p, apply(rot, centre))
            d = apply(rot, out)
            for s in (-1, 1):
                low = min(low, c[2] + s * 0.5 * FINGER_SEG * d[2] - FINGER_R)
            p = add(p, apply(rot, scale(out, 1.5)))
    return links, joints, actuators, -low


def main():
    links, joints, actuators, palm_height = build()
    doc = " ".join(__doc__.split("\n\n")[0].split())
    text = (
        '<?xml version="1.0"?>\n'
        f"<!-- carl-spec robot description, generated by scripts/robot_urdf_grasp.py. {doc} "
        "Brax grasp claw hand: palm on x/y/z slides, four fingers of three phalanges (universal "
        "knuckle, two hinges), Brax's masses (1 kg) and inertias. -->\n"
        f'<robot name="grasp">\n' + "\n".join(links + joints) + "\n</robot>\n"
    )
    with open(f"{ROBOTS}/grasp.urdf", "w") as f:
        f.write(text)
    side = {
        "robot": "grasp",
        "source": (
            "Brax v0.0.9 envs/grasp.py (_SYSTEM_CONFIG; unchanged v0.0.8-v0.0.10, CARL 2021's Brax), "
            "written by scripts/robot_urdf_grasp.py. 16 angle actuators of strength 300 "
            "(= actuator_strength): a position servo of stiffness gear x actuator_strength / 300 N m/rad "
            "towards the commanded angle, realised as rapier's implicit joint spring; dt 0.02 s = "
            "0.005 s x 4 substeps as Brax. The palm (frozen in Brax and moved kinematically) rides "
            "on three undamped slides driven by velocity by the task. Object (added by the task, not "
            f"in the URDF): capsule radius {OBJECT_R}, segment {OBJECT_SEG:.2f} m, mass 1, inertia 1, "
            f"at (0, 0, {OBJECT_R}); target sphere radius {TARGET_R}. Default pose: palm at "
            f"z = {palm_height:.6f} m (the hand lifted to touch z = 0, Brax's default_qp). Joint "
            "limits are springs of joint_stiffness on Brax's finger inertia (1 kg m^2)."
        ),
        "timestep": 0.005,
        "frame_skip": 4,
        "solver_iterations": 2,
        "root": "fixed",
        "torso_link": "HandPalm",
        "root_joints": ["slide_x", "slide_y", "slide_z"],
        "root_height": round(palm_height, 9),
        "ctrl_range": [-1.0, 1.0],
        "strength_reference": 300.0,
        "actuators": [{"joint": j, "gear": 300.0} for j in actuators],
        "limit_reference_inertia": 1.0,
        "limit_damping_ratio": 1.0,
        "restitution": 0.0,
        "self_collisions": False,
        "ground_contacts": False,
        "max_speed": 500.0,
    }
    with open(f"{ROBOTS}/grasp.actuators.json", "w") as f:
        f.write(json.dumps(side, indent=2) + "\n")
    print(f"palm height {palm_height:.6f}")


if __name__ == "__main__":
    main()
