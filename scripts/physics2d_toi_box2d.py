#!/usr/bin/env python3
"""Box2D's own answers for carl-spec's `physics2d` GJK distance and time of impact.

Runs pybox2d (Box2D 2.3, float32) `b2Distance` and `b2TimeOfImpact` on generated shape pairs and
sweeps and writes them as a parity fixture: the shapes as Box2D stores them (vertices after its
convex hull, radius), the sweeps, Box2D's core distance at the start of the sweeps and its TOI state
and time. Every input is a float32 value, so both sides start from identical numbers.

Cases: a box falling flat or tilted onto an edge at several speeds, a bar turning a quarter turn onto
an edge, and random convex polygons (3..8 vertices) and edges moving and turning within Box2D's
per-step limits (translation < 2 m, rotation <= pi/2).

Usage (pybox2d, e.g. the Gymnasium box2d extra, in a venv of its own):
    .venv-peers/bin/python scripts/physics2d_toi_box2d.py --cases 300 \
        --out crates/carl-physics2d/tests/fixtures/physics2d_toi_box2d.json

`crates/carl-physics2d/src/toi.rs` (test `matches_box2d_on_recorded_cases`) replays every case.
"""
import argparse
import json
import math
import platform
import random

import Box2D as B
import numpy as np

STATES = {
    B.b2TOIOutput.e_unknown: "unknown",
    B.b2TOIOutput.e_failed: "failed",
    B.b2TOIOutput.e_overlapped: "overlapped",
    B.b2TOIOutput.e_touching: "touching",
    B.b2TOIOutput.e_separated: "separated",
}


def f32(x):
    return float(np.float32(x))


def vec(v):
    return [f32(v[0]), f32(v[1])]


def polygon(rng, n):
    r = rng.uniform(0.2, 2.0)
    gaps = [rng.uniform(0.2, 1.0) for _ in range(n)]
    total = sum(gaps)
    angle = rng.uniform(0.0, 2 * math.pi)
    points = []
    for g in gaps:
        points.append(vec((r * math.cos(angle), r * math.sin(angle))))
        angle += 2 * math.pi * g / total
    if n == 2:
        return B.b2EdgeShape(vertices=points)
    return B.b2PolygonShape(vertices=points)


def box(hx, hy):
    return B.b2PolygonShape(box=(hx, hy))


def edge(v1, v2):
    return B.b2EdgeShape(vertices=[v1, v2])


def sweep(local_center, c0, c, a0, a):
    s = B.b2Sweep()
    s.localCenter = vec(local_center)
    s.c0 = vec(c0)
    s.c = vec(c)
    s.a0 = f32(a0)
    s.a = f32(a)
    s.alpha0 = 0.0
    return s


def random_sweep(rng, max_turn, max_travel):
    c0 = (rng.uniform(-3, 3), rng.uniform(-3, 3))
    travel = (rng.uniform(-max_travel, max_travel), rng.uniform(-max_travel, max_travel))
    a0 = rng.uniform(-math.pi, math.pi)
    return sweep(
        (rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5)),
        c0,
        (c0[0] + travel[0], c0[1] + travel[1]),
        a0,
        a0 + rng.uniform(-max_turn, max_turn),
    )


def shape_json(shape):
    return {"vertices": [vec(v) for v in shape.vertices], "radius": f32(shape.radius)}


def sweep_json(s):
    return {
        "local_center": vec(s.localCenter),
        "c0": vec(s.c0),
        "c": vec(s.c),
        "a0": f32(s.a0),
        "a": f32(s.a),
        "alpha0": f32(s.alpha0),
    }


def case(kind, shape_a, sweep_a, shape_b, sweep_b, t_max=1.0):
    state, t = B.b2TimeOfImpact(shapeA=shape_a, sweepA=sweep_a, shapeB=shape_b, sweepB=sweep_b, tMax=t_max)
    xf_a, xf_b = B.b2Transform(), B.b2Transform()
    sweep_a.GetTransform(xf_a, 0.0)
    sweep_b.GetTransform(xf_b, 0.0)
    d = B.b2Distance(shapeA=shape_a, shapeB=shape_b, transformA=xf_a, transformB=xf_b, useRadii=False)
    return {
        "kind": kind,
        "a": shape_json(shape_a),
        "sweep_a": sweep_json(sweep_a),
        "b": shape_json(shape_b),
        "sweep_b": sweep_json(sweep_b),
        "t_max": f32(t_max),
        "distance_at_0": float(d.distance),
        "state": STATES[state],
        "t": float(t),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", type=int, default=300, help="random polygon cases")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    rng = random.Random(args.seed)
    still = lambda: sweep((0, 0), (0, 0), (0, 0), 0, 0)  # noqa: E731
    ground = edge((-10, 0), (10, 0))
    cases = []
    for speed in [0.6, 1.0, 5.0, 50.0, 500.0]:
        cases.append(case(f"flat box falls at {speed}", ground, still(), box(0.5, 0.5),
                          sweep((0, 0), (0.3, 1.0), (0.3, 1.0 - speed), 0, 0)))
        cases.append(case(f"tilted box falls at {speed}", ground, still(), box(0.5, 0.5),
                          sweep((0, 0), (0.0, 1.0), (0.0, 1.0 - speed), 0.4, 0.4)))
    cases.append(case("bar turns a quarter onto an edge", ground, still(), box(1.0, 0.05),
                      sweep((0, 0), (0, 0.8), (0, 0.8), 0, 0.5 * math.pi)))
    cases.append(case("bar turns and slides onto an edge", ground, still(), box(1.0, 0.05),
                      sweep((0, 0), (-1.0, 1.5), (0.5, 0.2), 0.2, 0.2 + 0.5 * math.pi)))
    cases.append(case("box rises off an edge", ground, still(), box(0.5, 0.5),
                      sweep((0, 0), (0, 1.0), (0, 3.0), 0, 0.5)))
    cases.append(case("box sunk into an edge", ground, still(), box(0.5, 0.5),
                      sweep((0, 0), (0, 0.2), (0, -1.0), 0, 0)))
    i = 0
    overlapped = 0
    while i < args.cases:
        max_turn = 0.0 if i % 3 == 0 else 0.5 * math.pi
        a = polygon(rng, rng.randint(2, 8))
        b = polygon(rng, rng.randint(2, 8))
        if a.type == B.b2Shape.e_edge and b.type == B.b2Shape.e_edge:
            b = polygon(rng, rng.randint(3, 8))  # Box2D has no edge-edge contacts
        sa = random_sweep(rng, max_turn, 1.4)
        sb = random_sweep(rng, max_turn, 1.4)
        if i % 2 == 0:
            # Aim B's end near A's end so that most of these sweeps meet.
            end = (sa.c[0] + rng.uniform(-1, 1), sa.c[1] + rng.uniform(-1, 1))
            start = (end[0] + rng.uniform(-1.4, 1.4), end[1] + rng.uniform(-1.4, 1.4))
            sb = sweep(sb.localCenter, start, end, sb.a0, sb.a)
        c = case(f"random {i} (turn <= {max_turn:.2f})", a, sa, b, sb)
        if c["state"] == "overlapped":
            if overlapped * 20 >= args.cases:
                continue  # a few suffice
            overlapped += 1
        cases.append(c)
        i += 1
    out = {
        "generator": "scripts/physics2d_toi_box2d.py",
        "box2d": f"pybox2d {B.__version__} (Box2D 2.3, float32)",
        "python": platform.python_version(),
        "seed": args.seed,
        "cases": cases,
    }
    with open(args.out, "w") as f:
        json.dump(out, f, indent=None, separators=(",", ":"))
        f.write("\n")
    states = {}
    for c in cases:
        states[c["state"]] = states.get(c["state"], 0) + 1
    print(f"{len(cases)} cases: {states}")


if __name__ == "__main__":
    main()
