//! Context noise (the paper's "context measured with noise"): the agent observes visible features
//! with Gaussian noise, the dynamics use the true context, `info` carries both, and the draws are
//! seeded from the environment's seed.

use carl_spec::envs::contextual::{
    ContextNoise, ContextSource, ContextualEnv, ContextualOptions, Features, NoiseRedraw, NoiseStd, OBSERVED_PREFIX,
    Visibility,
};
use carl_spec::envs::registry::Context;
use carl_spec::envs::{Action, Env};
use carl_spec::spec::SpecSet;
use carl_spec::spec::model::Value;

fn lander(noise: Vec<(&str, NoiseStd)>, redraw: NoiseRedraw) -> Result<ContextualEnv, String> {
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get("lunar_lander").unwrap();
    let ctx: Context = [("GRAVITY_Y".to_string(), Value::Number(-5.0))].into_iter().collect();
    let opts = ContextualOptions {
        visibility: Visibility::Visible(Features::Only(vec!["GRAVITY_Y".into(), "GRAVITY_X".into()])),
        noise: ContextNoise {
            features: noise.into_iter().map(|(n, s)| (n.to_string(), s)).collect(),
            redraw,
        },
        ..ContextualOptions::default()
    };
    ContextualEnv::new(spec, ContextSource::Fixed(ctx), opts).map_err(|e| e.to_string())
}

/// Observations of 20 steps with the main engine on, after `reset(seed)`.
fn run(env: &mut ContextualEnv, seed: u64) -> Vec<Vec<f32>> {
    let (obs, _) = env.reset(Some(seed));
    let mut out = vec![obs];
    for _ in 0..20 {
        out.push(env.step(&Action::Discrete(2)).unwrap().obs);
    }
    out
}

#[test]
fn noise_changes_what_is_observed_not_the_dynamics() {
    let mut exact = lander(vec![], NoiseRedraw::Episode).unwrap();
    let mut noisy = lander(vec![("GRAVITY_Y", NoiseStd::Absolute(1.0))], NoiseRedraw::Episode).unwrap();
    let (a, b) = (run(&mut exact, 3), run(&mut noisy, 3));
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(x[..8], y[..8], "the physics saw the noise");
        assert_eq!(x[8], -5.0);
        assert_eq!(x[9], y[9], "GRAVITY_X has no noise");
    }
    let seen = b[0][8];
    assert_ne!(seen, -5.0);
    assert!(b.iter().all(|o| o[8] == seen), "per-episode noise is drawn once");
    let info = noisy.info();
    assert_eq!(info["context.GRAVITY_Y"], -5.0);
    assert_eq!(info[&format!("{OBSERVED_PREFIX}GRAVITY_Y")], f64::from(seen));
    // The space admits any measurement.
    assert!(noisy.observation_space().flat_dim() == 10);
    let sample = b.last().unwrap();
    assert!(
        matches!(noisy.observation_space(), carl_spec::envs::Space::Box { ref low, ref high, .. }
        if low[8] == f32::NEG_INFINITY && high[8] == f32::INFINITY && sample.len() == 10)
    );
}

#[test]
fn noise_is_seeded_from_the_env_seed_and_redrawn_as_asked() {
    let mut e = lander(vec![("GRAVITY_Y", NoiseStd::Relative(0.2))], NoiseRedraw::Step).unwrap();
    let first = run(&mut e, 5);
    assert_eq!(run(&mut e, 5), first, "same seed, same noise");
    assert_ne!(run(&mut e, 6)[0][8], first[0][8], "another seed, other noise");
    let values: std::collections::BTreeSet<u32> = first.iter().map(|o| o[8].to_bits()).collect();
    assert!(values.len() > 15, "per-step noise changes every step: {values:?}");
    // Relative: std 0.2 · |default -10| = 2; 21 draws stay within a few std of the truth.
    assert!(first.iter().all(|o| (o[8] + 5.0).abs() < 10.0));
}

#[test]
fn bad_noise_is_refused_with_the_reason() {
    let err = lander(
        vec![("MAIN_ENGINE_POWER", NoiseStd::Absolute(1.0))],
        NoiseRedraw::Episode,
    )
    .unwrap_err();
    assert!(err.contains("not observed"), "{err}");
    let err = lander(vec![("GRAVITY_Z", NoiseStd::Absolute(1.0))], NoiseRedraw::Episode).unwrap_err();
    assert!(err.contains("no such context feature"), "{err}");
    let err = lander(vec![("GRAVITY_Y", NoiseStd::Absolute(-1.0))], NoiseRedraw::Episode).unwrap_err();
    assert!(err.contains(">= 0"), "{err}");
    let err = lander(vec![("GRAVITY_X", NoiseStd::Relative(0.1))], NoiseRedraw::Episode).unwrap_err();
    assert!(err.contains("default is 0"), "{err}");
}

#[test]
fn rollout_reports_true_and_observed_context() {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_carl-spec"))
        .args([
            "rollout",
            "lunar_lander",
            "--obs-context",
            "GRAVITY_Y",
            "--noise",
            "GRAVITY_Y=10%",
            "--steps",
            "2",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let lines: Vec<serde_json::Value> = String::from_utf8_lossy(&o.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let reset = &lines[0]["reset"];
    assert_eq!(reset["context"]["GRAVITY_Y"], -10.0);
    let seen = reset["observed_context"]["GRAVITY_Y"].as_f64().unwrap();
    assert_ne!(seen, -10.0);
    assert_eq!(reset["obs"][8].as_f64().unwrap() as f32, seen as f32);
    // Without --obs-context, noise has nothing to act on.
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_carl-spec"))
        .args(["rollout", "lunar_lander", "--noise", "GRAVITY_Y=1"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--obs-context"));
}
