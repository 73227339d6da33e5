#!/usr/bin/env python3
"""Write crates/carl-envs-brax/robots/<name>.urdf from the published geometry of each robot (see the docstrings).

Ant and Humanoid are no longer written here: scripts/robot_urdf_mujoco.py converts Gymnasium's ant.xml and humanoid.xml.

The URDF files are authored for carl-spec: link lengths, radii, joint axes and ranges are read
from the published models (Gymnasium's MuJoCo v5 XML for HalfCheetah), masses from
Brax (2021) where CARL's context refers to Brax, and inertia tensors are computed here from
the collision shapes (solid capsules/spheres of the link's mass). Run from the repository root:
`python3 scripts/robot_urdf.py`; the output is committed, the build embeds it.
"""
import math

# The Brax family's robot files, relative to the repository root (run from there).
ROBOTS = "crates/carl-envs-brax/robots"

PI = math.pi


def capsule_inertia(m, r, L):
    """Solid capsule (cylinder length L + two hemispheres radius r) of total mass m, about its
    centre: (I_perp, I_axis)."""
    vc = PI * r * r * L
    vs = 4.0 / 3.0 * PI * r ** 3
    mc = m * vc / (vc + vs)
    ms = m - mc
    ia = mc * r * r / 2 + ms * 2 * r * r / 5
    ip = mc * (3 * r * r + L * L) / 12 + ms * (2 * r * r / 5 + L * L / 4 + 3 * L * r / 8)
    return ip, ia


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def norm(v):
    return math.sqrt(sum(x * x for x in v))


class Body:
    def __init__(self):
        self.mass = 0.0
        self.com_terms = []  # (mass, centre, I_perp, I_axis, axis)


def capsule_rpy(d):
    """rpy turning the URDF capsule's z axis onto unit direction d."""
    return (0.0, math.acos(max(-1.0, min(1.0, d[2]))), math.atan2(d[1], d[0]))


def fmt(x):
    s = f"{x:.9g}"
    return "0" if s in ("-0", "0") else s


def vec(v):
    return " ".join(fmt(x) for x in v)


def inertial(parts):
    """parts: list of (mass, centre, I_perp, I_axis, unit axis) -> mass, com, 3x3 inertia about com."""
    m = sum(p[0] for p in parts)
    com = [sum(p[0] * p[1][i] for p in parts) / m for i in range(3)]
    I = [[0.0] * 3 for _ in range(3)]
    for pm, c, ip, ia, ax in parts:
        for i in range(3):
            for j in range(3):
                eye = 1.0 if i == j else 0.0
                I[i][j] += ip * (eye - ax[i] * ax[j]) + ia * ax[i] * ax[j]
        r = sub(c, com)
        rr = sum(x * x for x in r)
        for i in range(3):
            for j in range(3):
                eye = 1.0 if i == j else 0.0
                I[i][j] += pm * (rr * eye - r[i] * r[j])
    return m, com, I


def link_xml(name, shapes, mass_parts):
    """shapes: list of ('capsule', a, b, r) or ('sphere', c, r) in the link frame."""
    out = [f'  <link name="{name}">']
    m, com, I = inertial(mass_parts)
    out.append("    <inertial>")
    out.append(f'      <origin xyz="{vec(com)}" rpy="0 0 0"/>')
    out.append(f'      <mass value="{fmt(m)}"/>')
    out.append(
        f'      <inertia ixx="{fmt(I[0][0])}" ixy="{fmt(I[0][1])}" ixz="{fmt(I[0][2])}" '
        f'iyy="{fmt(I[1][1])}" iyz="{fmt(I[1][2])}" izz="{fmt(I[2][2])}"/>'
    )
    out.append("    </inertial>")
    for s in shapes:
        out.append("    <collision>")
        if s[0] == "capsule":
            _, a, b, r = s
            d = sub(b, a)
            L = norm(d)
            u = [x / L for x in d]
            c = [(x + y) / 2 for x, y in zip(a, b)]
            out.append(f'      <origin xyz="{vec(c)}" rpy="{vec(capsule_rpy(u))}"/>')
            out.append(f'      <geometry><capsule radius="{fmt(r)}" length="{fmt(L)}"/></geometry>')
        else:
            _, c, r = s
            out.append(f'      <origin xyz="{vec(c)}" rpy="0 0 0"/>')
            out.append(f'      <geometry><sphere radius="{fmt(r)}"/></geometry>')
        out.append("    </collision>")
    out.append("  </link>")
    return "\n".join(out)


def capsule_part(m, a, b, r):
    d = sub(b, a)
    L = norm(d)
    u = [x / L for x in d]
    ip, ia = capsule_inertia(m, r, L)
    return (m, [(x + y) / 2 for x, y in zip(a, b)], ip, ia, u)


def sphere_part(m, c, r):
    i = 2.0 / 5.0 * m * r * r
    return (m, c, i, i, [0.0, 0.0, 1.0])


def joint_xml(name, parent, child, xyz, axis, lo, hi, kind="revolute"):
    n = norm(axis)
    ax = [x / n for x in axis]
    lim = f'\n    <limit lower="{fmt(lo)}" upper="{fmt(hi)}" effort="0" velocity="0"/>' if kind != "continuous" else ""
    return (
        f'  <joint name="{name}" type="{kind}">\n'
        f'    <parent link="{parent}"/>\n    <child link="{child}"/>\n'
        f'    <origin xyz="{vec(xyz)}" rpy="0 0 0"/>\n    <axis xyz="{vec(ax)}"/>{lim}\n  </joint>'
    )


def tiny_link(name):
    return (
        f'  <link name="{name}">\n    <inertial>\n      <origin xyz="0 0 0" rpy="0 0 0"/>\n'
        f'      <mass value="0.0001"/>\n'
        f'      <inertia ixx="1e-06" ixy="0" ixz="0" iyy="1e-06" iyz="0" izz="1e-06"/>\n'
        f"    </inertial>\n  </link>"
    )


def half_cheetah():
    """Gymnasium HalfCheetah-v5 (half_cheetah.xml): torso capsule r=0.046 from x=-0.5 to 0.5 at
    height 0.7 with a head capsule, back and front thigh/shin/foot capsules (positions, tilts
    and half-lengths of the XML), hinges about y with the XML's ranges; a planar root of two
    slides (x, z) and a pitch hinge on massless carrier links. Masses proportional to the
    capsule volumes with a 14 kg total (the XML's settotalmass); the torso mass is a context
    feature."""
    r = 0.046

    def caps(pos, angle, half):
        d = [math.sin(angle), 0.0, math.cos(angle)]
        a = [p - half * x for p, x in zip(pos, d)]
        b = [p + half * x for p, x in zip(pos, d)]
        return a, b

    def vol(a, b):
        L = norm(sub(b, a))
        return PI * r * r * L + 4.0 / 3.0 * PI * r ** 3

    torso = ([-0.5, 0, 0], [0.5, 0, 0])
    head = caps([0.6, 0, 0.1], 0.87, 0.15)
    segs = [  # name, parent, joint pos in parent, geom (pos, angle, half), range
        ("bthigh", "torso", [-0.5, 0, 0], ([0.1, 0, -0.13], -3.8, 0.145), (-0.52, 1.05)),
        ("bshin", "bthigh", [0.16, 0, -0.25], ([-0.14, 0, -0.07], -2.03, 0.15), (-0.785, 0.785)),
        ("bfoot", "bshin", [-0.28, 0, -0.14], ([0.03, 0, -0.097], -0.27, 0.094), (-0.4, 0.785)),
        ("fthigh", "torso", [0.5, 0, 0], ([-0.07, 0, -0.12], 0.52, 0.133), (-1.0, 0.7)),
        ("fshin", "fthigh", [-0.14, 0, -0.24], ([0.065, 0, -0.09], -0.6, 0.106), (-1.2, 0.87)),
        ("ffoot", "fshin", [0.13, 0, -0.18], ([0.045, 0, -0.07], -0.6, 0.07), (-0.5, 0.5)),
    ]
    caps_of = {name: caps(*g) for name, _, _, g, _ in segs}
    total_v = vol(*torso) + vol(*head) + sum(vol(*c) for c in caps_of.values())
    mass = lambda a, b: 14.0 * vol(a, b) / total_v
    links = ["  <link name=\"world\">\n    <inertial>\n      <origin xyz=\"0 0 0\" rpy=\"0 0 0\"/>\n"
             "      <mass value=\"1\"/>\n      <inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/>\n"
             "    </inertial>\n  </link>", tiny_link("slider_x"), tiny_link("slider_z")]
    links.append(link_xml("torso", [("capsule", *torso, r), ("capsule", *head, r)],
                          [capsule_part(mass(*torso), *torso, r), capsule_part(mass(*head), *head, r)]))
    joints = [
        joint_xml("rootx", "world", "slider_x", [0, 0, 0.7], [1, 0, 0], -1000.0, 1000.0, kind="prismatic"),
        joint_xml("rootz", "slider_x", "slider_z", [0, 0, 0], [0, 0, 1], -1000.0, 1000.0, kind="prismatic"),
        joint_xml("rooty", "slider_z", "torso", [0, 0, 0], [0, 1, 0], 0, 0, kind="continuous"),
    ]
    for name, parent, jpos, _, (lo, hi) in segs:
        a, b = caps_of[name]
        links.append(link_xml(name, [("capsule", a, b, r)], [capsule_part(mass(a, b), a, b, r)]))
        joints.append(joint_xml(name, parent, name, jpos, [0, 1, 0], lo, hi))
    return "half_cheetah", links, joints


def write(name, links, joints, doc):
    body = "\n".join(links + joints)
    text = (
        '<?xml version="1.0"?>\n'
        f"<!-- carl-spec robot description, generated by scripts/robot_urdf.py. {doc} -->\n"
        f'<robot name="{name}">\n{body}\n</robot>\n'
    )
    with open(f"{ROBOTS}/{name}.urdf", "w") as f:
        f.write(text)


if __name__ == "__main__":
    for make in (half_cheetah,):
        name, links, joints = make()
        write(name, links, joints, " ".join(make.__doc__.split()))
