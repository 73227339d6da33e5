//! The JSON Lines protocol of `carl-spec rollout`.
//!
//! First line `{"reset": {"obs": […], "context": {…}}}`, then one line per step
//! `{"t": 1, "action": …, "obs": […], "reward": r, "terminated": b, "truncated": b}`. Actions
//! come from a JSON array or, one JSON value per line, from a stream ([`ActionStream`]); in that
//! closed loop every line is written and flushed before the next action is read, so any program
//! can drive an environment through a pipe.
//!
//! A reader that goes away (closed pipe) ends the episode quietly; any other write failure
//! (a full disk) is an error, never a silently truncated result.

use std::io::{BufRead, ErrorKind, Write};

use serde::Serialize;
use serde_json::{Map, Value, json};

use super::{EpisodeError, EpisodeListener, Flow, StepRecord};
use crate::envs::api::{Action, Env, Space};
use crate::envs::contextual::OBSERVED_PREFIX;
use crate::envs::policy::{Policy, PolicyError};

/// `text` for a message: control characters escaped, cut short with the full length
/// (the crate's one quoting rule, [`crate::text::escape`]).
pub use crate::text::escape as quote_input;

// Lines are structs so their keys come out in the documented order.
#[derive(Serialize)]
struct ResetLine<'a> {
    reset: ResetBody<'a>,
}

#[derive(Serialize)]
struct ResetBody<'a> {
    obs: &'a [f32],
    context: &'a Map<String, Value>,
    #[serde(skip_serializing_if = "Option::is_none")]
    observed_context: Option<&'a Map<String, Value>>,
}

#[derive(Serialize)]
struct StepLine<'a> {
    t: u64,
    action: Value,
    obs: &'a [f32],
    reward: f64,
    terminated: bool,
    truncated: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    observed_context: Option<&'a Map<String, Value>>,
}

/// Write the reset line (`observed`: the context the agent observes, if it differs).
pub fn write_reset(
    w: &mut impl Write,
    obs: &[f32],
    context: &Map<String, Value>,
    observed: Option<&Map<String, Value>>,
) -> std::io::Result<()> {
    let line = ResetLine {
        reset: ResetBody {
            obs,
            context,
            observed_context: observed,
        },
    };
    serde_json::to_writer(&mut *w, &line)?;
    w.write_all(b"\n")
}

/// Write one step line.
pub fn write_step(
    w: &mut impl Write,
    s: &StepRecord<'_>,
    observed: Option<&Map<String, Value>>,
) -> std::io::Result<()> {
    let line = StepLine {
        t: s.t,
        action: action_json(s.action),
        obs: s.obs,
        reward: s.outcome.reward,
        terminated: s.outcome.terminated,
        truncated: s.outcome.truncated,
        observed_context: observed,
    };
    serde_json::to_writer(&mut *w, &line)?;
    w.write_all(b"\n")
}

/// An action as JSON: an integer, or an array of numbers.
pub fn action_json(action: &Action) -> Value {
    match action {
        Action::Discrete(a) => json!(a),
        Action::Continuous(v) => json!(v),
    }
}

/// Parse one JSON action for `space` (a 1-D Box also takes a bare number).
pub fn parse_action(v: &Value, space: &Space) -> Result<Action, String> {
    let shown = || quote_input(&v.to_string());
    match space {
        Space::Discrete { n, start } => {
            let a = v
                .as_i64()
                .ok_or_else(|| format!("expected an integer action in {start}..{}, got {}", start + n, shown()))?;
            Ok(Action::Discrete(a))
        }
        Space::Box { low, .. } => {
            let xs: Vec<f32> = match v {
                Value::Number(x) if low.len() == 1 => vec![x.as_f64().unwrap_or(f64::NAN) as f32],
                Value::Array(items) => items
                    .iter()
                    .map(|x| {
                        x.as_f64()
                            .map(|f| f as f32)
                            .ok_or_else(|| format!("action element {} is not a number", quote_input(&x.to_string())))
                    })
                    .collect::<Result<_, _>>()?,
                _ => return Err(format!("expected an array of {} number(s), got {}", low.len(), shown())),
            };
            if xs.len() != low.len() {
                return Err(format!("expected {} number(s), got {}", low.len(), xs.len()));
            }
            if xs.iter().any(|x| !x.is_finite()) {
                return Err("action values must be finite (and within float32 range)".into());
            }
            Ok(Action::Continuous(xs))
        }
    }
}

/// The longest action line [`ActionStream`] reads (an action of the largest space is a few
/// hundred bytes): a longer line, or a stream without line breaks (`/dev/zero`), is an error
/// after at most this many bytes, not read whole into memory.
pub const MAX_ACTION_LINE: u64 = 1 << 20;

/// The largest actions file (`rollout --actions FILE`, a JSON array) read.
pub const MAX_ACTIONS_FILE: u64 = 64 << 20;

/// Actions read one JSON value per line from a stream (blank lines skipped; each line at most
/// [`MAX_ACTION_LINE`] bytes); the episode stops at the end of the stream.
pub struct ActionStream<R> {
    reader: R,
    space: Space,
    line: String,
}

impl<R: BufRead + Send> ActionStream<R> {
    pub fn new(reader: R, space: Space) -> Self {
        ActionStream {
            reader,
            space,
            line: String::new(),
        }
    }
}

impl<R: BufRead + Send> Policy for ActionStream<R> {
    fn act(&mut self, _obs: &[f32]) -> Result<Option<Action>, PolicyError> {
        loop {
            let read = crate::input::read_line(
                &mut self.reader,
                &mut self.line,
                MAX_ACTION_LINE,
                "an action line",
                "give one JSON action per line",
            );
            match read {
                Ok(0) => return Ok(None),
                Ok(_) if self.line.trim().is_empty() => continue,
                Ok(_) => {
                    let text = self.line.trim();
                    let v: Value = serde_json::from_str(text)
                        .map_err(|e| PolicyError(format!("action \"{}\" is not JSON: {e}", quote_input(text))))?;
                    return parse_action(&v, &self.space).map(Some).map_err(PolicyError);
                }
                Err(e) => return Err(PolicyError(format!("reading actions: {e}"))),
            }
        }
    }
}

/// Actions from a list (a JSON array file); the episode stops when the list ends.
pub struct ActionList {
    actions: std::vec::IntoIter<Value>,
    space: Space,
}

impl ActionList {
    /// Parse a JSON array of actions (`source` names it in errors).
    pub fn parse(text: &str, source: &str, space: Space) -> Result<Self, String> {
        let v: Value = serde_json::from_str(text).map_err(|e| format!("{source}: not JSON: {e}"))?;
        let Value::Array(list) = v else {
            return Err(format!("{source}: expected a JSON array of actions"));
        };
        Ok(ActionList {
            actions: list.into_iter(),
            space,
        })
    }
}

impl Policy for ActionList {
    fn act(&mut self, _obs: &[f32]) -> Result<Option<Action>, PolicyError> {
        match self.actions.next() {
            None => Ok(None),
            Some(v) => parse_action(&v, &self.space).map(Some).map_err(PolicyError),
        }
    }
}

/// A listener that writes the protocol's lines to `out` (flushing each line when `interactive`).
pub struct JsonLinesWriter<W: Write> {
    out: W,
    context: Map<String, Value>,
    interactive: bool,
    /// Report the context the agent observes (the `observed_context.*` entries of the env's
    /// info: noisy copies of the visible features).
    observed: bool,
}

impl<W: Write> JsonLinesWriter<W> {
    pub fn new(out: W, context: Map<String, Value>, interactive: bool) -> Self {
        JsonLinesWriter {
            out,
            context,
            interactive,
            observed: false,
        }
    }

    /// Add `observed_context` (from the env's info) to the reset line and every step line.
    pub fn observing_context(mut self) -> Self {
        self.observed = true;
        self
    }

    /// The full context reported on the next reset lines (a writer that streams several episodes).
    pub fn set_context(&mut self, context: Map<String, Value>) {
        self.context = context;
    }

    /// Write one extra line (e.g. a header before an episode's reset line), flushed like the others.
    pub fn write_line(&mut self, value: &impl Serialize) -> Result<Flow, EpisodeError> {
        let r = serde_json::to_writer(&mut self.out, value)
            .map_err(std::io::Error::from)
            .and_then(|()| self.out.write_all(b"\n"));
        self.done(r)
    }

    /// Flush what is buffered (a failure is an error, a closed pipe is not).
    pub fn finish(mut self) -> Result<(), EpisodeError> {
        match self.out.flush() {
            Err(e) if e.kind() != ErrorKind::BrokenPipe => Err(write_error(&e)),
            _ => Ok(()),
        }
    }

    /// Flush after a line when interactive; a closed pipe stops the episode, other failures are errors.
    fn done(&mut self, r: std::io::Result<()>) -> Result<Flow, EpisodeError> {
        let r = r.and_then(|()| if self.interactive { self.out.flush() } else { Ok(()) });
        match r {
            Ok(()) => Ok(Flow::Continue),
            Err(e) if e.kind() == ErrorKind::BrokenPipe => Ok(Flow::Stop),
            Err(e) => Err(write_error(&e)),
        }
    }
}

/// The `observed_context.<feature>` entries of `env`'s info, by feature.
fn observed_context<E: Env + ?Sized>(env: &E) -> Map<String, Value> {
    env.info()
        .into_iter()
        .filter_map(|(k, v)| Some((k.strip_prefix(OBSERVED_PREFIX)?.to_string(), json!(v))))
        .collect()
}

fn write_error(e: &std::io::Error) -> EpisodeError {
    EpisodeError::Listener(format!("cannot write the output: {e}"))
}

impl<E: Env + ?Sized, W: Write> EpisodeListener<E> for JsonLinesWriter<W> {
    fn on_reset(&mut self, env: &E, obs: &[f32]) -> Result<Flow, EpisodeError> {
        let observed = self.observed.then(|| observed_context(env));
        let r = write_reset(&mut self.out, obs, &self.context, observed.as_ref());
        self.done(r)
    }

    fn on_step(&mut self, env: &E, s: &StepRecord<'_>) -> Result<Flow, EpisodeError> {
        let observed = self.observed.then(|| observed_context(env));
        let r = write_step(&mut self.out, s, observed.as_ref());
        self.done(r)
    }
}
