//! `carl-spec audit ENV|--all [--format text|json]`: check every feature's `affects` claim against
//! its runtime. Exit 0 when every claim holds, 1 on a contradiction, 2 for an unknown environment or
//! one without a runtime.

use std::fmt::Write as _;

use super::{Cli, CmdResult, Failure, Format, exit, load_specs, out};
use crate::audit::{self, AuditReport, EffectResult, Measured, Verdict, format_num};
use crate::envs::registry::{has_runtime, ids_text};
use crate::spec::model::Effect;

pub fn run(cli: &Cli, env: Option<&str>, all: bool, format: Format) -> CmdResult {
    let specs = load_specs(cli)?;
    let targets: Vec<&crate::spec::EnvSpec> = if all {
        specs.envs().iter().filter(|e| has_runtime(&e.id)).collect()
    } else {
        let Some(name) = env else {
            return Err(Failure::usage(format!(
                "name an environment or pass --all; environments with a runtime: {}",
                ids_text()
            )));
        };
        let spec = specs
            .require(name)
            .map_err(|m| Failure::usage(format!("{m}; environments with a runtime: {}", ids_text())))?;
        if !has_runtime(&spec.id) {
            return Err(Failure::usage(format!(
                "environment \"{}\" has a spec but no runtime, so it cannot be audited; environments with a runtime: {}",
                spec.id,
                ids_text()
            )));
        }
        vec![spec]
    };
    let mut reports = Vec::with_capacity(targets.len());
    let progress = super::progress::Progress::bar(targets.len() as u64, "environments audited");
    for spec in targets {
        progress.message(spec.id.clone());
        reports.push(audit::audit(spec).map_err(|e| Failure::failed(e.to_string()))?);
        progress.inc(1);
    }
    progress.finish();
    let passed = reports.iter().all(|r| r.passed);
    match format {
        Format::Json => {
            let text = if all {
                serde_json::to_string_pretty(&reports)
            } else {
                serde_json::to_string_pretty(&reports[0])
            };
            out(&format!("{}\n", text.unwrap_or_default()))?;
        }
        Format::Text | Format::Github => {
            let mut s = String::new();
            for (i, r) in reports.iter().enumerate() {
                if i > 0 {
                    s.push('\n');
                }
                s.push_str(&render_text(r));
            }
            if reports.len() > 1 {
                let failed: Vec<&str> = reports.iter().filter(|r| !r.passed).map(|r| r.env.as_str()).collect();
                let _ = writeln!(
                    s,
                    "\n{} environment(s) audited: {}",
                    reports.len(),
                    if failed.is_empty() {
                        "all claims hold".to_string()
                    } else {
                        format!("contradictions in {}", failed.join(", "))
                    }
                );
            }
            out(&s)?;
        }
    }
    Ok(if passed { exit::OK } else { exit::FAILED })
}

/// The columns of the table (task generation is shown only when a feature claims it).
fn columns(r: &AuditReport) -> Vec<Effect> {
    let any_task = r.features.iter().any(|f| f.claimed.contains(&Effect::TaskGeneration));
    Effect::ALL
        .into_iter()
        .filter(|e| *e != Effect::TaskGeneration || any_task)
        .collect()
}

fn cell(e: &EffectResult) -> String {
    let mag = format_num(e.max_abs_diff);
    match (e.verdict, e.measured) {
        (Verdict::NotApplicable, _) => if e.claimed { "n/a (claimed)" } else { "n/a" }.into(),
        (Verdict::MissingEffect, _) => "✗ MISSING".into(),
        (Verdict::UndeclaredEffect, _) => format!("✗ UNDECLARED {mag}"),
        (Verdict::Ok, Measured::Changed) => format!("✓ {mag}"),
        (Verdict::Ok, Measured::ViaDynamics) if e.claimed => "✓ ~dyn".into(),
        (Verdict::Ok, Measured::ViaDynamics) => "· ~dyn".into(),
        (Verdict::Ok, _) => "·".into(),
    }
}

/// The text report of one environment.
pub fn render_text(r: &AuditReport) -> String {
    let cols = columns(r);
    let name_w = r
        .features
        .iter()
        .map(|f| f.name.chars().count())
        .max()
        .unwrap_or(7)
        .max(7);
    let rows: Vec<(String, Vec<String>)> = r
        .features
        .iter()
        .map(|f| {
            let cells = match &f.skipped {
                Some(why) => vec![format!("skipped: {why}")],
                None => cols
                    .iter()
                    .map(|c| f.effect(*c).map(cell).unwrap_or_default())
                    .collect(),
            };
            (f.name.clone(), cells)
        })
        .collect();
    let widths: Vec<usize> = cols
        .iter()
        .enumerate()
        .map(|(i, c)| {
            rows.iter()
                .filter(|(_, cells)| cells.len() == cols.len())
                .map(|(_, cells)| cells[i].chars().count())
                .chain([c.as_str().len()])
                .max()
                .unwrap_or(0)
        })
        .collect();

    let p = &r.probes;
    let mut s = format!(
        "audit {}: {} feature(s); {} base states × {} actions per value, {} reset seeds\n\n",
        r.env,
        r.features.len(),
        p.base_states,
        p.actions,
        p.reset_seeds
    );
    let _ = write!(s, "{:<name_w$}  {:>6}", "feature", "values");
    for (c, w) in cols.iter().zip(&widths) {
        let _ = write!(s, "  {:<w$}", c.as_str());
    }
    s = s.trim_end().to_string();
    s.push('\n');
    for ((name, cells), f) in rows.iter().zip(&r.features) {
        let mut line = format!("{name:<name_w$}  {:>6}", f.values.len());
        for (c, w) in cells.iter().zip(&widths) {
            let _ = write!(line, "  {c:<w$}");
        }
        s.push_str(line.trim_end());
        s.push('\n');
    }
    s.push_str(
        "\n✓ claimed and measured (max |Δ|)   · not claimed, not measured   ~dyn changed only together with the next state\n",
    );
    if r.passed {
        let _ = writeln!(s, "{}: ok, every claim matches the runtime", r.env);
    } else {
        for c in &r.contradictions {
            let _ = writeln!(s, "✗ {} {}: {}", r.env, c.verdict.as_str(), c.message);
        }
        let _ = writeln!(s, "{}: FAILED, {} contradiction(s)", r.env, r.contradictions.len());
    }
    s
}
