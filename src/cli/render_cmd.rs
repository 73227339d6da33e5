//! `carl-spec render ENV …`: pictures of a configured instance. `--out frame.png` writes one
//! frame (after `--steps` steps, default the reset state), `--out run.gif` an animation of the
//! episode, `--out DIR/` a numbered PNG per frame. The output path follows the crate's one rule
//! (`crate::output`, `crate::render`): checked before the episode runs, parent directory must
//! exist, nothing replaced without `--force`, atomic writes; `--force` on a frame directory
//! leaves exactly this run's frames in it.

use std::path::PathBuf;

use clap::Args;

use super::context_args::ContextArgs;
use super::rollout_cmd::{parse_action, random_action};
use super::{Cli, CmdResult, Failure, exit, load_specs};
use crate::envs::api::{Action, Env};
use crate::envs::registry::{MakeOptions, has_runtime, make_with};
use crate::render::{RenderError, RenderOutput};
use crate::sampling::Pcg64;

/// Environments with a built-in controller for `--policy heuristic`.
const HEURISTICS: &[&str] = &["lunar_lander", "bipedal_walker"];

/// Frames an animation may have (a 600×400 GIF frame is ~100 kB).
const MAX_FRAMES: usize = 2000;

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Environment id or alias (renderers: lunar_lander and the other 2-D and 3-D physics envs).
    pub env: String,
    #[command(flatten)]
    pub ctx: ContextArgs,
    /// Seed of the reset (terrain, initial push) and of the random policy.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Steps to take: a PNG shows the state after them (default 0: the reset state); an
    /// animation shows them all (default: until the episode ends).
    #[arg(long, value_name = "N")]
    pub steps: Option<u64>,
    /// Who acts during the steps.
    #[arg(long, value_enum, default_value_t = RenderPolicy::Random)]
    pub policy: RenderPolicy,
    /// Keep every K-th frame of an animation.
    #[arg(long, value_name = "K", default_value_t = 2)]
    pub every: u64,
    /// GIF frame delay in hundredths of a second (default 4: with --every 2, real time at 50 FPS).
    #[arg(long, value_name = "CS", default_value_t = 4)]
    pub delay: u16,
    /// Output: `*.png` (one frame), `*.gif` (animation) or a directory (`DIR/`: frame_00000.png, …).
    #[arg(long, value_name = "PATH")]
    pub out: PathBuf,
    /// Replace existing output files (in a frame directory: replace and remove the old frames).
    #[arg(long)]
    pub force: bool,
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum RenderPolicy {
    /// Uniform over the action space, seeded with `--seed`.
    Random,
    /// Action 0 (discrete) or all zeros (continuous).
    Noop,
    /// The environment's built-in controller (lunar_lander, bipedal_walker: Gymnasium's heuristics).
    Heuristic,
}

fn render_failure(e: RenderError) -> Failure {
    match e {
        RenderError::Encode(m) => Failure::failed(m),
        e => Failure::usage(e.to_string()),
    }
}

/// `id` cannot be drawn: the message lists the environments that can.
fn no_renderer(cli: &Cli, id: &str, why: &str) -> Failure {
    let list = load_specs(cli).map(|s| crate::render::renderable(&s).join(", ")).unwrap_or_default();
    Failure::usage(format!("{id} {why}; render works for: {list}"))
}

pub fn run(cli: &Cli, args: &RenderArgs) -> CmdResult {
    let output = RenderOutput::parse(&args.out).map_err(render_failure)?;
    output.check(args.force).map_err(|e| Failure::usage(e.to_string()))?;
    if args.every == 0 {
        return Err(Failure::usage("--every must be at least 1"));
    }
    if let Ok(spec) = load_specs(cli)?.require(&args.env) {
        if !has_runtime(&spec.id) {
            return Err(no_renderer(cli, &spec.id, "has a spec but no runtime (and no renderer) yet"));
        }
    }
    let resolved = args.ctx.resolve(cli, &args.env, "render")?;
    let opts = MakeOptions {
        allow_out_of_bounds: resolved.allow_out_of_bounds,
    };
    let mut env = make_with(&resolved.spec, &resolved.context, opts).map_err(|e| Failure::usage(e.to_string()))?;
    let id = env.id();
    if args.policy == RenderPolicy::Heuristic && !HEURISTICS.contains(&id) {
        return Err(Failure::usage(format!(
            "{id} has no built-in controller; use --policy random or noop"
        )));
    }
    let space = env.action_space();
    let mut rng = Pcg64::new(args.seed, crate::sampling::stream_id("render-policy"));
    let mut obs = vec![0.0f32; env.obs_dim()];
    env.reset_into(Some(args.seed), &mut obs)
        .map_err(|e| Failure::failed(e.to_string()))?;
    let Some(first) = env.render() else {
        return Err(no_renderer(cli, id, "has no renderer yet"));
    };
    let animated = output.is_animation();
    let steps = args.steps.unwrap_or(if animated { u64::MAX } else { 0 });
    let mut walker = crate::envs::box2d::WalkerHeuristic::default();
    let mut frames = vec![first];
    let mut t = 0u64;
    let mut last = None;
    while t < steps {
        let action = match args.policy {
            RenderPolicy::Random => parse_action(&random_action(&mut rng, &space), &space).map_err(Failure::failed)?,
            RenderPolicy::Noop => match &space {
                crate::envs::Space::Discrete { start, .. } => Action::Discrete(*start),
                crate::envs::Space::Box { low, .. } => Action::Continuous(vec![0.0; low.len()]),
            },
            RenderPolicy::Heuristic if id == "bipedal_walker" => Action::Continuous(walker.act(&obs).to_vec()),
            RenderPolicy::Heuristic => Action::Discrete(crate::envs::box2d::heuristic(&obs)),
        };
        let out = env
            .step_into(&action, &mut obs)
            .map_err(|e| Failure::failed(format!("step {}: {e}", t + 1)))?;
        t += 1;
        let end = out.terminated || out.truncated;
        if animated {
            if t % args.every == 0 || end {
                frames.push(env.render().ok_or_else(|| Failure::failed("renderer stopped"))?);
            }
            if frames.len() > MAX_FRAMES {
                return Err(Failure::usage(format!(
                    "more than {MAX_FRAMES} frames; pass --steps or a larger --every"
                )));
            }
        }
        if end {
            last = Some(if out.terminated { "terminated" } else { "truncated" });
            break;
        }
    }
    if !animated {
        frames = vec![env.render().ok_or_else(|| Failure::failed("renderer stopped"))?];
    }
    let title = format!("{id}, seed {}, step {t}", args.seed);
    let (w, h) = (frames[0].width, frames[0].height);
    let written = output
        .write(&frames, &title, args.delay, args.force)
        .map_err(render_failure)?;
    for p in &written.removed {
        eprintln!("removed {} (a frame of an earlier run)", p.display());
    }
    let ended = last.map(|s| format!(", episode {s}")).unwrap_or_default();
    println!(
        "wrote {} ({} frame{}, {w}x{h}, {id}, seed {}, {t} step{}{ended})",
        args.out.display(),
        written.frames,
        if written.frames == 1 { "" } else { "s" },
        args.seed,
        if t == 1 { "" } else { "s" },
    );
    Ok(exit::OK)
}
