//! `carl-spec plot ENV/SET --out FILE.svg|FILE.png [--mark ENV/SET]... [--rug ENV/SET]... [--force]`

use std::path::{Path, PathBuf};

use clap::Args;

use super::instances_cmd::store_failure;
use super::{Cli, CmdResult, Failure, exit, load_specs, out};
use crate::instances::Store;
use crate::plot::{self, Format, Overlay, WriteError};

#[derive(Args, Debug)]
pub struct PlotArgs {
    /// The instance set to draw, e.g. lunar_lander/landing_in_space_train.
    pub name: String,
    /// Output file; the format follows the extension (.svg or .png).
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Overlay another set of the same environment: named instances as labelled markers coloured
    /// by their split, unnamed ones as a rug (repeatable).
    #[arg(long, value_name = "ENV/SET")]
    pub mark: Vec<String>,
    /// Overlay another set's values as a rug of ticks (repeatable).
    #[arg(long, value_name = "ENV/SET")]
    pub rug: Vec<String>,
    /// Number of histogram bins (default: Freedman–Diaconis rule, square-root rule as fallback).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=200))]
    pub bins: Option<u16>,
    /// Replace FILE if it exists.
    #[arg(long)]
    pub force: bool,
}

pub fn plot(cli: &Cli, args: &PlotArgs) -> CmdResult {
    // Check everything that needs no work first, so a bad call writes nothing.
    let format = Format::from_path(&args.out).map_err(Failure::usage)?;
    check_target(&args.out, args.force)?;

    let specs = load_specs(cli)?;
    let store = Store::new(&specs);
    let set = store.load(&args.name).map_err(store_failure)?;
    let (spec, _) = store.resolve(&args.name).map_err(store_failure)?;
    let mut loaded = Vec::new();
    for (how, names) in [(Overlay::Mark, &args.mark), (Overlay::Rug, &args.rug)] {
        for name in names {
            loaded.push((how, store.load(name).map_err(store_failure)?));
        }
    }
    let overlays: Vec<(Overlay, &crate::instances::FrozenSet)> = loaded.iter().map(|(h, s)| (*h, s)).collect();
    let (figure, warnings) =
        plot::build(spec, &set, &overlays, args.bins.map(usize::from)).map_err(|e| Failure::usage(e.to_string()))?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    let bytes = plot::render(&figure, format).map_err(Failure::failed)?;
    plot::write_output(&args.out, &bytes, args.force).map_err(write_failure)?;

    let marks: usize = figure.panels.iter().map(|p| p.marks.len()).sum();
    let rugs: usize = figure.panels.iter().map(|p| p.rugs.len()).sum();
    let features: Vec<&str> = figure.panels.iter().map(|p| p.feature.as_str()).collect();
    out(&format!(
        "wrote {} ({}: {} instances, {} panel(s): {}; {marks} marked, {rugs} rug(s))\n",
        args.out.display(),
        figure.title,
        set.instances.len(),
        figure.panels.len(),
        features.join(", "),
    ))?;
    Ok(exit::OK)
}

fn write_failure(e: WriteError) -> Failure {
    Failure::usage(e.to_string())
}

/// Fail early (before loading anything) when the output could not or must not be written.
fn check_target(path: &Path, force: bool) -> Result<(), Failure> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if !dir.is_dir() {
        return Err(write_failure(WriteError::NoDir {
            path: path.display().to_string(),
            dir: dir.display().to_string(),
        }));
    }
    if path.is_dir() {
        return Err(Failure::usage(format!("{} is a directory", path.display())));
    }
    if !force && path.symlink_metadata().is_ok() {
        return Err(write_failure(WriteError::Exists(path.display().to_string())));
    }
    Ok(())
}
