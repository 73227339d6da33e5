//! `carl-spec validate [PATH…] [--format text|json|github]`

use std::io::IsTerminal;
use std::path::PathBuf;

use super::{CmdResult, Failure, Format, exit, out};
use crate::spec::load::validation_inputs;
use crate::validate;

pub fn run(paths: &[PathBuf], format: Format) -> CmdResult {
    let inputs = validation_inputs(paths).map_err(|e| Failure::usage(e.to_string()))?;
    let (_resolved, report) = validate::run(&inputs);
    let summary = format!(
        "{} file(s), {} environment(s): {} error(s), {} warning(s)",
        report.files_checked,
        report.environments,
        report.errors(),
        report.warnings()
    );
    match format {
        Format::Text => {
            let color = std::io::stdout().is_terminal() && std::env::var_os("NO_COLOR").is_none();
            let mut s = String::new();
            for d in &report.diagnostics {
                s.push_str(&d.render_text(color));
                s.push('\n');
            }
            s.push_str(if report.has_errors() { "invalid: " } else { "valid: " });
            s.push_str(&summary);
            s.push('\n');
            out(&s)?;
        }
        Format::Json => {
            out(&format!(
                "{}\n",
                serde_json::to_string_pretty(&report.to_json()).unwrap_or_default()
            ))?;
        }
        Format::Github => {
            let mut s = String::new();
            for d in &report.diagnostics {
                s.push_str(&d.render_github());
                s.push('\n');
            }
            s.push_str(&summary);
            s.push('\n');
            out(&s)?;
        }
    }
    Ok(if report.has_errors() { exit::FAILED } else { exit::OK })
}
