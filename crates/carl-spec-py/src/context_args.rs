//! What `make` / `make_vec` (and users' wrapped envs) pass about contexts: the source (context,
//! instance set, distribution), selection, visibility and noise, turned into the library's options.

use pyo3::prelude::*;

use carl_spec::envs::contextual::{
    ContextNoise, ContextSource, ContextualEnv, ContextualOptions, NoiseRedraw, NoiseStd,
};
use carl_spec::envs::registry::{Context, EnvOptions, MakeError, has_runtime, ids_text};
use carl_spec::envs::schedules::parse_schedules;
use carl_spec::envs::{Features, Selection, Visibility};
use carl_spec::instances::Store;
use carl_spec::spec::SpecSet;

use crate::errors::{contextual_error, store_error, unknown_name, value_error};
use crate::specs::require;

/// Everything `make` / `make_vec` pass about contexts, as the Python constructors hand it over.
#[derive(Clone)]
pub(crate) struct SourceArgs {
    pub(crate) context_json: Option<String>,
    pub(crate) instances: Option<String>,
    pub(crate) distribution: Option<String>,
    pub(crate) selection: String,
    pub(crate) instance: Option<usize>,
    pub(crate) obs_context: Option<Vec<String>>,
    pub(crate) obs_context_all: bool,
    /// Variant options (`{"continuous": true}`), as a JSON object.
    pub(crate) options_json: Option<String>,
    pub(crate) noise: ContextNoise,
    pub(crate) allow_out_of_bounds: bool,
    /// Features changing within episodes, `{"feature": {"kind": ...}}` as JSON.
    pub(crate) schedules_json: Option<String>,
    /// A curriculum chooses the contexts: the batch keeps the contextual wrapper.
    pub(crate) curriculum: bool,
}

impl Default for SourceArgs {
    /// The default context, hidden, without noise.
    fn default() -> Self {
        SourceArgs {
            context_json: None,
            instances: None,
            distribution: None,
            selection: "round_robin".into(),
            instance: None,
            obs_context: None,
            obs_context_all: false,
            options_json: None,
            noise: ContextNoise {
                features: Vec::new(),
                redraw: NoiseRedraw::Episode,
            },
            allow_out_of_bounds: false,
            schedules_json: None,
            curriculum: false,
        }
    }
}

impl SourceArgs {
    pub(crate) fn context(&self) -> PyResult<Context> {
        match &self.context_json {
            Some(text) => serde_json::from_str(text).map_err(|e| value_error(format!("context: {e}"))),
            None => Ok(Context::new()),
        }
    }

    pub(crate) fn env_options(&self) -> PyResult<EnvOptions> {
        match &self.options_json {
            Some(text) => serde_json::from_str(text).map_err(|e| {
                value_error(format!(
                    "options: {e} (values are true/false, numbers or lists of numbers)"
                ))
            }),
            None => Ok(EnvOptions::new()),
        }
    }

    /// A fixed context without visible features: the plain batch (no contextual wrapper).
    pub(crate) fn is_plain(&self) -> bool {
        self.instances.is_none()
            && self.distribution.is_none()
            && self.obs_context.as_ref().is_none_or(Vec::is_empty)
            && !self.obs_context_all
            && self.noise.is_empty()
            && self.schedules_json.is_none()
            && !self.curriculum
    }
}

/// The contextual environment `env` that `a` describes, checked against `specs`.
pub(crate) fn build_contextual(py: Python<'_>, specs: &SpecSet, env: &str, a: &SourceArgs) -> PyResult<ContextualEnv> {
    let spec = require(py, specs, env)?;
    if !has_runtime(&spec.id) {
        return Err(unknown_name(
            py,
            MakeError::NoRuntime {
                env: spec.id.clone(),
                available: ids_text(),
            }
            .to_string(),
        ));
    }
    let given = [
        a.context_json.is_some(),
        a.instances.is_some(),
        a.distribution.is_some(),
    ];
    if given.iter().filter(|g| **g).count() > 1 {
        return Err(value_error(
            "give at most one of context=, instances= and distribution=",
        ));
    }
    if a.allow_out_of_bounds && (a.instances.is_some() || a.distribution.is_some()) {
        return Err(value_error(
            "allow_out_of_bounds=True applies to a fixed context= (an instance set declares its own \
             out-of-bounds policy; distribution draws are always inside the bounds)",
        ));
    }
    let source = if let Some(name) = &a.instances {
        let name = if name.contains('/') {
            name.clone()
        } else {
            format!("{}/{name}", spec.id)
        };
        ContextSource::Set(Store::new(specs).load(&name).map_err(|e| store_error(py, e))?)
    } else if let Some(name) = &a.distribution {
        ContextSource::Distribution { name: name.clone() }
    } else {
        ContextSource::Fixed(a.context()?)
    };
    let selection = parse_selection(&a.selection, a.instance)?;
    let visibility = if a.obs_context_all {
        Visibility::Visible(Features::All)
    } else {
        match &a.obs_context {
            Some(names) if !names.is_empty() => Visibility::Visible(Features::Only(names.clone())),
            _ => Visibility::Hidden,
        }
    };
    if !a.noise.is_empty() && visibility == Visibility::Hidden {
        return Err(value_error(NOISE_NEEDS_OBS_CONTEXT));
    }
    ContextualEnv::new(
        spec,
        source,
        ContextualOptions {
            selection,
            visibility,
            noise: a.noise.clone(),
            env_options: a.env_options()?,
            allow_out_of_bounds: a.allow_out_of_bounds,
            schedules: match &a.schedules_json {
                Some(text) => parse_schedules(text).map_err(value_error)?,
                None => Vec::new(),
            },
        },
    )
    .map_err(|e| contextual_error(py, &e))
}

/// Everything about contexts that `make`, `make_vec` and `wrap` take, as one frozen value: built
/// once by `carl_spec._args.context_args` from the public keyword arguments (`context` and
/// `options` as JSON objects, `context_noise` as `(feature, "absolute" | "relative", std)`
/// triples; `obs_context`: a list of feature names or True) and handed to `Env`, `VecEnv` and
/// `ContextChooser`. This constructor is the one place the binding reads those arguments.
#[pyclass(module = "carl_spec._core", frozen, name = "ContextArgs")]
pub(crate) struct ContextArgs {
    pub(crate) source: SourceArgs,
}

#[pymethods]
impl ContextArgs {
    #[new]
    #[pyo3(signature = (*, context=None, instances=None, distribution=None, selection="round_robin", instance=None, obs_context=None, context_noise=None, context_noise_redraw="episode", options=None, allow_out_of_bounds=false, schedules=None, curriculum=false))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        context: Option<String>,
        instances: Option<String>,
        distribution: Option<String>,
        selection: &str,
        instance: Option<&Bound<'_, PyAny>>,
        obs_context: Option<&Bound<'_, PyAny>>,
        context_noise: Option<Vec<(String, String, f64)>>,
        context_noise_redraw: &str,
        options: Option<String>,
        allow_out_of_bounds: bool,
        schedules: Option<String>,
        curriculum: bool,
    ) -> PyResult<Self> {
        let (obs_context, obs_context_all) = match obs_context {
            None => (None, false),
            Some(v) if v.is_none() => (None, false),
            Some(v) => match v.extract::<bool>() {
                Ok(all) => (None, all),
                Err(_) => (Some(v.extract::<Vec<String>>()?), false),
            },
        };
        let instance = match instance {
            None => None,
            Some(v) if v.is_none() => None,
            Some(v) => Some(
                v.extract::<usize>()
                    .map_err(|_| value_error(format!("instance must be a non-negative int, got {}", short_repr(v))))?,
            ),
        };
        Ok(ContextArgs {
            source: SourceArgs {
                context_json: context,
                instances,
                distribution,
                selection: selection.to_string(),
                instance,
                obs_context,
                obs_context_all,
                options_json: options,
                noise: context_noise_arg(context_noise, context_noise_redraw)?,
                allow_out_of_bounds,
                schedules_json: schedules,
                curriculum,
            },
        })
    }
}

/// `repr(v)` escaped and cut, for messages.
pub(crate) fn short_repr(v: &Bound<'_, PyAny>) -> String {
    let text = v.repr().map(|r| r.to_string()).unwrap_or_else(|_| "?".into());
    carl_spec::text::escape(&text)
}

/// The source a native constructor was given (`None`: the default context).
pub(crate) fn source_of(args: Option<&Bound<'_, ContextArgs>>) -> SourceArgs {
    args.map_or_else(SourceArgs::default, |a| a.get().source.clone())
}

/// Largest noise std: draws many std away still fit a float32 observation (3.4e38).
const MAX_NOISE_STD: f64 = 1e36;

pub(crate) const NOISE_NEEDS_OBS_CONTEXT: &str =
    "context_noise applies to observed context features: name them in obs_context= (or obs_context=True)";

/// `context_noise=` as the Python package passes it (`(feature, "absolute" | "relative", std)`
/// triples) and `context_noise_redraw=`.
pub(crate) fn context_noise_arg(noise: Option<Vec<(String, String, f64)>>, redraw: &str) -> PyResult<ContextNoise> {
    let redraw = match redraw {
        "episode" => NoiseRedraw::Episode,
        "step" => NoiseRedraw::Step,
        other => {
            return Err(value_error(format!(
                "context_noise_redraw must be \"episode\" or \"step\", got {}",
                carl_spec::text::quote(other)
            )));
        }
    };
    let mut features = Vec::new();
    for (name, kind, std) in noise.unwrap_or_default() {
        let problem = if !std.is_finite() {
            Some("is not a finite number".to_string())
        } else if std < 0.0 {
            Some("must be >= 0".to_string())
        } else if std > MAX_NOISE_STD {
            Some(format!(
                "is too large: at most {MAX_NOISE_STD:e} (observations are float32)"
            ))
        } else {
            None
        };
        if let Some(problem) = problem {
            return Err(value_error(format!(
                "context_noise[{}]: std {std} {problem}",
                carl_spec::text::quote(&name)
            )));
        }
        let std = match kind.as_str() {
            "absolute" => NoiseStd::Absolute(std),
            "relative" => NoiseStd::Relative(std),
            other => {
                return Err(value_error(format!(
                    "context_noise[{}]: kind must be \"absolute\" or \"relative\", got {}",
                    carl_spec::text::quote(&name),
                    carl_spec::text::quote(other)
                )));
            }
        };
        features.push((name, std));
    }
    Ok(ContextNoise { features, redraw })
}

/// `selection=` and `instance=` as the Python constructors take them.
pub(crate) fn parse_selection(selection: &str, instance: Option<usize>) -> PyResult<Selection> {
    match (selection, instance) {
        ("round_robin", None) => Ok(Selection::RoundRobin),
        ("random", None) => Ok(Selection::Random),
        ("static", Some(i)) => Ok(Selection::Static(i)),
        ("static", None) => Err(value_error("selection=\"static\" needs instance=<index>")),
        (_, Some(_)) => Err(value_error("instance= goes with selection=\"static\"")),
        (other, None) => Err(value_error(format!(
            "selection must be \"round_robin\", \"random\" or \"static\", got {}",
            carl_spec::text::quote(other)
        ))),
    }
}
