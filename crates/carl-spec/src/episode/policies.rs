//! A [`Policy`] by kind for a registry entry: the same three policies for every command.

use crate::envs::api::Space;
use crate::envs::policy::{NoopPolicy, Policy, PolicyKind, RandomPolicy};
use crate::envs::registry::{Registration, ids_where};

/// The policy `kind` for environment `reg` with action space `space`; random policies draw from
/// a stream seeded with `seed`. Asking for a heuristic the environment does not have is an
/// error naming the environments that do.
pub fn policy_for(reg: &Registration, kind: PolicyKind, space: &Space, seed: u64) -> Result<Box<dyn Policy>, String> {
    Ok(match kind {
        PolicyKind::Random => Box::new(RandomPolicy::new(space.clone(), seed)),
        PolicyKind::Noop => Box::new(NoopPolicy::new(space)),
        PolicyKind::Heuristic => match reg.heuristic {
            Some(make) => make(space),
            None => {
                return Err(format!(
                    "{} has no built-in controller; environments with one: {} (or use --policy random or noop)",
                    reg.id,
                    ids_where(|r| r.heuristic.is_some())
                ));
            }
        },
    })
}
