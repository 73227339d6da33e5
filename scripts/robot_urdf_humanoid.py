#!/usr/bin/env python3
"""Write crates/carl-envs-brax/robots/humanoid.urdf from the published geometry of Gymnasium's MuJoCo humanoid.xml
(Humanoid-v5; https://github.com/Farama-Foundation/Gymnasium, gymnasium/envs/mujoco/assets/).

What is taken from the XML: every geom (capsules given by `fromto` and radius, spheres), body
positions, joint anchors (`pos`), axes and ranges, in the XML's body order and joint order.
Masses follow MuJoCo's `inertiafromgeom` with its default density 1000 kg/m^3 (torso
8.907463 kg, which is also Brax's/CARL's torso mass); inertia tensors are computed here from the
same solid shapes (helpers of scripts/robot_urdf.py).

Multi-DoF joints: MuJoCo stacks several hinges in one body (abdomen_z then abdomen_y in lwaist,
hip x/z/y in each thigh, shoulder1/shoulder2 in each upper arm); MuJoCo applies them in XML order
from the parent outwards. URDF joints have one axis, so each stack becomes a chain of revolute
joints through massless carrier links (1e-4 kg, no shapes) named `<joint>_link`; rapier's
reduced-coordinate multibody then has exactly one coordinate per MuJoCo hinge, with the hinge's
own range, damping, spring, armature and motor. The carrier links are not MuJoCo bodies: the
side file lists the 13 real bodies for the observation.

Dropped: the tiny body tilts of lwaist and pelvis (`quat="1 0 -0.002 0"`, 0.23 degrees), the
fixed tendons (they carry no stiffness or limit in the XML and only appear in `info`).
All link frames are parallel to the torso frame at the zero pose. The feet are separate bodies
welded (fixed joint) to the shins, as in the XML. Run from the repository root:
`python3 scripts/robot_urdf_humanoid.py`; the output is committed, the build embeds it.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from robot_urdf import capsule_part, fmt, joint_xml, link_xml, norm, sphere_part, sub, tiny_link, vec  # noqa: E402

# The Brax family's robot files, relative to the repository root (run from there).
ROBOTS = "crates/carl-envs-brax/robots"

PI = math.pi
DENSITY = 1000.0


def capsule_mass(a, b, r):
    L = norm(sub(b, a))
    return DENSITY * (PI * r * r * L + 4.0 / 3.0 * PI * r ** 3)


def sphere_mass(r):
    return DENSITY * 4.0 / 3.0 * PI * r ** 3


def add(a, b):
    return [x + y for x, y in zip(a, b)]


class Builder:
    def __init__(self):
        self.links = []
        self.joints = []
        self.origin = {}  # link name -> origin in the torso frame (all frames parallel)
        self.bodies = []
        self.masses = {}

    def body(self, name, origin, geoms):
        """geoms in the body's own frame: ('capsule', a, b, r) or ('sphere', c, r)."""
        self.origin[name] = origin
        self.bodies.append(name)
        shapes, parts = [], []
        for g in geoms:
            if g[0] == "capsule":
                _, a, b, r = g
                shapes.append(("capsule", a, b, r))
                parts.append(capsule_part(capsule_mass(a, b, r), a, b, r))
            else:
                _, c, r = g
                shapes.append(("sphere", c, r))
                parts.append(sphere_part(sphere_mass(r), c, r))
        self.masses[name] = sum(p[0] for p in parts)
        self.links.append(link_xml(name, shapes, parts))

    def hinges(self, parent, child, child_origin, anchor, hinges):
        """A MuJoCo body `child` at `child_origin` (torso frame) with hinges [(name, axis, lo, hi)]
        anchored at `anchor` (child frame). Returns the frame the child's geoms are given in:
        the child link's frame sits at the anchor, so geoms shift by -anchor."""
        at = add(child_origin, anchor)
        prev = parent
        for k, (name, axis, lo, hi) in enumerate(hinges):
            last = k == len(hinges) - 1
            link = child if last else f"{name}_link"
            if not last:
                self.origin[link] = at
                self.links.append(tiny_link(link))
            self.joints.append(
                joint_xml(name, prev, link, sub(at, self.origin[prev]), axis, lo * PI / 180, hi * PI / 180)
            )
            prev = link
        return at

    def fixed(self, name, parent, child):
        xyz = sub(self.origin[child], self.origin[parent])
        self.joints.append(
            f'  <joint name="{name}" type="fixed">\n    <parent link="{parent}"/>\n    <child link="{child}"/>\n'
            f'    <origin xyz="{vec(xyz)}" rpy="0 0 0"/>\n  </joint>'
        )


def shift(geoms, by):
    out = []
    for g in geoms:
        if g[0] == "capsule":
            out.append(("capsule", sub(g[1], by), sub(g[2], by), g[3]))
        else:
            out.append(("sphere", sub(g[1], by), g[2]))
    return out


def humanoid():
    b = Builder()
    # torso (free root at z = 1.4): torso1, head, uwaist.
    b.body(
        "torso",
        [0.0, 0.0, 0.0],
        [
            ("capsule", [0, -0.07, 0], [0, 0.07, 0], 0.07),
            ("sphere", [0, 0, 0.19], 0.09),
            ("capsule", [-0.01, -0.06, -0.12], [-0.01, 0.06, -0.12], 0.06),
        ],
    )
    # lwaist at (-0.01, 0, -0.26); abdomen_z, abdomen_y anchored at (0, 0, 0.065).
    lw = [-0.01, 0.0, -0.26]
    anchor = [0, 0, 0.065]
    at = b.hinges("torso", "lwaist", lw, anchor, [("abdomen_z", [0, 0, 1], -45, 45), ("abdomen_y", [0, 1, 0], -75, 30)])
    b.body("lwaist", at, shift([("capsule", [0, -0.06, 0], [0, 0.06, 0], 0.06)], anchor))
    # pelvis at lwaist + (0, 0, -0.165); abdomen_x anchored at (0, 0, 0.1).
    pv = add(lw, [0, 0, -0.165])
    anchor = [0, 0, 0.1]
    at = b.hinges("lwaist", "pelvis", pv, anchor, [("abdomen_x", [1, 0, 0], -35, 35)])
    b.body("pelvis", at, shift([("capsule", [-0.02, -0.07, 0], [-0.02, 0.07, 0], 0.09)], anchor))
    for side, s in (("right", -1.0), ("left", 1.0)):
        th = add(pv, [0, 0.1 * s, -0.04])
        # Mirrored hip axes as in the XML (left: -x, -z).
        hips = [
            (f"{side}_hip_x", [-s, 0, 0], -25, 5),
            (f"{side}_hip_z", [0, 0, -s], -60, 35),
            (f"{side}_hip_y", [0, 1, 0], -110, 20),
        ]
        b.hinges("pelvis", f"{side}_thigh", th, [0, 0, 0], hips)
        b.body(f"{side}_thigh", th, [("capsule", [0, 0, 0], [0, -0.01 * s, -0.34], 0.06)])
        sh = add(th, [0, -0.01 * s, -0.403])
        anchor = [0, 0, 0.02]
        at = b.hinges(f"{side}_thigh", f"{side}_shin", sh, anchor, [(f"{side}_knee", [0, -1, 0], -160, -2)])
        b.body(f"{side}_shin", at, shift([("capsule", [0, 0, 0], [0, 0, -0.3], 0.049)], anchor))
        ft = add(sh, [0, 0, -0.45])
        b.body(f"{side}_foot", ft, [("sphere", [0, 0, 0.1], 0.075)])
        b.fixed(f"{side}_ankle_weld", f"{side}_shin", f"{side}_foot")
    for side, s in (("right", -1.0), ("left", 1.0)):
        ua = [0, 0.17 * s, 0.06]
        if side == "right":
            sh_axes = [(f"{side}_shoulder1", [2, 1, 1], -85, 60), (f"{side}_shoulder2", [0, -1, 1], -85, 60)]
            elbow = [0, -1, 1]
        else:
            sh_axes = [(f"{side}_shoulder1", [2, -1, 1], -60, 85), (f"{side}_shoulder2", [0, 1, 1], -60, 85)]
            elbow = [0, -1, -1]
        b.hinges("torso", f"{side}_upper_arm", ua, [0, 0, 0], sh_axes)
        b.body(f"{side}_upper_arm", ua, [("capsule", [0, 0, 0], [0.16, 0.16 * s, -0.16], 0.04)])
        la = add(ua, [0.18, 0.18 * s, -0.18])
        b.hinges(f"{side}_upper_arm", f"{side}_lower_arm", la, [0, 0, 0], [(f"{side}_elbow", elbow, -90, 50)])
        b.body(
            f"{side}_lower_arm",
            la,
            [
                ("capsule", [0.01, -0.01 * s, 0.01], [0.17, -0.17 * s, 0.17], 0.031),
                ("sphere", [0.18, -0.18 * s, 0.18], 0.04),
            ],
        )
    return b


def order_links(b):
    """URDF links in the XML's body order with each carrier link just before the body it carries."""
    by_name = {}
    for text in b.links:
        name = text.split('name="', 1)[1].split('"', 1)[0]
        by_name[name] = text
    order = []
    carriers = {
        "lwaist": ["abdomen_z_link"],
        "right_thigh": ["right_hip_x_link", "right_hip_z_link"],
        "left_thigh": ["left_hip_x_link", "left_hip_z_link"],
        "right_upper_arm": ["right_shoulder1_link"],
        "left_upper_arm": ["left_shoulder1_link"],
    }
    for body in b.bodies:
        order.extend(carriers.get(body, []))
        order.append(body)
    assert sorted(order) == sorted(by_name), (order, list(by_name))
    return [by_name[n] for n in order]


if __name__ == "__main__":
    b = humanoid()
    links = order_links(b)
    doc = " ".join(__doc__.split())
    body = "\n".join(links + b.joints)
    text = (
        '<?xml version="1.0"?>\n'
        f"<!-- carl-spec robot description, generated by scripts/robot_urdf_humanoid.py. {doc} -->\n"
        f'<robot name="humanoid">\n{body}\n</robot>\n'
    )
    with open(f"{ROBOTS}/humanoid.urdf", "w") as f:
        f.write(text)
    total = sum(b.masses.values())
    print("bodies:", b.bodies)
    print("masses:", {k: round(v, 6) for k, v in b.masses.items()}, "total", round(total, 4))
    print("lowest foot point (torso frame):", fmt(b.origin["right_foot"][2] + 0.1 - 0.075))
