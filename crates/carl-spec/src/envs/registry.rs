//! The registry: every environment family's registrations in one table, and `make`.
//!
//! Each family crate declares its environments ([`Registration`]s, see
//! [`carl_env::registration`]); this table joins them in a fixed order. Everything that runs
//! environments (the CLI's `rollout`, `render`, `bench`, `audit`, the contextual wrapper,
//! [`VecEnv`](super::vec_env::VecEnv), the Python package) reads it.
//!
//! [`make`] checks every context name and value against the environment's spec (unknown names
//! and out-of-bounds values are errors unless explicitly allowed), writes them into the runtime's
//! `Params`, and wraps the result in the spec's episode limit. Nothing is shared between
//! environments: each owns its `Params`.

use super::api::TimeLimit;
use super::runtime::AnyEnv;
use crate::spec::model::EnvSpec;

pub use carl_env::context::{
    Context, EnvOptions, MakeError, MakeOptions, OptionKind, OptionSpec, OptionValues, check_option_features,
    resolve_context, resolve_options,
};
pub use carl_env::registration::{AuditProfile, BuildFn, HeuristicFn, Registration, StepCost, VectorKernel};

/// A runtime environment as `make` returns it: the spec's episode limit around the dynamics.
pub type SpecEnv = TimeLimit<AnyEnv>;

/// The families, in registry order.
const FAMILIES: &[&[Registration]] = &[
    carl_envs_classic_control::REGISTRATIONS,
    carl_envs_box2d::REGISTRATIONS,
    carl_envs_brax::REGISTRATIONS,
    carl_envs_dmc::REGISTRATIONS,
    carl_envs_rna_design::REGISTRATIONS,
    carl_envs_mario::REGISTRATIONS,
];

const LEN: usize = {
    let mut n = 0;
    let mut i = 0;
    while i < FAMILIES.len() {
        n += FAMILIES[i].len();
        i += 1;
    }
    n
};

const TABLE: [Registration; LEN] = {
    let mut out = [FAMILIES[0][0]; LEN];
    let (mut k, mut i) = (0, 0);
    while i < FAMILIES.len() {
        let mut j = 0;
        while j < FAMILIES[i].len() {
            out[k] = FAMILIES[i][j];
            k += 1;
            j += 1;
        }
        i += 1;
    }
    out
};

/// Every runtime of carl-spec, family by family.
pub static REGISTRY: &[Registration] = &TABLE;

/// The registration of environment `id` (a spec id, not an alias).
pub fn lookup(id: &str) -> Option<&'static Registration> {
    REGISTRY.iter().find(|r| r.id == id)
}

/// Whether `id` has a runtime.
pub fn has_runtime(id: &str) -> bool {
    lookup(id).is_some()
}

/// Ids of every runtime, in table order.
pub fn ids() -> impl Iterator<Item = &'static str> {
    REGISTRY.iter().map(|r| r.id)
}

/// `"cartpole, pendulum, …"`: for messages.
pub fn ids_text() -> String {
    ids().collect::<Vec<_>>().join(", ")
}

/// Ids of the runtimes that satisfy `pred`, comma-separated (e.g. those with a renderer).
pub fn ids_where(pred: impl Fn(&Registration) -> bool) -> String {
    REGISTRY
        .iter()
        .filter(|r| pred(r))
        .map(|r| r.id)
        .collect::<Vec<_>>()
        .join(", ")
}

/// Build `spec`'s environment under `context` (bounds enforced, default options).
pub fn make(spec: &EnvSpec, context: &Context) -> Result<SpecEnv, MakeError> {
    make_env(spec, context, MakeOptions::default(), &EnvOptions::new())
}

/// [`make`] with a bounds policy.
pub fn make_with(spec: &EnvSpec, context: &Context, opts: MakeOptions) -> Result<SpecEnv, MakeError> {
    make_env(spec, context, opts, &EnvOptions::new())
}

/// [`make`] with a bounds policy and variant options (`continuous = true`, …).
pub fn make_env(
    spec: &EnvSpec,
    context: &Context,
    opts: MakeOptions,
    options: &EnvOptions,
) -> Result<SpecEnv, MakeError> {
    // "No runtime" first: a spec-only environment may have features (strings, lists) that no
    // runtime could take, and the missing runtime is what the user needs to hear.
    let reg = lookup(&spec.id).ok_or_else(|| MakeError::NoRuntime {
        env: spec.id.clone(),
        available: ids_text(),
    })?;
    let values = resolve_context(spec, context, opts)?;
    let options = resolve_options(reg.id, reg.options, options)?;
    check_option_features(spec, &values, &options)?;
    let env = (reg.build)(&values, &options)?;
    Ok(TimeLimit::new(env, spec.max_episode_steps))
}
