//! The context of a robot environment: Brax's physics parameters as CARL writes them
//! (`specs/shared/brax_physics.json`), the task's target features, and optional per-link
//! masses (`mass_<link>`).

use carl_env::api::UnknownFeature;

/// Context of a robot instance. Features a robot's spec does not have keep their defaults and,
/// where they are optional (`actuator_strength`, `torso_mass`), are `None` = "as the model".
#[derive(Debug, Clone, PartialEq)]
pub struct RobotParams {
    /// Vertical gravity (m/s²), negative = down.
    pub gravity: f64,
    pub friction: f64,
    /// Brax's global angular damping (1/s; negative damps).
    pub angular_damping: f64,
    /// Viscous damping of every hinge (N·m·s/rad).
    pub joint_angular_damping: f64,
    /// Joint-limit spring stiffness (N·m/rad on the side file's reference inertia).
    pub joint_stiffness: f64,
    /// Torque of a full-scale control relative to the side file's reference.
    pub actuator_strength: Option<f64>,
    /// Mass of the first URDF link (kg).
    pub torso_mass: Option<f64>,
    /// Restitution of contacts and end stops (0: inelastic, as MuJoCo's soft contacts).
    pub elasticity: f64,
    /// Viscosity of the surrounding medium (Pa·s, MuJoCo's `option viscosity`).
    pub viscosity: f64,
    pub target_distance: f64,
    pub target_radius: f64,
    /// carl-bench's compass code of the goal's direction (the locomotion robots' `goal` option,
    /// [`crate::goal`]).
    pub target_direction: f64,
    pub target_height: f64,
    /// Pusher's goal: x, y in the world and the height above the table (m).
    pub goal_position: [f64; 3],
    /// `mass_<link>` overrides (link name, kg).
    pub link_masses: Vec<(String, f64)>,
    /// The link names `mass_<link>` may name.
    pub known_links: Vec<String>,
    /// The model's mass of each of `known_links` (what `get("mass_<link>")` reports when the
    /// context does not override it); empty when the params were made without a model.
    pub model_masses: Vec<f64>,
    env: &'static str,
}

/// Canonical feature names and their aliases.
const NAMES: &[(&str, &[&str])] = &[
    ("gravity", &[]),
    ("friction", &[]),
    ("angular_damping", &["ang_damping"]),
    ("joint_angular_damping", &[]),
    ("joint_stiffness", &[]),
    ("actuator_strength", &[]),
    ("torso_mass", &["mass_torso"]),
    ("elasticity", &[]),
    ("viscosity", &[]),
    ("target_distance", &[]),
    ("target_radius", &[]),
    ("target_direction", &[]),
    ("target_height", &[]),
    ("goal_position_x", &[]),
    ("goal_position_y", &[]),
    ("goal_position_z", &[]),
];

/// `x`, or `fallback` where a context value is not finite (NaN, ±∞): the physics never sees one.
pub(crate) fn finite_or(x: f64, fallback: f64) -> f64 {
    if x.is_finite() { x } else { fallback }
}

impl RobotParams {
    /// Brax/CARL defaults of the shared fragment for `env` with the given link names.
    pub fn new(env: &'static str, known_links: Vec<String>) -> Self {
        RobotParams {
            gravity: -9.8,
            friction: 0.6,
            angular_damping: -0.05,
            joint_angular_damping: 20.0,
            joint_stiffness: 5000.0,
            actuator_strength: None,
            torso_mass: None,
            elasticity: 0.0,
            viscosity: 0.0,
            target_distance: 15.0,
            target_radius: 2.0,
            target_direction: 1.0,
            target_height: 8.0,
            goal_position: [0.45, 0.05, 0.05],
            link_masses: Vec::new(),
            known_links,
            model_masses: Vec::new(),
            env,
        }
    }

    /// [`RobotParams::new`] for a loaded model: its links and their URDF masses.
    pub fn for_model(env: &'static str, model: &super::RobotModel) -> Self {
        let mut p = RobotParams::new(env, model.link_names.clone());
        p.model_masses = model
            .link_names
            .iter()
            .map(|l| model.link_mass(l).unwrap_or(f64::NAN))
            .collect();
        p
    }

    fn canonical(name: &str) -> Option<&'static str> {
        NAMES
            .iter()
            .find(|(c, aliases)| *c == name || aliases.contains(&name))
            .map(|(c, _)| *c)
    }

    fn unknown(&self, name: &str) -> UnknownFeature {
        let mut known: Vec<String> = NAMES.iter().map(|(c, _)| c.to_string()).collect();
        known.extend(self.known_links.iter().map(|l| format!("mass_{l}")));
        UnknownFeature {
            env: self.env,
            name: name.to_string(),
            known: known.join(", "),
        }
    }

    /// Set a feature by canonical name, alias or `mass_<link>`.
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), UnknownFeature> {
        match Self::canonical(name) {
            Some("gravity") => self.gravity = value,
            Some("friction") => self.friction = value,
            Some("angular_damping") => self.angular_damping = value,
            Some("joint_angular_damping") => self.joint_angular_damping = value,
            Some("joint_stiffness") => self.joint_stiffness = value,
            Some("actuator_strength") => self.actuator_strength = Some(value),
            Some("torso_mass") => self.torso_mass = Some(value),
            Some("elasticity") => self.elasticity = value,
            Some("viscosity") => self.viscosity = value,
            Some("target_distance") => self.target_distance = value,
            Some("target_radius") => self.target_radius = value,
            Some("target_direction") => self.target_direction = value,
            Some("target_height") => self.target_height = value,
            Some("goal_position_x") => self.goal_position[0] = value,
            Some("goal_position_y") => self.goal_position[1] = value,
            Some("goal_position_z") => self.goal_position[2] = value,
            _ => {
                let link = name
                    .strip_prefix("mass_")
                    .filter(|l| self.known_links.iter().any(|k| k == l));
                let Some(link) = link else {
                    return Err(self.unknown(name));
                };
                match self.link_masses.iter_mut().find(|(l, _)| l == link) {
                    Some(entry) => entry.1 = value,
                    None => self.link_masses.push((link.to_string(), value)),
                }
            }
        }
        Ok(())
    }

    /// Read a feature (`NaN` for an optional feature left at a value only the model knows).
    pub fn get(&self, name: &str) -> Result<f64, UnknownFeature> {
        Ok(match Self::canonical(name) {
            Some("gravity") => self.gravity,
            Some("friction") => self.friction,
            Some("angular_damping") => self.angular_damping,
            Some("joint_angular_damping") => self.joint_angular_damping,
            Some("joint_stiffness") => self.joint_stiffness,
            Some("actuator_strength") => self.actuator_strength.unwrap_or(f64::NAN),
            Some("torso_mass") => self.torso_mass.unwrap_or(f64::NAN),
            Some("elasticity") => self.elasticity,
            Some("viscosity") => self.viscosity,
            Some("target_distance") => self.target_distance,
            Some("target_radius") => self.target_radius,
            Some("target_direction") => self.target_direction,
            Some("target_height") => self.target_height,
            Some("goal_position_x") => self.goal_position[0],
            Some("goal_position_y") => self.goal_position[1],
            Some("goal_position_z") => self.goal_position[2],
            _ => {
                let link = name.strip_prefix("mass_").ok_or_else(|| self.unknown(name))?;
                let Some(i) = self.known_links.iter().position(|k| k == link) else {
                    return Err(self.unknown(name));
                };
                let model = self.model_masses.get(i).copied().unwrap_or(f64::NAN);
                self.link_masses
                    .iter()
                    .find(|(l, _)| l == link)
                    .map_or(model, |(_, v)| *v)
            }
        })
    }
}
