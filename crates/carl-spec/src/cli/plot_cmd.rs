//! `carl-spec plot ENV/SET --out FILE.svg|FILE.png [--mark ENV/SET]... [--rug ENV/SET]... [--force]`
//!
//! The output path follows `crate::output`'s rule, checked before any set is loaded.

use std::path::PathBuf;

use clap::Args;

use super::instances_cmd::store_failure;
use super::{Cli, CmdResult, Failure, exit, load_specs, out};
use crate::instances::Store;
use crate::output;
use crate::plot::{self, Format, Overlay};

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
    output::check_file(&args.out, args.force).map_err(|e| Failure::usage(e.to_string()))?;

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
    output::write_file(&args.out, &bytes, args.force).map_err(|e| Failure::usage(e.to_string()))?;

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
