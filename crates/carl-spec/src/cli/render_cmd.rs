//! `carl-spec render ENV …`: pictures of a configured instance. `--out frame.png` writes one
//! frame (after `--steps` steps, default the reset state), `--out run.gif` an animation of the
//! episode, `--out DIR/` a numbered PNG per frame. The output path follows the crate's one rule
//! (`crate::output`, `crate::render`): checked before the episode runs, parent directory must
//! exist, nothing replaced without `--force`, atomic writes; `--force` on a frame directory
//! leaves exactly this run's frames in it.

use std::path::PathBuf;

use clap::Args;

use super::context_args::{ContextArgs, PolicyArg};
use super::{Cli, CmdResult, Failure, exit};
use crate::envs::Env;
use crate::envs::registry::{ids_where, lookup};
use crate::episode::policies::policy_for;
use crate::episode::{EpisodeConfig, EpisodeError, EpisodeListener, Flow, StepRecord, run_episode};
use crate::pixels::Frame;
use crate::render::{RenderError, RenderOutput};

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
    #[arg(long, value_enum, default_value_t = PolicyArg::Random)]
    pub policy: PolicyArg,
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

fn render_failure(e: RenderError) -> Failure {
    match e {
        RenderError::Encode(m) => Failure::failed(m),
        e => Failure::usage(e.to_string()),
    }
}

pub fn run(cli: &Cli, args: &RenderArgs) -> CmdResult {
    let output = RenderOutput::parse(&args.out).map_err(render_failure)?;
    output.check(args.force).map_err(|e| Failure::usage(e.to_string()))?;
    if args.every == 0 {
        return Err(Failure::usage("--every must be at least 1"));
    }
    // Environments without a renderer (spec-only ones included) hear which ones have one.
    if let Ok(spec) = super::load_specs(cli)?.require(&args.env)
        && lookup(&spec.id).is_none_or(|r| !r.renders)
    {
        return Err(Failure::usage(format!(
            "{} has no renderer yet; render works for: {}",
            spec.id,
            ids_where(|r| r.renders)
        )));
    }
    let resolved = args.ctx.resolve(cli, &args.env, "render")?;
    let reg = resolved.registration;
    let mut env = resolved.build()?;
    let id = env.id();
    let mut policy = policy_for(reg, args.policy.into(), &env.action_space(), args.seed).map_err(Failure::usage)?;
    let animated = output.is_animation();
    let steps = args.steps.unwrap_or(if animated { u64::MAX } else { 0 });
    let mut frames = FrameCollector {
        animated,
        every: args.every,
        frames: Vec::new(),
        progress: if animated {
            super::progress::Progress::counter("frames drawn")
        } else {
            super::progress::Progress::bar(0, "")
        },
    };
    let config = EpisodeConfig {
        seed: args.seed,
        initial_state: None,
        max_steps: Some(steps),
    };
    let summary = run_episode(&mut env, policy.as_mut(), &config, &mut frames).map_err(|e| match e {
        EpisodeError::Listener(m) => Failure::usage(m),
        e => Failure::failed(e.to_string()),
    })?;
    frames.progress.finish();
    let mut frames = frames.frames;
    if !animated {
        frames = vec![env.render().ok_or_else(|| Failure::failed("renderer stopped"))?];
    }
    let t = summary.steps;
    let last = matches!(
        summary.end,
        crate::episode::EpisodeEnd::Terminated | crate::episode::EpisodeEnd::Truncated
    )
    .then(|| summary.end.as_str());
    let title = format!("{id}, seed {}, step {t}", args.seed);
    let (w, h) = (frames[0].width, frames[0].height);
    let written = output
        .write(&frames, &title, args.delay, args.force)
        .map_err(render_failure)?;
    for p in &written.removed {
        eprintln!("removed {} (a frame of an earlier run)", p.display());
    }
    let ended = last.map(|s| format!(", episode {s}")).unwrap_or_default();
    super::out(&format!(
        "wrote {} ({} frame{}, {w}x{h}, {id}, seed {}, {t} step{}{ended})\n",
        args.out.display(),
        written.frames,
        if written.frames == 1 { "" } else { "s" },
        args.seed,
        if t == 1 { "" } else { "s" },
    ))?;
    Ok(exit::OK)
}

/// Collects the frames of an animation: the reset, every `every`-th step and the last one.
struct FrameCollector {
    animated: bool,
    every: u64,
    frames: Vec<Frame>,
    progress: super::progress::Progress,
}

impl FrameCollector {
    fn push<E: Env + ?Sized>(&mut self, env: &E) -> Result<Flow, EpisodeError> {
        let frame = env
            .render()
            .ok_or_else(|| EpisodeError::Listener(format!("{} drew no picture", env.id())))?;
        self.frames.push(frame);
        self.progress.inc(1);
        if self.frames.len() > MAX_FRAMES {
            return Err(EpisodeError::Listener(format!(
                "more than {MAX_FRAMES} frames; pass --steps or a larger --every"
            )));
        }
        Ok(Flow::Continue)
    }
}

impl<E: Env + ?Sized> EpisodeListener<E> for FrameCollector {
    fn on_reset(&mut self, env: &E, _obs: &[f32]) -> Result<Flow, EpisodeError> {
        self.push(env)
    }
    fn on_step(&mut self, env: &E, s: &StepRecord<'_>) -> Result<Flow, EpisodeError> {
        let end = s.outcome.terminated || s.outcome.truncated;
        if self.animated && (s.t.is_multiple_of(self.every) || end) {
            return self.push(env);
        }
        Ok(Flow::Continue)
    }
}
