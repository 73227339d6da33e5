//! The options shared by the commands that run an environment (`rollout`, `render`):
//! `--context NAME=VALUE`, `--instance-set ENV/SET [--instance I]`, `--allow-out-of-bounds`,
//! `--option NAME=VALUE`, `--obs-context NAME`, `--noise NAME=STD[%]`, `--noise-redraw`,
//! `--schedule NAME=JSON`, and `--policy`.

use clap::{Args, ValueEnum};

use super::{Cli, Failure, load_specs};
use crate::envs::Env;
use crate::envs::contextual::{
    ContextNoise, ContextSource, ContextualEnv, ContextualOptions, Features, NoiseRedraw, NoiseStd, Visibility,
};
use crate::envs::policy::PolicyKind;
use crate::envs::registry::{
    Context, EnvOptions, MakeOptions, Registration, ids_text, lookup, make_env, resolve_context,
};
use crate::envs::schedules::{Schedule, parse_schedules};
use crate::episode::jsonl::quote_input;
use crate::instances::Store;
use crate::spec::SpecSet;
use crate::spec::model::{EnvSpec, Value};

#[derive(Args, Debug, Clone, Default)]
pub struct ContextArgs {
    /// Set a context feature, e.g. `--context gravity=3.7` or `--context VEHICLE=Bus` (a choice's
    /// label); repeatable; canonical names or aliases.
    #[arg(long = "context", value_name = "NAME=VALUE")]
    pub context: Vec<String>,
    /// Take the context from a frozen instance set (ENV/SET); `--context` values override it.
    #[arg(long, value_name = "ENV/SET")]
    pub instance_set: Option<String>,
    /// Index of the instance within `--instance-set` (default 0).
    #[arg(long, value_name = "I")]
    pub instance: Option<usize>,
    /// Accept `--context` values outside the spec's bounds (an instance set that declares
    /// out-of-bounds instances runs them without this flag; its overrides still need it).
    #[arg(long)]
    pub allow_out_of_bounds: bool,
    /// A variant option of the environment, e.g. `--option continuous=true` (LunarLander),
    /// `--option hardcore=true` (BipedalWalker), `--option target_structure_ids=1,5,17`
    /// (rna_design's targets); repeatable.
    #[arg(long = "option", value_name = "NAME=VALUE")]
    pub options: Vec<String>,
    /// Append this context feature to the observation (repeatable; `all` for every feature).
    #[arg(long = "obs-context", value_name = "NAME")]
    pub obs_context: Vec<String>,
    /// Observe a visible feature with Gaussian noise: `NAME=STD` (feature's unit) or
    /// `NAME=STD%` (of |default|); the dynamics keep the true value. Repeatable.
    #[arg(long = "noise", value_name = "NAME=STD[%]")]
    pub noise: Vec<String>,
    /// When noise is drawn anew.
    #[arg(long, value_enum, default_value_t = RedrawArg::Episode)]
    pub noise_redraw: RedrawArg,
    /// Change a dynamics feature within the episode: `NAME=JSON`, e.g.
    /// `--schedule 'g={"kind": "sine", "amplitude": 2, "period": 100}'`; kinds `step {at, to}`,
    /// `linear {to, over}`, `sine {amplitude, period, phase}`, `random_walk {std, low, high}`
    /// (steps count from the reset). Repeatable.
    #[arg(long = "schedule", value_name = "NAME=JSON")]
    pub schedules: Vec<String>,
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum, Default)]
pub enum RedrawArg {
    /// Once per episode (a consistently wrong measurement).
    #[default]
    Episode,
    /// At every step (a noisy sensor).
    Step,
}

/// `--policy`: the same three for every command that runs episodes.
#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
pub enum PolicyArg {
    /// Uniform over the action space, seeded with `--seed`.
    Random,
    /// Action 0 (discrete) or all zeros (continuous).
    Noop,
    /// The environment's built-in controller (lunar_lander, bipedal_walker: Gymnasium's heuristics).
    Heuristic,
}

impl From<PolicyArg> for PolicyKind {
    fn from(p: PolicyArg) -> Self {
        match p {
            PolicyArg::Random => PolicyKind::Random,
            PolicyArg::Noop => PolicyKind::Noop,
            PolicyArg::Heuristic => PolicyKind::Heuristic,
        }
    }
}

/// What the options resolve to.
pub struct Resolved {
    pub specs: SpecSet,
    pub spec: EnvSpec,
    pub registration: &'static Registration,
    pub context: Context,
    /// Out-of-bounds values are accepted (asked for, or declared by the instance set).
    pub allow_out_of_bounds: bool,
    pub env_options: EnvOptions,
    pub visibility: Visibility,
    pub noise: ContextNoise,
    pub schedules: Vec<(String, Schedule)>,
}

impl Resolved {
    fn make_options(&self) -> MakeOptions {
        MakeOptions {
            allow_out_of_bounds: self.allow_out_of_bounds,
        }
    }

    /// Every feature's value (defaults filled in), canonical names in spec order.
    pub fn full_context(&self) -> Result<Vec<(String, f64)>, Failure> {
        resolve_context(&self.spec, &self.context, self.make_options()).map_err(|e| Failure::usage(e.to_string()))
    }

    /// Whether the context is part of the observation or changes within the episode (then the
    /// contextual wrapper runs).
    pub fn observes_context(&self) -> bool {
        self.visibility != Visibility::Hidden || !self.schedules.is_empty()
    }

    /// The environment: the runtime itself, or, when context is observed, CARL's contextual
    /// wrapper around it (whose seeding derives the runtime's reset seed from `--seed`).
    pub fn build(&self) -> Result<Box<dyn Env>, Failure> {
        if !self.observes_context() {
            let env = make_env(&self.spec, &self.context, self.make_options(), &self.env_options)
                .map_err(|e| Failure::usage(e.to_string()))?;
            return Ok(Box::new(env));
        }
        let opts = ContextualOptions {
            visibility: self.visibility.clone(),
            noise: self.noise.clone(),
            env_options: self.env_options.clone(),
            allow_out_of_bounds: self.allow_out_of_bounds,
            schedules: self.schedules.clone(),
            ..ContextualOptions::default()
        };
        let env = ContextualEnv::new(&self.spec, ContextSource::Fixed(self.context.clone()), opts)
            .map_err(|e| Failure::usage(e.to_string()))?;
        Ok(Box::new(env))
    }
}

/// `NAME=VALUE` split, or a usage error naming the flag.
pub(super) fn split_kv<'a>(flag: &str, kv: &'a str) -> Result<(&'a str, &'a str), Failure> {
    kv.split_once('=')
        .map(|(k, v)| (k.trim(), v.trim()))
        .ok_or_else(|| Failure::usage(format!("{flag} expects NAME=VALUE, got \"{}\"", quote_input(kv))))
}

/// A value as typed: a number, `true`/`false`, or text (a categorical choice's label).
pub(super) fn parse_value(v: &str) -> Value {
    match v {
        "true" => Value::Bool(true),
        "false" => Value::Bool(false),
        _ => v
            .parse::<f64>()
            .map_or_else(|_| Value::String(v.to_string()), Value::Number),
    }
}

impl ContextArgs {
    /// Resolve against environment `env`, which must have a runtime (`what` names the command
    /// in the error).
    pub fn resolve(&self, cli: &Cli, env: &str, what: &str) -> Result<Resolved, Failure> {
        let specs = load_specs(cli)?;
        let spec = specs.require(env).map_err(Failure::usage)?.clone();
        let Some(registration) = lookup(&spec.id) else {
            return Err(Failure::usage(format!(
                "{} has a spec but no runtime yet; {what} works for: {}",
                spec.id,
                ids_text()
            )));
        };
        let mut ctx = Context::new();
        let mut set_allows = false;
        match (&self.instance_set, self.instance) {
            (Some(name), i) => {
                let store = Store::new(&specs);
                let set = store.load(name).map_err(|e| Failure::usage(e.to_string()))?;
                if set.env != spec.id {
                    return Err(Failure::usage(format!(
                        "instance set {name} belongs to {}, not {}",
                        set.env, spec.id
                    )));
                }
                let i = i.unwrap_or(0);
                let inst = set.instances.get(i).ok_or_else(|| {
                    Failure::usage(format!(
                        "{name} has {} instances (0..{}); no instance {i}",
                        set.instances.len(),
                        set.instances.len()
                    ))
                })?;
                ctx.extend(inst.context.clone());
                // A set that deliberately goes out of bounds (e.g. Jupiter) is runnable as declared.
                set_allows = set.provenance.definition.allow_out_of_bounds;
            }
            (None, Some(_)) => return Err(Failure::usage("--instance needs --instance-set ENV/SET")),
            (None, None) => {}
        }
        let mut overrides = Context::new();
        for kv in &self.context {
            let (k, v) = split_kv("--context", kv)?;
            overrides.insert(k.to_string(), parse_value(v));
        }
        // The set's permission covers its own values only: overrides are checked on their own.
        let own = MakeOptions {
            allow_out_of_bounds: self.allow_out_of_bounds,
        };
        resolve_context(&spec, &overrides, own).map_err(|e| Failure::usage(e.to_string()))?;
        ctx.extend(overrides);

        let mut env_options = EnvOptions::new();
        for kv in &self.options {
            let (k, v) = split_kv("--option", kv)?;
            env_options.insert(k.to_string(), parse_value(v));
        }
        let visibility = match self.obs_context.as_slice() {
            [] => Visibility::Hidden,
            [all] if all == "all" => Visibility::Visible(Features::All),
            names => Visibility::Visible(Features::Only(names.to_vec())),
        };
        let mut noise = ContextNoise {
            features: Vec::new(),
            redraw: match self.noise_redraw {
                RedrawArg::Episode => NoiseRedraw::Episode,
                RedrawArg::Step => NoiseRedraw::Step,
            },
        };
        for kv in &self.noise {
            let (k, v) = split_kv("--noise", kv)?;
            let (num, relative) = match v.strip_suffix('%') {
                Some(p) => (p, true),
                None => (v, false),
            };
            let x: f64 = num.trim().parse().map_err(|_| {
                Failure::usage(format!(
                    "--noise {k}: \"{}\" is not a number or a percentage",
                    quote_input(v)
                ))
            })?;
            noise.features.push((
                k.to_string(),
                if relative {
                    NoiseStd::Relative(x / 100.0)
                } else {
                    NoiseStd::Absolute(x)
                },
            ));
        }
        if !noise.is_empty() && visibility == Visibility::Hidden {
            return Err(Failure::usage(
                "--noise applies to observed context features: add --obs-context NAME (or --obs-context all)",
            ));
        }
        let mut schedules = Vec::new();
        for kv in &self.schedules {
            let (k, v) = split_kv("--schedule", kv)?;
            let one = parse_schedules(&format!("{{{}: {v}}}", serde_json::Value::from(k)))
                .map_err(|e| Failure::usage(format!("--schedule {e}")))?;
            schedules.extend(one);
        }
        Ok(Resolved {
            specs,
            spec,
            registration,
            context: ctx,
            allow_out_of_bounds: self.allow_out_of_bounds || set_allows,
            env_options,
            visibility,
            noise,
            schedules,
        })
    }
}
