//! The context options shared by the commands that run an environment (`rollout`, `render`):
//! `--context NAME=VALUE`, `--instance-set ENV/SET [--instance I]`, `--allow-out-of-bounds`.

use clap::Args;

use super::{Cli, Failure, load_specs};
use crate::envs::registry::{Context, RUNTIMES, has_runtime};
use crate::instances::Store;
use crate::spec::SpecSet;
use crate::spec::model::{EnvSpec, Value};

#[derive(Args, Debug, Clone, Default)]
pub struct ContextArgs {
    /// Set a context feature, e.g. `--context gravity=3.7` (repeatable; canonical names or aliases).
    #[arg(long = "context", value_name = "NAME=VALUE")]
    pub context: Vec<String>,
    /// Take the context from a frozen instance set (ENV/SET); `--context` values override it.
    #[arg(long, value_name = "ENV/SET")]
    pub instance_set: Option<String>,
    /// Index of the instance within `--instance-set` (default 0).
    #[arg(long, value_name = "I")]
    pub instance: Option<usize>,
    /// Accept context values outside the spec's bounds.
    #[arg(long)]
    pub allow_out_of_bounds: bool,
}

/// What the options resolve to: the spec set, the environment's spec, the context and whether
/// out-of-bounds values are accepted (asked for, or declared by the instance set).
pub struct Resolved {
    pub specs: SpecSet,
    pub spec: EnvSpec,
    pub context: Context,
    pub allow_out_of_bounds: bool,
}

impl ContextArgs {
    /// Resolve against environment `env`, which must have a runtime (`what` names the command
    /// in the error).
    pub fn resolve(&self, cli: &Cli, env: &str, what: &str) -> Result<Resolved, Failure> {
        let specs = load_specs(cli)?;
        let spec = specs.require(env).map_err(Failure::usage)?.clone();
        if !has_runtime(&spec.id) {
            return Err(Failure::usage(format!(
                "{} has a spec but no runtime yet; {what} works for: {}",
                spec.id,
                RUNTIMES.join(", ")
            )));
        }
        let mut ctx = Context::new();
        let mut allow = self.allow_out_of_bounds;
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
                allow |= set.provenance.definition.allow_out_of_bounds;
            }
            (None, Some(_)) => return Err(Failure::usage("--instance needs --instance-set ENV/SET")),
            (None, None) => {}
        }
        for kv in &self.context {
            let (k, v) = kv
                .split_once('=')
                .ok_or_else(|| Failure::usage(format!("--context expects NAME=VALUE, got \"{kv}\"")))?;
            let x: f64 = v
                .trim()
                .parse()
                .map_err(|_| Failure::usage(format!("--context {k}: \"{v}\" is not a number")))?;
            ctx.insert(k.trim().to_string(), Value::Number(x));
        }
        Ok(Resolved {
            specs,
            spec,
            context: ctx,
            allow_out_of_bounds: allow,
        })
    }
}
