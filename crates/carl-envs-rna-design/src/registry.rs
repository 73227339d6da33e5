//! The RNA design environment's registration.

use carl_env::context::{MakeError, OptionKind, OptionSpec, OptionValues};
use carl_env::registration::{AuditProfile, Registration, StepCost};
use carl_env::runtime::AnyEnv;

use crate::{Dataset, RnaDesign, RnaDesignParams, TargetError};

/// The environments of this family, in registry order.
pub const REGISTRATIONS: &[Registration] = &[Registration {
    id: "rna_design",
    build: |v, o| {
        let p = rna_design_params(v, o)?;
        let env = RnaDesign::new(p).map_err(|e| match e {
            TargetError::UnknownId { .. } | TargetError::NoTargets { .. } => MakeError::Runtime {
                env: "rna_design".into(),
                message: format!("option target_structure_ids: {e}"),
            },
            other => MakeError::BadValue {
                env: "rna_design".into(),
                name: "dataset".into(),
                expected: "loadable",
                got: other.to_string(),
            },
        })?;
        Ok(AnyEnv::new(env))
    },
    runtime_default: rna_design_default,
    options: &[
        OptionSpec {
            name: "max_improvement_folds",
            help: "cap on the folds of LEARNA's local improvement per episode (it costs up to 4^d folds); 0: no cap, as LEARNA",
            kind: OptionKind::Number {
                default: 0.0,
                min: 0.0,
                max: 1e12,
            },
        },
        OptionSpec {
            name: "target_structure_ids",
            help: "ids of the dataset's targets to design for (Eterna100: puzzle numbers 1-100; Rfam-Taneda: 1-29), e.g. 1,5,17; default: all",
            kind: OptionKind::Ids,
        },
    ],
    heuristic: None,
    renders: false,
    cost: StepCost::Heavy,
    // A step is a table write; the last one of an episode folds (up to 400 nt for Eterna100).
    audit: AuditProfile {
        trajectory_seeds: 4,
        trajectory_steps: 24,
        random_states: 0,
        reset_seeds: 8,
        state_hint: &[],
    },
    vector_kernel: None,
}];

/// rna_design's context: the spec's `dataset` choice index (eterna, rfam_learn, rfam_taneda)
/// becomes a [`Dataset`]; Rfam-Learn is read from `$CARL_SPEC_DATA`.
fn rna_design_params(values: &[(String, f64)], options: &OptionValues) -> Result<RnaDesignParams, MakeError> {
    let mut p = RnaDesignParams::default();
    for (name, x) in values {
        match name.as_str() {
            "mutation_threshold" => p.mutation_threshold = *x,
            "reward_exponent" => p.reward_exponent = *x,
            "state_radius" => {
                if !(0.0..=crate::MAX_STATE_RADIUS as f64).contains(x) {
                    return Err(MakeError::Runtime {
                        env: "rna_design".into(),
                        message: format!(
                            "state_radius = {x} is more than this runtime can observe (at most {}, even out of bounds: the observation has 2*state_radius + 1 entries)",
                            crate::MAX_STATE_RADIUS
                        ),
                    });
                }
                p.state_radius = *x as usize;
            }
            "dataset" => {
                p.dataset = match *x as usize {
                    0 => Dataset::Eterna,
                    1 => Dataset::RfamLearn(crate::RfamLearnSplit::Train),
                    _ => Dataset::RfamTaneda,
                }
            }
            other => {
                return Err(MakeError::UnknownFeature {
                    env: "rna_design".into(),
                    name: other.into(),
                    hint: " (the spec names a feature the runtime does not know)".into(),
                    valid: "mutation_threshold, reward_exponent, state_radius, dataset".into(),
                });
            }
        }
    }
    let cap = options.get("max_improvement_folds");
    p.max_improvement_folds = (cap > 0.0).then_some(cap as u64);
    p.target_structure_ids = options.ids("target_structure_ids").map(<[u32]>::to_vec);
    Ok(p)
}

/// The runtime's own default of a numeric feature (`dataset` is a choice, decided by the spec).
fn rna_design_default(name: &str) -> Option<f64> {
    let p = RnaDesignParams::default();
    match name {
        "mutation_threshold" => Some(p.mutation_threshold),
        "reward_exponent" => Some(p.reward_exponent),
        "state_radius" => Some(p.state_radius as f64),
        _ => None,
    }
}
