//! dm_control's models as MuJoCo compiles them (`models/<domain>.json`, written by
//! `scripts/dmc_models.py` from dm_control's own XML: the fields of `mjModel` the engine needs,
//! with names) and their loading into a [`carl_articulated::Model`].
//!
//! The family's context features that act the same way in every domain enter through
//! [`Physics`]: each is applied to the compiled model, as carl-bench 1.1.1 applies them to the
//! XML (`carl/envs/dmc/dmc_tasks/utils.py`, `adapt_context`), bugs fixed:
//! * `timestep`: the physics step (see [`substeps`] for how it meets the control step);
//! * `joint_damping`, `joint_stiffness`: multiply every joint's and tendon's damping and
//!   stiffness;
//! * `actuator_strength`: multiplies every actuator's force (a motor's gear, as carl-bench; a
//!   servo's gain, bias and force range, so its target stays the control);
//! * `friction_tangential`, `friction_torsional`, `friction_rolling`: multiply every geom's
//!   sliding, torsional and rolling friction (only the sliding one acts under condim 3);
//! * `density`, `viscosity`, `wind_x/y/z`: MuJoCo's medium (its inertia-box fluid model);
//! * `geom_density`: multiplies the mass and inertia of every body whose mass comes from its
//!   geoms' density (MuJoCo's 1000 kg/m³ unless the XML says otherwise);
//! * gravity: the domain decides (its XML may disable it).
//!
//! The XML's `<flag contact="disable"/>` removes contacts, `<flag constraint="disable"/>`
//! contacts and joint limits; geoms of shapes the engine cannot collide (ellipsoids) are left
//! out of the engine's model when nothing collides with them (find geoms by name in the
//! built model: its indices are then not the file's).

use carl_articulated::model::{
    Actuator, Body, Cone, Dynamics, Geom, Integrator, Joint, JointKind, Model, Options, Shape, SolImp, SolRef, Tendon,
    TendonEquality,
};
use serde::Deserialize;

/// A compiled model file.
#[derive(Debug, Clone, Deserialize)]
pub struct ModelFile {
    pub source: String,
    pub model: Desc,
}

#[derive(Debug, Clone, Deserialize)]
pub struct OptDesc {
    pub timestep: f64,
    pub gravity: [f64; 3],
    pub integrator: String,
    pub impratio: f64,
    pub viscosity: f64,
    pub density: f64,
    pub wind: [f64; 3],
    /// `false`: the XML disables contacts.
    pub contact: bool,
    /// `false`: the XML disables every constraint (contacts and joint limits).
    #[serde(default = "yes")]
    pub constraint: bool,
    pub gravity_disabled: bool,
    /// MuJoCo's friction cone (`"elliptic"`; absent: pyramidal).
    #[serde(default)]
    pub cone: Option<String>,
}

#[derive(Debug, Clone, Deserialize)]
pub struct BodyDesc {
    pub parent: usize,
    pub pos: [f64; 3],
    pub quat: [f64; 4],
    pub mass: f64,
    pub ipos: [f64; 3],
    pub iquat: [f64; 4],
    pub inertia: [f64; 3],
}

#[derive(Debug, Clone, Deserialize)]
pub struct JointDesc {
    pub kind: String,
    pub body: usize,
    pub pos: [f64; 3],
    pub axis: [f64; 3],
    pub armature: f64,
    pub damping: f64,
    pub stiffness: f64,
    pub springref: f64,
    pub qpos0: f64,
    pub range: Option<[f64; 2]>,
    pub margin: f64,
    pub solref: SolRef,
    pub solimp: SolImp,
    /// MuJoCo's `frictionloss` (dry friction) and its `solreffriction` / `solimpfriction`.
    #[serde(default)]
    pub frictionloss: f64,
    #[serde(default)]
    pub solreffriction: Option<SolRef>,
    #[serde(default)]
    pub solimpfriction: Option<SolImp>,
}

#[derive(Debug, Clone, Deserialize)]
pub struct GeomDesc {
    pub body: usize,
    pub shape: String,
    pub size: [f64; 3],
    pub pos: [f64; 3],
    pub quat: [f64; 4],
    pub contype: u32,
    pub conaffinity: u32,
    pub condim: u8,
    pub friction: [f64; 3],
    pub solmix: f64,
    pub solref: SolRef,
    pub solimp: SolImp,
    pub margin: f64,
    pub gap: f64,
}

/// An actuator: MuJoCo's `<general>` fields (a plain motor's are left out of the file: gain
/// 1, no bias, no dynamics, no force or activation range).
#[derive(Debug, Clone, Deserialize)]
pub struct ActDesc {
    pub joint: usize,
    pub gear: f64,
    pub ctrlrange: Option<[f64; 2]>,
    #[serde(default)]
    pub tendon: Option<usize>,
    /// `gainprm[0]` (gain type fixed).
    #[serde(default = "one")]
    pub gain: f64,
    /// `biasprm[0..3]` (bias type affine; zeros: none).
    #[serde(default)]
    pub bias: [f64; 3],
    #[serde(default)]
    pub forcerange: Option<[f64; 2]>,
    #[serde(default)]
    pub actrange: Option<[f64; 2]>,
    /// `none`, `filter` or `filterexact`, with its time constant `tau` (`dynprm[0]`).
    #[serde(default)]
    pub dyntype: Option<String>,
    #[serde(default)]
    pub tau: f64,
}

fn one() -> f64 {
    1.0
}

fn yes() -> bool {
    true
}

/// A tendon's passive spring and damper (MuJoCo's `tendon_stiffness`, `tendon_damping`,
/// `tendon_lengthspring`).
#[derive(Debug, Clone, Deserialize)]
pub struct TendonPassive {
    pub stiffness: f64,
    pub damping: f64,
    pub lengthspring: [f64; 2],
}

/// A tendon equality (`<equality><tendon>`).
#[derive(Debug, Clone, Deserialize)]
pub struct EqDesc {
    pub tendon1: usize,
    pub tendon2: Option<usize>,
    pub polycoef: [f64; 5],
    pub solref: SolRef,
    pub solimp: SolImp,
}

/// A site: a named frame of a body (the sensors' frames).
#[derive(Debug, Clone, Deserialize)]
pub struct SiteDesc {
    pub name: String,
    pub body: usize,
    pub pos: [f64; 3],
    pub quat: [f64; 4],
}

#[derive(Debug, Clone, Deserialize)]
pub struct Names {
    pub bodies: Vec<String>,
    pub joints: Vec<String>,
    pub geoms: Vec<String>,
    pub actuators: Vec<String>,
    pub tendons: Vec<String>,
}

/// The compiled model: `mjModel`'s fields.
#[derive(Debug, Clone, Deserialize)]
pub struct Desc {
    pub opt: OptDesc,
    pub bodies: Vec<BodyDesc>,
    pub joints: Vec<JointDesc>,
    pub geoms: Vec<GeomDesc>,
    pub actuators: Vec<ActDesc>,
    /// `(joint, coef)` of each fixed tendon.
    #[serde(default)]
    pub tendons: Vec<Vec<(usize, f64)>>,
    /// Each tendon's passive spring and damper (absent: none has any).
    #[serde(default)]
    pub tendon_passive: Vec<TendonPassive>,
    pub names: Names,
    /// Whether each body's mass comes from its geoms' density (no geom of it states a mass).
    #[serde(default)]
    pub body_mass_from_density: Vec<bool>,
    #[serde(default)]
    pub tendon_equalities: Vec<EqDesc>,
    #[serde(default)]
    pub sites: Vec<SiteDesc>,
}

impl Desc {
    /// Parse a model file's text.
    pub fn parse(text: &str) -> Result<Desc, String> {
        let file: ModelFile = serde_json::from_str(text).map_err(|e| e.to_string())?;
        let d = file.model;
        let n = &d.names;
        if n.bodies.len() != d.bodies.len()
            || n.joints.len() != d.joints.len()
            || n.geoms.len() != d.geoms.len()
            || n.actuators.len() != d.actuators.len()
            || n.tendons.len() != d.tendons.len()
            || !(d.tendon_passive.is_empty() || d.tendon_passive.len() == d.tendons.len())
        {
            return Err("names do not match the model's elements".into());
        }
        Ok(d)
    }
    pub fn body(&self, name: &str) -> Option<usize> {
        self.names.bodies.iter().position(|n| n == name)
    }
    pub fn joint(&self, name: &str) -> Option<usize> {
        self.names.joints.iter().position(|n| n == name)
    }
    pub fn geom(&self, name: &str) -> Option<usize> {
        self.names.geoms.iter().position(|n| n == name)
    }
    /// The site called `name` as the engine's [`carl_articulated::Site`].
    pub fn site(&self, name: &str) -> Option<carl_articulated::Site> {
        let s = self.sites.iter().find(|s| s.name == name)?;
        Some(carl_articulated::Site {
            body: s.body,
            pos: s.pos,
            mat: carl_articulated::math::quat_to_mat(s.quat),
        })
    }
}

/// carl-bench's 14 physics features of every dm_control environment (the `dmc_physics` spec
/// fragment), in its order: each environment's `Params` holds them and its own.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Common {
    pub gravity: f64,
    pub friction_torsional: f64,
    pub friction_rolling: f64,
    pub friction_tangential: f64,
    pub timestep: f64,
    pub joint_damping: f64,
    pub joint_stiffness: f64,
    pub actuator_strength: f64,
    pub density: f64,
    pub viscosity: f64,
    pub geom_density: f64,
    pub wind_x: f64,
    pub wind_y: f64,
    pub wind_z: f64,
}

impl Common {
    /// dm_control's model values with the physics step `timestep` (gravity 9.81 down).
    pub const fn dm_control(timestep: f64) -> Common {
        Common {
            gravity: 9.81,
            friction_torsional: 1.0,
            friction_rolling: 1.0,
            friction_tangential: 1.0,
            timestep,
            joint_damping: 1.0,
            joint_stiffness: 1.0,
            actuator_strength: 1.0,
            density: 0.0,
            viscosity: 0.0,
            geom_density: 1.0,
            wind_x: 0.0,
            wind_y: 0.0,
            wind_z: 0.0,
        }
    }

    /// The feature called `name`, if it is one of these.
    pub fn slot(&mut self, name: &str) -> Option<&mut f64> {
        Some(match name {
            "gravity" => &mut self.gravity,
            "friction_torsional" => &mut self.friction_torsional,
            "friction_rolling" => &mut self.friction_rolling,
            "friction_tangential" => &mut self.friction_tangential,
            "timestep" => &mut self.timestep,
            "joint_damping" => &mut self.joint_damping,
            "joint_stiffness" => &mut self.joint_stiffness,
            "actuator_strength" => &mut self.actuator_strength,
            "density" => &mut self.density,
            "viscosity" => &mut self.viscosity,
            "geom_density" => &mut self.geom_density,
            "wind_x" => &mut self.wind_x,
            "wind_y" => &mut self.wind_y,
            "wind_z" => &mut self.wind_z,
            _ => return None,
        })
    }

    /// The engine's options and multipliers for a control step of `control` s, with gravity
    /// `gravity` (the environment decides how its `gravity` feature enters).
    pub fn physics(&self, control: f64, gravity: [f64; 3]) -> Physics {
        Physics {
            gravity,
            friction: [self.friction_tangential, self.friction_torsional, self.friction_rolling],
            timestep: substeps(control, self.timestep).1,
            joint_damping: self.joint_damping,
            joint_stiffness: self.joint_stiffness,
            actuator_strength: self.actuator_strength,
            density: self.density,
            viscosity: self.viscosity,
            wind: [self.wind_x, self.wind_y, self.wind_z],
            geom_density: self.geom_density,
        }
    }
}

/// The family's common physics features (see the module doc), as multipliers and absolute
/// values over the compiled model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Physics {
    pub gravity: [f64; 3],
    /// Multipliers of (sliding, torsional, rolling) friction.
    pub friction: [f64; 3],
    pub timestep: f64,
    pub joint_damping: f64,
    pub joint_stiffness: f64,
    pub actuator_strength: f64,
    pub density: f64,
    pub viscosity: f64,
    pub wind: [f64; 3],
    /// Multiplier of the mass and inertia of the bodies whose mass comes from density.
    pub geom_density: f64,
}

/// The engine model of `desc` under `p`, or why it cannot be built.
pub fn build(desc: &Desc, p: &Physics) -> Result<Model, String> {
    let o = &desc.opt;
    let opt = Options {
        timestep: p.timestep,
        gravity: p.gravity,
        integrator: if o.integrator == "rk4" {
            Integrator::Rk4
        } else {
            Integrator::Euler
        },
        impratio: o.impratio,
        viscosity: p.viscosity,
        density: p.density,
        wind: p.wind,
        cone: if o.cone.as_deref() == Some("elliptic") {
            Cone::Elliptic
        } else {
            Cone::Pyramidal
        },
        ..Options::default()
    };
    let bodies = desc
        .bodies
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let k = if desc.body_mass_from_density.get(i).copied().unwrap_or(false) {
                p.geom_density
            } else {
                1.0
            };
            Body {
                name: desc.names.bodies[i].clone(),
                parent: b.parent,
                pos: b.pos,
                quat: b.quat,
                mass: b.mass * k,
                ipos: b.ipos,
                iquat: b.iquat,
                inertia: b.inertia.map(|x| x * k),
                dryfriction: 0.0,
            }
        })
        .collect();
    let mut joints = Vec::with_capacity(desc.joints.len());
    for (i, j) in desc.joints.iter().enumerate() {
        let kind = match j.kind.as_str() {
            "free" => JointKind::Free,
            "hinge" => JointKind::Hinge,
            "slide" => JointKind::Slide,
            other => return Err(format!("joint {}: unknown kind {other}", desc.names.joints[i])),
        };
        let mut jt = Joint::new(&desc.names.joints[i], j.body, kind, j.axis);
        jt.pos = j.pos;
        jt.armature = j.armature;
        jt.damping = j.damping * p.joint_damping;
        jt.stiffness = j.stiffness * p.joint_stiffness;
        jt.springref = j.springref;
        jt.qpos0 = j.qpos0;
        // `<flag constraint="disable"/>`: no limit acts.
        jt.range = if o.constraint { j.range } else { None };
        jt.margin = j.margin;
        jt.solref_limit = j.solref;
        jt.solimp_limit = j.solimp;
        jt.frictionloss = j.frictionloss;
        if let Some(r) = j.solreffriction {
            jt.solref_friction = r;
        }
        if let Some(r) = j.solimpfriction {
            jt.solimp_friction = r;
        }
        joints.push(jt);
    }
    let mut geoms = Vec::with_capacity(desc.geoms.len());
    for (i, g) in desc.geoms.iter().enumerate() {
        let s = g.size;
        let shape = match g.shape.as_str() {
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
            "box" => Shape::Box { half: s },
            "ellipsoid" => Shape::Ellipsoid { radii: s },
            other => return Err(format!("geom {}: unsupported shape {other}", desc.names.geoms[i])),
        };
        let mut geom = Geom::new(&desc.names.geoms[i], g.body, shape, g.pos);
        geom.quat = g.quat;
        // `<flag contact="disable"/>`: no geom collides.
        (geom.contype, geom.conaffinity) = if o.contact && o.constraint {
            (g.contype, g.conaffinity)
        } else {
            (0, 0)
        };
        geom.condim = g.condim;
        geom.friction = [
            g.friction[0] * p.friction[0],
            g.friction[1] * p.friction[1],
            g.friction[2] * p.friction[2],
        ];
        geom.solmix = g.solmix;
        geom.solref = g.solref;
        geom.solimp = g.solimp;
        geom.margin = g.margin;
        geom.gap = g.gap;
        geoms.push(geom);
    }
    let actuators = desc
        .actuators
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let dynamics = match a.dyntype.as_deref() {
                None | Some("none") => Dynamics::None,
                Some("filter") => Dynamics::Filter { tau: a.tau },
                Some("filterexact") => Dynamics::FilterExact { tau: a.tau },
                Some(other) => {
                    return Err(format!(
                        "actuator {}: unsupported dyntype {other}",
                        desc.names.actuators[i]
                    ));
                }
            };
            // The strength scales the force: a motor's gear (as carl-bench), a servo's gain and
            // bias (its target stays the control; scaling its gear would move the target).
            let s = p.actuator_strength;
            let motor = a.bias == [0.0; 3];
            Ok(Actuator {
                gain: if motor { a.gain } else { a.gain * s },
                bias: if motor { a.bias } else { a.bias.map(|b| b * s) },
                forcerange: a.forcerange.map(|r| if motor { r } else { r.map(|x| x * s) }),
                actrange: a.actrange,
                dynamics,
                ..Actuator::motor(
                    &desc.names.actuators[i],
                    a.joint,
                    if motor { a.gear * s } else { a.gear },
                    a.ctrlrange,
                )
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    let tendons = desc
        .tendons
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let mut tendon = Tendon::fixed(&desc.names.tendons[i], t.clone());
            if let Some(tp) = desc.tendon_passive.get(i) {
                tendon.stiffness = tp.stiffness * p.joint_stiffness;
                tendon.damping = tp.damping * p.joint_damping;
                tendon.lengthspring = Some(tp.lengthspring);
            }
            tendon
        })
        .collect();
    let actuator_tendon = desc.actuators.iter().map(|a| a.tendon).collect();
    let equalities = desc
        .tendon_equalities
        .iter()
        .enumerate()
        .map(|(i, e)| TendonEquality {
            name: format!("equality {i}"),
            tendon1: e.tendon1,
            tendon2: e.tendon2,
            polycoef: e.polycoef,
            solref: e.solref,
            solimp: e.solimp,
        })
        .collect();
    Model::new(opt, bodies, joints, geoms, actuators)
        .and_then(|m| m.with_tendons(tendons, actuator_tendon))
        .and_then(|m| m.with_tendon_equalities(equalities))
        .map_err(|e| e.to_string())
}

/// Physics steps per control step and their length: the control step `control` is kept, cut
/// into the fewest equal steps no longer than `timestep` (so any time step works, where
/// dm_control raises unless it divides the control step); a `timestep` longer than the control
/// step is one physics step of that length per action.
pub fn substeps(control: f64, timestep: f64) -> (usize, f64) {
    if timestep >= control {
        return (1, timestep);
    }
    let n = (control / timestep - 1e-9).ceil().max(1.0);
    (n as usize, control / n)
}

#[cfg(test)]
mod tests {
    use super::substeps;

    #[test]
    fn substeps_keep_the_control_step() {
        assert_eq!(substeps(0.02, 0.02), (1, 0.02));
        let (n, h) = substeps(0.02, 0.004);
        assert_eq!(n, 5);
        assert!((h - 0.004).abs() < 1e-15);
        let (n, h) = substeps(0.02, 0.015);
        assert_eq!(n, 2);
        assert!((h - 0.01).abs() < 1e-15);
        assert_eq!(substeps(0.02, 0.05), (1, 0.05));
    }
}
