//! "Landing in Space" (CARL paper, LunarLander with varied gravity) end to end: evaluate a policy
//! on each named test body of `lunar_lander/landing_in_space_test_planets` and on a sample of
//! `lunar_lander/landing_in_space_train`, and summarise returns and outcomes per row. Every
//! episode is a job of the generic evaluation engine ([`crate::evaluation::run_job`], what
//! `carl-spec evaluate` runs), with this experiment's rows and seeds.
//!
//! * **Rows.** One per test body (in the frozen set's order, labelled with its `split`), then one
//!   `train` row whose `episodes` are spread round-robin over the train set's instances (episode
//!   `k` runs on instance `k mod len`).
//! * **Seeds.** Episode `k` of row `r` (a body's name, or `train`) resets with
//!   [`reset_seed`]`(S, r, k)`: the first output of `Pcg64::new(S, fnv1a64("landing_in_space/{r}/{k}"))`.
//!   So every (seed, row, episode) has its own independent start, and adding rows or episodes never
//!   changes the others.
//! * **Outcomes.** LunarLander's own ([`Env::outcome`]): `landed`: came to rest (+100);
//!   `crashed`: the lander body touched the ground; `out_of_view`: `|x| >= 1`; `timeout`: truncated
//!   by the spec's episode limit (1000 steps). `crash_rate` counts crashes and out-of-view together (both end with
//!   `-crash_penalty`).
//! * **Statistics.** Mean return and population standard deviation (ddof 0, NumPy's default).
//!
//! Physics (see `envs::box2d::lunar_lander`): Box2D 2.3's semantics in `f64` (free flight in
//! closed form, [`crate::physics2d`] near the ground), recorded as
//! [`crate::envs::box2d::PHYSICS_ENGINE`] in the results; the heuristic's landing
//! and crash rates are within 0.10 of Gymnasium's on every body (README table).

use serde::Serialize;
use serde_json::{Map, Value, json};

use crate::envs::api::{Action, Env, Space};
use crate::envs::box2d::{Outcome, PHYSICS_ENGINE, heuristic};
use crate::envs::contextual::ContextualEnv;
use crate::envs::policy::{Policy, PolicyError};
use crate::envs::registry::{EnvOptions, MakeOptions, make_with, resolve_context};
use crate::episode::{EpisodeError, EpisodeListener, Flow, StepRecord};
use crate::evaluation::{self, Job};
use crate::instances::{FrozenSet, Store};
use crate::sampling::{Pcg64, stream_id};
use crate::spec::SpecSet;
use crate::spec::raw::Split;

pub const TEST_SET: &str = "lunar_lander/landing_in_space_test_planets";
pub const TRAIN_SET: &str = "lunar_lander/landing_in_space_train";
/// Name of the row that samples the train set.
pub const TRAIN_ROW: &str = "train";

/// What to run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Config {
    /// Episodes per row (per test body, and in total on the train set).
    pub episodes: usize,
    /// Base seed `S` of [`reset_seed`].
    pub seed: u64,
    /// Reward on crash / out of view is `-crash_penalty` (Gymnasium 100, the paper's evaluation 10000).
    pub crash_penalty: f64,
}

/// Largest crash penalty accepted: 10^5 times the paper's 10,000. Far beyond any sensible
/// evaluation, and small enough that sums and variances of returns stay finite.
pub const MAX_CRASH_PENALTY: f64 = 1e9;

impl Config {
    /// An error message for values that cannot give meaningful (finite) results.
    pub fn check(&self) -> Result<(), String> {
        let p = self.crash_penalty;
        // Short for huge values: `{}` of 1e308 has 309 digits.
        let shown = if p.abs() >= 1e16 {
            format!("{p:e}")
        } else {
            format!("{p}")
        };
        if !p.is_finite() {
            return Err(format!("crash penalty {shown} is not finite"));
        }
        if !(0.0..=MAX_CRASH_PENALTY).contains(&p) {
            return Err(format!(
                "crash penalty {shown} is outside 0..={MAX_CRASH_PENALTY:e} (the reward on a crash is minus the penalty; Gymnasium uses 100, the paper's evaluation 10000)"
            ));
        }
        Ok(())
    }
}

impl Default for Config {
    fn default() -> Self {
        Config {
            episodes: 20,
            seed: 0,
            crash_penalty: 100.0,
        }
    }
}

/// The reset seed of episode `k` of row `row` (a body's name or [`TRAIN_ROW`]) under base seed `seed`.
pub fn reset_seed(seed: u64, row: &str, k: usize) -> u64 {
    Pcg64::new(seed, stream_id(&format!("landing_in_space/{row}/{k}"))).next_u64()
}

/// The episode about to start, as an [`Observer`] is told of it.
#[derive(Debug, Clone, Serialize)]
pub struct EpisodeInfo {
    /// Body name, or [`TRAIN_ROW`].
    pub body: String,
    pub gravity: f64,
    pub seed: u64,
    /// Index of the instance within its frozen set.
    #[serde(skip)]
    pub instance: usize,
    /// Episode number within its row.
    #[serde(skip)]
    pub k: usize,
    #[serde(skip)]
    pub action_space: Space,
}

/// What watches an evaluation besides the policy: told of each episode before its reset, then
/// a listener of the shared episode loop ([`crate::episode::run_episode`]) for its reset and
/// steps. The CLI's `--policy stdin` streams them as JSON lines; a [`Flow::Stop`] from the
/// listener (its reader went away) ends the whole evaluation ([`EvalError::Stopped`]).
pub trait Observer: EpisodeListener<ContextualEnv> {
    /// Episode `info` is about to start under the full context `context`.
    fn begin(&mut self, _info: &EpisodeInfo, _context: &Map<String, Value>) -> Result<(), String> {
        Ok(())
    }
}

/// An observer that watches nothing.
pub struct Unobserved;

impl<E: Env + ?Sized> EpisodeListener<E> for Unobserved {
    fn on_step(&mut self, _env: &E, _step: &StepRecord<'_>) -> Result<Flow, EpisodeError> {
        Ok(Flow::Continue)
    }
}

impl Observer for Unobserved {}

/// Gymnasium's heuristic controller (discrete).
pub struct Heuristic;

impl Policy for Heuristic {
    fn act(&mut self, obs: &[f32]) -> Result<Option<Action>, PolicyError> {
        Ok(Some(Action::Discrete(heuristic(obs))))
    }
}

/// Why an evaluation did not finish.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EvalError {
    /// The observer asked to stop (the reader of a pipe went away): not a failure.
    #[error("stopped by its observer")]
    Stopped,
    #[error("{0}")]
    Failed(String),
}

impl From<String> for EvalError {
    fn from(s: String) -> Self {
        EvalError::Failed(s)
    }
}

/// The action space every episode of the evaluation has (the discrete lander).
pub fn action_space(specs: &SpecSet) -> Result<Space, String> {
    let spec = specs.require("lunar_lander")?;
    let env = make_with(spec, &Default::default(), MakeOptions::default()).map_err(|e| e.to_string())?;
    Ok(env.action_space())
}

/// One episode's result.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EpisodeEnd {
    Landed,
    Crashed,
    OutOfView,
    Timeout,
}

#[derive(Debug, Clone, Serialize)]
pub struct EpisodeResult {
    pub instance: usize,
    pub gravity: f64,
    pub seed: u64,
    #[serde(rename = "return")]
    pub ret: f64,
    pub length: u64,
    pub end: EpisodeEnd,
}

/// One row of the table.
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    pub body: String,
    /// `in_distribution`, `out_of_distribution` or `train`.
    pub split: String,
    /// The body's GRAVITY_Y; for the train row, the mean over its episodes.
    pub gravity: f64,
    /// Smallest and largest GRAVITY_Y among the row's episodes.
    pub gravity_range: [f64; 2],
    pub episodes: usize,
    pub mean_return: f64,
    pub std_return: f64,
    pub landed_rate: f64,
    /// Crashed or out of view.
    pub crash_rate: f64,
    pub out_of_view_rate: f64,
    pub timeout_rate: f64,
    pub mean_length: f64,
    pub runs: Vec<EpisodeResult>,
}

impl Row {
    fn from_runs(body: &str, split: &str, runs: Vec<EpisodeResult>) -> Row {
        let n = runs.len().max(1) as f64;
        let mean = runs.iter().map(|r| r.ret).sum::<f64>() / n;
        let var = runs.iter().map(|r| (r.ret - mean).powi(2)).sum::<f64>() / n;
        let rate = |f: &dyn Fn(EpisodeEnd) -> bool| runs.iter().filter(|r| f(r.end)).count() as f64 / n;
        let gmin = runs.iter().map(|r| r.gravity).fold(f64::INFINITY, f64::min);
        let gmax = runs.iter().map(|r| r.gravity).fold(f64::NEG_INFINITY, f64::max);
        Row {
            body: body.to_string(),
            split: split.to_string(),
            // Exact for a single body (a mean of equal values can be off in the last digit).
            gravity: if gmin == gmax {
                gmin
            } else {
                runs.iter().map(|r| r.gravity).sum::<f64>() / n
            },
            gravity_range: [gmin, gmax],
            episodes: runs.len(),
            mean_return: mean,
            std_return: var.sqrt(),
            landed_rate: rate(&|e| e == EpisodeEnd::Landed),
            crash_rate: rate(&|e| matches!(e, EpisodeEnd::Crashed | EpisodeEnd::OutOfView)),
            out_of_view_rate: rate(&|e| e == EpisodeEnd::OutOfView),
            timeout_rate: rate(&|e| e == EpisodeEnd::Timeout),
            mean_length: runs.iter().map(|r| r.length as f64).sum::<f64>() / n,
            runs,
        }
    }
}

/// Everything `--out` writes.
#[derive(Debug, Clone, Serialize)]
pub struct Results {
    pub experiment: &'static str,
    pub policy: String,
    pub episodes_per_row: usize,
    pub seed: u64,
    pub crash_penalty: f64,
    pub seed_derivation: &'static str,
    pub physics_engine: &'static str,
    pub generator: String,
    pub instance_sets: serde_json::Value,
    pub rows: Vec<Row>,
}

/// Evaluate `policy` (named `label` in the results) on every test body and on the train sample.
pub fn evaluate(
    specs: &SpecSet,
    cfg: &Config,
    label: &str,
    policy: &mut dyn Policy,
    observer: &mut dyn Observer,
) -> Result<Results, EvalError> {
    cfg.check()?;
    let store = Store::new(specs);
    let test = store.load(TEST_SET).map_err(|e| e.to_string())?;
    let train = store.load(TRAIN_SET).map_err(|e| e.to_string())?;
    if train.instances.is_empty() {
        return Err(format!("{TRAIN_SET} has no instances").into());
    }
    let spec = specs.require("lunar_lander")?;
    let options: EnvOptions = [(
        "crash_penalty".to_string(),
        crate::spec::model::Value::Number(cfg.crash_penalty),
    )]
    .into();
    let source = |set: &FrozenSet| evaluation::Source::Set {
        set: set.clone(),
        episodes: cfg.episodes,
    };
    let mut test_env = evaluation::environment(spec, &source(&test), &options)?;
    let mut train_env = evaluation::environment(spec, &source(&train), &options)?;
    let mut rows = Vec::new();
    for (i, inst) in test.instances.iter().enumerate() {
        let body = inst.label();
        let split = match inst.split {
            Some(Split::InDistribution) => "in_distribution",
            Some(Split::OutOfDistribution) => "out_of_distribution",
            None => "unlabelled",
        };
        let runs = (0..cfg.episodes)
            .map(|k| run_one(specs, &test, &mut test_env, i, &body, k, cfg, policy, observer))
            .collect::<Result<Vec<_>, _>>()?;
        rows.push(Row::from_runs(&body, split, runs));
    }
    let runs = (0..cfg.episodes)
        .map(|k| {
            run_one(
                specs,
                &train,
                &mut train_env,
                k % train.instances.len(),
                TRAIN_ROW,
                k,
                cfg,
                policy,
                observer,
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    rows.push(Row::from_runs(TRAIN_ROW, TRAIN_ROW, runs));
    Ok(Results {
        experiment: "landing_in_space",
        policy: label.to_string(),
        episodes_per_row: cfg.episodes,
        seed: cfg.seed,
        crash_penalty: cfg.crash_penalty,
        seed_derivation: "reset seed of episode k of row r = Pcg64::new(seed, fnv1a64(\"landing_in_space/{r}/{k}\")).next_u64()",
        physics_engine: PHYSICS_ENGINE,
        generator: format!("carl-spec {}", env!("CARGO_PKG_VERSION")),
        instance_sets: json!({
            TEST_SET: test.content_hash,
            TRAIN_SET: train.content_hash,
        }),
        rows,
    })
}

#[allow(clippy::too_many_arguments)]
fn run_one(
    specs: &SpecSet,
    set: &FrozenSet,
    env: &mut ContextualEnv,
    i: usize,
    row: &str,
    k: usize,
    cfg: &Config,
    policy: &mut dyn Policy,
    observer: &mut dyn Observer,
) -> Result<EpisodeResult, EvalError> {
    let spec = specs.require(&set.env)?;
    let ctx = set
        .full_context(spec, i)
        .ok_or_else(|| format!("{}/{} has no instance {i}", set.env, set.set))?;
    let opts = MakeOptions {
        allow_out_of_bounds: set.provenance.definition.allow_out_of_bounds,
    };
    let full: Map<String, Value> = resolve_context(spec, &ctx, opts)
        .map_err(|e| e.to_string())?
        .into_iter()
        .map(|(k, v)| (k, json!(v)))
        .collect();
    let gravity = full.get("GRAVITY_Y").and_then(|v| v.as_f64()).unwrap_or(f64::NAN);
    let seed = reset_seed(cfg.seed, row, k);
    let info = EpisodeInfo {
        body: row.to_string(),
        gravity,
        seed,
        instance: i,
        k,
        action_space: env.action_space(),
    };
    observer.begin(&info, &full)?;
    let job = Job {
        instance: i,
        episode: k,
        seed,
    };
    let (result, _) = evaluation::run_job(env, true, &job, policy, observer).map_err(|e| match e {
        evaluation::EvalError::Stopped => EvalError::Stopped,
        evaluation::EvalError::BadInput(m) | evaluation::EvalError::Failed(m) => {
            EvalError::Failed(format!("{row} episode {k}: {m}"))
        }
    })?;
    let end = match (
        result.terminated,
        result.outcome.as_deref().and_then(Outcome::from_name),
    ) {
        (true, Some(Outcome::Landed)) => EpisodeEnd::Landed,
        (true, Some(Outcome::OutOfView)) => EpisodeEnd::OutOfView,
        (true, _) => EpisodeEnd::Crashed,
        (false, _) => EpisodeEnd::Timeout,
    };
    Ok(EpisodeResult {
        instance: i,
        gravity,
        seed,
        ret: result.ret,
        length: result.length,
        end,
    })
}

impl Results {
    /// An error naming the first row with a non-finite statistic (such numbers would be `null`
    /// in JSON and `NaN` in the figure).
    pub fn check_finite(&self) -> Result<(), String> {
        for r in &self.rows {
            let stats = [
                ("mean return", r.mean_return),
                ("std of returns", r.std_return),
                ("mean length", r.mean_length),
            ];
            for (what, v) in stats {
                if !v.is_finite() {
                    return Err(format!("row {}: the {what} is {v}, not a finite number", r.body));
                }
            }
            if let Some(run) = r.runs.iter().find(|x| !x.ret.is_finite()) {
                return Err(format!(
                    "row {}: episode with seed {} returned {}",
                    r.body, run.seed, run.ret
                ));
            }
        }
        Ok(())
    }
}

/// The results as a text table.
pub fn table(results: &Results) -> String {
    let mut s = format!(
        "Landing in Space: policy {}, {} episodes per row, seed {}, crash penalty {}\n",
        results.policy, results.episodes_per_row, results.seed, results.crash_penalty
    );
    s.push_str(&format!(
        "{:<8} {:>9} {:<20} {:>20} {:>7} {:>7} {:>8} {:>8}\n",
        "body", "gravity", "split", "return (mean ± std)", "landed", "crash", "(oov)", "timeout"
    ));
    for r in &results.rows {
        let g = if r.body == TRAIN_ROW {
            format!("{:.1}..{:.1}", r.gravity_range[0], r.gravity_range[1])
        } else {
            format!("{:.3}", r.gravity)
        };
        s.push_str(&format!(
            "{:<8} {:>9} {:<20} {:>20} {:>7.2} {:>7.2} {:>8.2} {:>8.2}\n",
            r.body,
            g,
            r.split,
            format!("{:.1} ± {:.1}", r.mean_return, r.std_return),
            r.landed_rate,
            r.crash_rate,
            r.out_of_view_rate,
            r.timeout_rate
        ));
    }
    s.push_str("rates: landed = came to rest (+100); crash = crashed or out of view, (oov) = out of view alone\n");
    s
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// An SVG bar chart: mean return per body (weakest to strongest gravity, then the train sample)
/// with ±std whiskers, coloured by split. An error (never a broken file) if any number to draw
/// is not finite.
pub fn figure_svg(results: &Results) -> Result<String, String> {
    results.check_finite()?;
    let mut rows: Vec<&Row> = results.rows.iter().filter(|r| r.body != TRAIN_ROW).collect();
    rows.sort_by(|a, b| a.gravity.abs().total_cmp(&b.gravity.abs()));
    rows.extend(results.rows.iter().filter(|r| r.body == TRAIN_ROW));
    let (w, h) = (640.0f64, 400.0f64);
    let (left, right, top, bottom) = (70.0, 20.0, 40.0, 70.0);
    let lo = rows.iter().map(|r| r.mean_return - r.std_return).fold(0.0f64, f64::min);
    let hi = rows.iter().map(|r| r.mean_return + r.std_return).fold(0.0f64, f64::max);
    let (lo, hi) = if hi - lo < 1e-9 { (lo - 1.0, hi + 1.0) } else { (lo, hi) };
    let pad = 0.05 * (hi - lo);
    let (lo, hi) = (lo - pad, hi + pad);
    let plot_h = h - top - bottom;
    let y = |v: f64| top + (hi - v) / (hi - lo) * plot_h;
    let slot = (w - left - right) / rows.len().max(1) as f64;
    let colour = |split: &str| match split {
        "in_distribution" => "#1f77b4",
        "out_of_distribution" => "#d62728",
        _ => "#7f7f7f",
    };
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" font-family=\"sans-serif\" font-size=\"12\">\n"
    );
    s.push_str(&format!("<rect width=\"{w}\" height=\"{h}\" fill=\"white\"/>\n"));
    s.push_str(&format!(
        "<text x=\"{}\" y=\"20\" text-anchor=\"middle\" font-size=\"14\">{}</text>\n",
        w / 2.0,
        esc(&format!(
            "Landing in Space: {} policy, {} episodes per body, crash penalty {}",
            results.policy, results.episodes_per_row, results.crash_penalty
        ))
    ));
    // Axis with ticks at "nice" steps.
    let raw = (hi - lo) / 6.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|st| *st >= raw)
        .unwrap_or(10.0 * mag);
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    for i in ((lo / step).ceil() as i64)..=((hi / step).floor() as i64) {
        let v = i as f64 * step;
        let yy = y(v);
        s.push_str(&format!(
            "<line x1=\"{left}\" y1=\"{yy:.2}\" x2=\"{:.2}\" y2=\"{yy:.2}\" stroke=\"#dddddd\"/>\n<text x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"end\">{v:.decimals$}</text>\n",
            w - right,
            left - 5.0,
            yy + 4.0,
        ));
    }
    s.push_str(&format!(
        "<line x1=\"{left}\" y1=\"{:.2}\" x2=\"{:.2}\" y2=\"{:.2}\" stroke=\"black\"/>\n",
        y(0.0),
        w - right,
        y(0.0)
    ));
    s.push_str(&format!(
        "<line x1=\"{left}\" y1=\"{top}\" x2=\"{left}\" y2=\"{:.2}\" stroke=\"black\"/>\n",
        h - bottom
    ));
    s.push_str(&format!(
        "<text transform=\"translate(16 {:.2}) rotate(-90)\" text-anchor=\"middle\">mean return ± std</text>\n",
        top + plot_h / 2.0
    ));
    for (j, r) in rows.iter().enumerate() {
        let cx = left + slot * (j as f64 + 0.5);
        let bw = slot * 0.6;
        let (y0, y1) = (y(0.0), y(r.mean_return));
        s.push_str(&format!(
            "<rect x=\"{:.2}\" y=\"{:.2}\" width=\"{bw:.2}\" height=\"{:.2}\" fill=\"{}\"><title>{}</title></rect>\n",
            cx - bw / 2.0,
            y0.min(y1),
            (y1 - y0).abs(),
            colour(&r.split),
            esc(&format!("{}: {:.1} ± {:.1}", r.body, r.mean_return, r.std_return))
        ));
        let (wa, wb) = (y(r.mean_return + r.std_return), y(r.mean_return - r.std_return));
        s.push_str(&format!(
            "<line x1=\"{cx:.2}\" y1=\"{wa:.2}\" x2=\"{cx:.2}\" y2=\"{wb:.2}\" stroke=\"black\"/>\n<line x1=\"{:.2}\" y1=\"{wa:.2}\" x2=\"{:.2}\" y2=\"{wa:.2}\" stroke=\"black\"/>\n<line x1=\"{:.2}\" y1=\"{wb:.2}\" x2=\"{:.2}\" y2=\"{wb:.2}\" stroke=\"black\"/>\n",
            cx - bw / 6.0,
            cx + bw / 6.0,
            cx - bw / 6.0,
            cx + bw / 6.0
        ));
        let g = if r.body == TRAIN_ROW {
            format!("g {:.1}..{:.1}", r.gravity_range[0], r.gravity_range[1])
        } else {
            format!("g {:.2}", r.gravity)
        };
        s.push_str(&format!(
            "<text x=\"{cx:.2}\" y=\"{:.2}\" text-anchor=\"middle\">{}</text>\n<text x=\"{cx:.2}\" y=\"{:.2}\" text-anchor=\"middle\" font-size=\"10\">{}</text>\n",
            h - bottom + 16.0,
            esc(&r.body),
            h - bottom + 30.0,
            esc(&g)
        ));
    }
    // Legend.
    for (j, (label, split)) in [
        ("in distribution", "in_distribution"),
        ("out of distribution", "out_of_distribution"),
        ("train sample", "train"),
    ]
    .iter()
    .enumerate()
    {
        let x = left + 160.0 * j as f64;
        s.push_str(&format!(
            "<rect x=\"{x:.2}\" y=\"{:.2}\" width=\"12\" height=\"12\" fill=\"{}\"/>\n<text x=\"{:.2}\" y=\"{:.2}\">{label}</text>\n",
            h - 22.0,
            colour(split),
            x + 16.0,
            h - 12.0
        ));
    }
    s.push_str("</svg>\n");
    // Finite statistics can still overflow the axis arithmetic; a coordinate is never NaN/inf.
    let bad = ["NaN", "inf"]
        .into_iter()
        .find(|w| s.contains(&format!("=\"{w}")) || s.contains(&format!("=\"-{w}")));
    if let Some(w) = bad {
        return Err(format!(
            "the figure would contain a {w} coordinate; refusing to write it"
        ));
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn results(rets: &[f64]) -> Results {
        let runs = rets
            .iter()
            .enumerate()
            .map(|(k, &ret)| EpisodeResult {
                instance: 0,
                gravity: -10.0,
                seed: k as u64,
                ret,
                length: 10,
                end: EpisodeEnd::Crashed,
            })
            .collect();
        Results {
            experiment: "landing_in_space",
            policy: "heuristic".into(),
            episodes_per_row: rets.len(),
            seed: 0,
            crash_penalty: 1e308,
            seed_derivation: "",
            physics_engine: PHYSICS_ENGINE,
            generator: String::new(),
            instance_sets: json!({}),
            rows: vec![Row::from_runs("Earth", "in_distribution", runs)],
        }
    }

    #[test]
    fn absurd_crash_penalties_are_refused() {
        for p in [f64::NAN, f64::INFINITY, 1e308, MAX_CRASH_PENALTY * 2.0, -1.0] {
            let cfg = Config {
                crash_penalty: p,
                ..Config::default()
            };
            let err = cfg.check().unwrap_err();
            assert!(err.len() < 200, "{err}");
        }
        for p in [0.0, 100.0, 10_000.0, MAX_CRASH_PENALTY] {
            let cfg = Config {
                crash_penalty: p,
                ..Config::default()
            };
            assert!(cfg.check().is_ok(), "{p}");
        }
    }

    #[test]
    fn the_figure_refuses_non_finite_numbers() {
        // Regression: --crash-penalty 1e308 gave mean -inf, std NaN and "NaN" in the SVG.
        let bad = results(&[-1e308, -1e308, 0.0]);
        assert!(bad.check_finite().is_err());
        let err = figure_svg(&bad).unwrap_err();
        assert!(err.contains("Earth"), "{err}");
        let good = figure_svg(&results(&[-100.0, 50.0, 0.0])).unwrap();
        assert!(!good.contains("NaN") && !good.contains("inf\""), "{good}");
    }
}
