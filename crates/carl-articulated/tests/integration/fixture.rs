//! Builds a [`Model`] from a MuJoCo fixture's compiled-model fields (as
//! `scripts/articulated_mujoco_fixtures.py` writes them).

use carl_articulated::model::{
    Actuator, Body, Cone, Dynamics, Geom, Integrator, Joint, JointKind, Model, Options, Shape, Tendon, TendonEquality,
};
use serde_json::Value;

pub fn load(name: &str) -> Value {
    let path = format!("{}/tests/fixtures/mujoco_{name}.json", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    serde_json::from_str(&text).expect("fixture JSON")
}

pub fn f(v: &Value) -> f64 {
    v.as_f64().expect("number")
}
pub fn fs(v: &Value) -> Vec<f64> {
    v.as_array().expect("array").iter().map(f).collect()
}
fn v3(v: &Value) -> [f64; 3] {
    let x = fs(v);
    [x[0], x[1], x[2]]
}
fn q4(v: &Value) -> [f64; 4] {
    let x = fs(v);
    [x[0], x[1], x[2], x[3]]
}
fn arr<const N: usize>(v: &Value) -> [f64; N] {
    let x = fs(v);
    std::array::from_fn(|i| x[i])
}

pub fn model(fx: &Value) -> Model {
    let m = &fx["model"];
    let o = &m["opt"];
    let opt = Options {
        timestep: f(&o["timestep"]),
        gravity: v3(&o["gravity"]),
        integrator: match o["integrator"].as_str() {
            Some("rk4") => Integrator::Rk4,
            _ => Integrator::Euler,
        },
        impratio: f(&o["impratio"]),
        viscosity: f(&o["viscosity"]),
        density: o.get("density").map_or(0.0, f),
        wind: o.get("wind").map_or([0.0; 3], v3),
        cone: match o.get("cone").and_then(Value::as_str) {
            Some("elliptic") => Cone::Elliptic,
            _ => Cone::Pyramidal,
        },
        ..Options::default()
    };
    let bodies = m["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
        .map(|(i, b)| Body {
            name: format!("body{i}"),
            parent: b["parent"].as_u64().unwrap() as usize,
            pos: v3(&b["pos"]),
            quat: q4(&b["quat"]),
            mass: f(&b["mass"]),
            ipos: v3(&b["ipos"]),
            iquat: q4(&b["iquat"]),
            inertia: v3(&b["inertia"]),
            dryfriction: 0.0,
        })
        .collect();
    let joints = m["joints"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
        .map(|(i, j)| {
            let kind = match j["kind"].as_str().unwrap() {
                "free" => JointKind::Free,
                "hinge" => JointKind::Hinge,
                _ => JointKind::Slide,
            };
            let mut jt = Joint::new(
                &format!("joint{i}"),
                j["body"].as_u64().unwrap() as usize,
                kind,
                v3(&j["axis"]),
            );
            jt.pos = v3(&j["pos"]);
            jt.armature = f(&j["armature"]);
            jt.damping = f(&j["damping"]);
            jt.stiffness = f(&j["stiffness"]);
            jt.springref = f(&j["springref"]);
            jt.qpos0 = f(&j["qpos0"]);
            jt.range = (!j["range"].is_null()).then(|| arr::<2>(&j["range"]));
            jt.margin = f(&j["margin"]);
            jt.solref_limit = arr(&j["solref"]);
            jt.solimp_limit = arr(&j["solimp"]);
            if !j["frictionloss"].is_null() {
                jt.frictionloss = f(&j["frictionloss"]);
                jt.solref_friction = arr(&j["solreffriction"]);
                jt.solimp_friction = arr(&j["solimpfriction"]);
            }
            jt
        })
        .collect();
    let geoms = m["geoms"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
        .map(|(i, g)| {
            let s = fs(&g["size"]);
            let shape = match g["shape"].as_str().unwrap() {
                "plane" => Shape::Plane,
                "sphere" => Shape::Sphere { radius: s[0] },
                "capsule" => Shape::Capsule {
                    radius: s[0],
                    half_length: s[1],
                },
                "cylinder" => Shape::Cylinder {
                    radius: s[0],
                    half_length: s[1],
                },
                "ellipsoid" => Shape::Ellipsoid {
                    radii: [s[0], s[1], s[2]],
                },
                _ => Shape::Box {
                    half: [s[0], s[1], s[2]],
                },
            };
            let mut geom = Geom::new(
                &format!("geom{i}"),
                g["body"].as_u64().unwrap() as usize,
                shape,
                v3(&g["pos"]),
            );
            geom.quat = q4(&g["quat"]);
            geom.contype = g["contype"].as_u64().unwrap() as u32;
            geom.conaffinity = g["conaffinity"].as_u64().unwrap() as u32;
            geom.condim = g["condim"].as_u64().unwrap() as u8;
            geom.friction = arr(&g["friction"]);
            geom.solmix = f(&g["solmix"]);
            geom.solref = arr(&g["solref"]);
            geom.solimp = arr(&g["solimp"]);
            geom.margin = f(&g["margin"]);
            geom.gap = f(&g["gap"]);
            geom
        })
        .collect();
    let actuators = m["actuators"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let mut act = Actuator::motor(
                &format!("act{i}"),
                a["joint"].as_u64().unwrap() as usize,
                f(&a["gear"]),
                (!a["ctrlrange"].is_null()).then(|| arr::<2>(&a["ctrlrange"])),
            );
            // MuJoCo's general actuators: the fields the script writes when not a plain motor.
            act.gain = a.get("gain").map_or(1.0, f);
            act.bias = a.get("bias").map_or([0.0; 3], arr);
            act.forcerange = a.get("forcerange").map(arr::<2>);
            act.actrange = a.get("actrange").map(arr::<2>);
            act.dynamics = match a.get("dyntype").and_then(Value::as_str) {
                Some("filter") => Dynamics::Filter { tau: f(&a["tau"]) },
                Some("filterexact") => Dynamics::FilterExact { tau: f(&a["tau"]) },
                _ => Dynamics::None,
            };
            act
        })
        .collect();
    let actuator_tendon = m["actuators"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a.get("tendon").map(|t| t.as_u64().unwrap() as usize))
        .collect();
    let tendons = m
        .get("tendons")
        .and_then(Value::as_array)
        .map(|ts| {
            ts.iter()
                .enumerate()
                .map(|(i, t)| {
                    let joints = t
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|jc| (jc[0].as_u64().unwrap() as usize, f(&jc[1])))
                        .collect();
                    let mut tendon = Tendon::fixed(&format!("tendon{i}"), joints);
                    if let Some(p) = m.get("tendon_passive").map(|p| &p[i]) {
                        tendon.stiffness = f(&p["stiffness"]);
                        tendon.damping = f(&p["damping"]);
                        tendon.lengthspring = Some(arr(&p["lengthspring"]));
                    }
                    tendon
                })
                .collect()
        })
        .unwrap_or_default();
    let equalities = m
        .get("tendon_equalities")
        .and_then(Value::as_array)
        .map(|es| {
            es.iter()
                .enumerate()
                .map(|(i, e)| TendonEquality {
                    name: format!("equality{i}"),
                    tendon1: e["tendon1"].as_u64().unwrap() as usize,
                    tendon2: e["tendon2"].as_u64().map(|t| t as usize),
                    polycoef: arr(&e["polycoef"]),
                    solref: arr(&e["solref"]),
                    solimp: arr(&e["solimp"]),
                })
                .collect()
        })
        .unwrap_or_default();
    Model::new(opt, bodies, joints, geoms, actuators)
        .and_then(|m| m.with_tendons(tendons, actuator_tendon))
        .and_then(|m| m.with_tendon_equalities(equalities))
        .expect("fixture model")
}

/// The fixtures' open-loop control (as the script's `control`).
pub fn control(t: f64, nu: usize, out: &mut [f64]) {
    for (a, u) in out.iter_mut().enumerate().take(nu) {
        *u = (2.0 * std::f64::consts::PI * 1.3 * t + 0.7 * a as f64).sin() * (0.6 + 0.1 * a as f64);
    }
}
