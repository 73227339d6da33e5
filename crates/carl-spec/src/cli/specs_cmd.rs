//! `carl-spec list | show ID | schema | stats`: reading the resolved specs.

use std::fmt::Write as _;

use super::{Cli, CmdResult, Failure, Format, exit, load_specs, out};
use crate::spec::model::{EnvSpec, FeatureType, Value};
use crate::spec::stats::compute_stats;

pub fn list(cli: &Cli, format: Format) -> CmdResult {
    let specs = load_specs(cli)?;
    if format == Format::Json {
        let rows: Vec<_> = specs.envs().iter().map(EnvSpec::summary_json).collect();
        out(&format!(
            "{}\n",
            serde_json::to_string_pretty(&rows).unwrap_or_default()
        ))?;
        return Ok(exit::OK);
    }
    let mut s = format!(
        "{:<24} {:<16} {:<34} {:>8}  {}\n",
        "ID", "FAMILY", "UPSTREAM", "FEATURES", "ALIASES"
    );
    for e in specs.envs() {
        let _ = writeln!(
            s,
            "{:<24} {:<16} {:<34} {:>8}  {}",
            e.id,
            e.family,
            format!("{} {}", e.upstream.library, e.upstream.id),
            e.features.len(),
            e.aliases.join(", ")
        );
    }
    out(&s)?;
    Ok(exit::OK)
}

pub fn show(cli: &Cli, id: &str, format: Format) -> CmdResult {
    let specs = load_specs(cli)?;
    let env = specs.require(id).map_err(Failure::usage)?;
    if format == Format::Json {
        out(&format!("{}\n", serde_json::to_string_pretty(env).unwrap_or_default()))?;
        return Ok(exit::OK);
    }
    out(&render_env(env))?;
    Ok(exit::OK)
}

pub fn schema() -> CmdResult {
    out(&crate::schema::schema_text())?;
    Ok(exit::OK)
}

fn num(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        format!("{x:.0}")
    } else {
        format!("{x}")
    }
}

pub fn value_text(v: &Value) -> String {
    match v {
        Value::Bool(b) => b.to_string(),
        Value::Number(x) => num(*x),
        Value::String(s) => s.clone(),
        Value::List(l) => format!("[{}]", l.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", ")),
    }
}

fn render_env(e: &EnvSpec) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{} ({})", e.id, e.aliases.join(", "));
    let _ = writeln!(s, "  family:   {}", e.family);
    let _ = writeln!(
        s,
        "  upstream: {} {}{}",
        e.upstream.library,
        e.upstream.id,
        e.upstream
            .version
            .as_deref()
            .map(|v| format!(" ({v})"))
            .unwrap_or_default()
    );
    let _ = writeln!(
        s,
        "  episode:  {}",
        e.max_episode_steps.map_or("no limit".into(), |n| format!("{n} steps"))
    );
    let _ = writeln!(s, "  {}", e.description);
    let _ = writeln!(
        s,
        "\n  {:<22} {:<11} {:>12}  {:<26} {:<8} AFFECTS",
        "FEATURE", "TYPE", "DEFAULT", "BOUNDS", "UNIT"
    );
    for f in &e.features {
        let ty = match f.kind {
            FeatureType::Categorical => format!("cat(n={})", f.choices.as_ref().map_or(0, Vec::len)),
            k => format!("{k:?}").to_lowercase().replace("listint", "list_int"),
        };
        let default = match (&f.default, &f.default_from) {
            (Some(v), _) => value_text(v),
            (None, Some(d)) => d.clone(),
            _ => "-".into(),
        };
        let bounds = match f.kind {
            FeatureType::Categorical | FeatureType::Bool => "-".to_string(),
            _ => format!(
                "[{}, {}]",
                f.bounds[0].map_or("-inf".into(), num),
                f.bounds[1].map_or("inf".into(), num)
            ),
        };
        let affects: Vec<&str> = f.affects.iter().map(|a| a.as_str()).collect();
        let _ = writeln!(
            s,
            "  {:<22} {:<11} {:>12}  {:<26} {:<8} {}{}",
            f.name,
            ty,
            default,
            bounds,
            f.unit.as_deref().unwrap_or(""),
            affects.join(","),
            f.from_fragment
                .as_deref()
                .map(|fr| format!("  (from {fr})"))
                .unwrap_or_default()
        );
    }
    if !e.distributions.is_empty() {
        let _ = writeln!(
            s,
            "\n  distributions: {}",
            e.distributions.keys().cloned().collect::<Vec<_>>().join(", ")
        );
    }
    if !e.instance_sets.is_empty() {
        let _ = writeln!(
            s,
            "  instance sets: {}",
            e.instance_sets.keys().cloned().collect::<Vec<_>>().join(", ")
        );
    }
    s
}

pub fn stats(cli: &Cli, format: Format) -> CmdResult {
    let specs = load_specs(cli)?;
    let st = compute_stats(specs.envs());
    if format == Format::Json {
        out(&format!("{}\n", serde_json::to_string_pretty(&st).unwrap_or_default()))?;
        return Ok(exit::OK);
    }
    let pct = |n: usize| {
        if st.features == 0 {
            0.0
        } else {
            100.0 * n as f64 / st.features as f64
        }
    };
    let mut s = String::new();
    let _ = writeln!(s, "{:<28} {:>10} {:>10}", "", "carl-spec", "paper");
    let _ = writeln!(s, "{:<28} {:>10} {:>10}", "environments", st.environments, 16);
    let _ = writeln!(s, "{:<28} {:>10} {:>10}", "context features", st.features, 131);
    let _ = writeln!(s, "{:<28} {:>9.0}% {:>9}%", "affect dynamics", pct(st.dynamics), 98);
    let _ = writeln!(s, "{:<28} {:>9.0}% {:>9}%", "affect reward", pct(st.reward), 5);
    let _ = writeln!(
        s,
        "{:<28} {:>9.0}% {:>9}%",
        "continuous (float)",
        pct(st.continuous),
        87
    );
    let _ = writeln!(s, "\nfeatures per effect:");
    for (e, n) in &st.per_effect {
        let _ = writeln!(s, "  {e:<20} {n:>4} ({:.0}%)", pct(*n));
    }
    out(&s)?;
    Ok(exit::OK)
}
