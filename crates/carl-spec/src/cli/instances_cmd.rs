//! `carl-spec instances list|show|verify`, `carl-spec freeze`, `carl-spec sample`.

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::Subcommand;

use super::specs_cmd::value_text;
use super::{Cli, CmdResult, Failure, Format, exit, load_specs, out};
use crate::instances::store::StoreError;
use crate::instances::{FrozenSet, Store, sample_adhoc};

#[derive(Subcommand, Debug)]
pub enum InstancesCommand {
    /// Every declared instance set: kind, size, role, frozen or not.
    List {
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
    },
    /// The instances of one set (ENV/SET), loaded from its frozen file.
    Show {
        /// e.g. lunar_lander/landing_in_space_train
        name: String,
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
    },
    /// Re-derive every declared set and check every frozen file (hash, spec digest, values).
    Verify {
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
    },
}

pub(super) fn store_failure(e: StoreError) -> Failure {
    match e {
        StoreError::BadName(_) | StoreError::Unknown(_) | StoreError::Write { .. } | StoreError::Read { .. } => {
            Failure::usage(e.to_string())
        }
        _ => Failure::failed(e.to_string()),
    }
}

/// The store the instance commands use: run from a checkout (`./specs` holding the bundled
/// specs), the bundled specs' frozen files are the editable ones there, not the binary's copies.
fn store_here(specs: &crate::spec::SpecSet) -> Store<'_> {
    let store = Store::new(specs);
    match Store::find_checkout(std::path::Path::new("")) {
        Some(dir) => store.with_checkout(dir),
        None => store,
    }
}

pub fn instances(cli: &Cli, cmd: &InstancesCommand) -> CmdResult {
    let specs = load_specs(cli)?;
    let store = store_here(&specs);
    match cmd {
        InstancesCommand::List { format } => {
            let rows: Vec<serde_json::Value> = store
                .declared()
                .into_iter()
                .map(|(spec, set)| {
                    let def = &spec.instance_sets[set];
                    let (kind, size) = if let Some(s) = &def.sampled {
                        (format!("sampled({}, seed {})", s.distribution, s.seed), s.size as usize)
                    } else if let Some(e) = &def.explicit {
                        ("explicit".to_string(), e.len())
                    } else if let Some(g) = &def.grid {
                        (format!("grid({})", g.feature), crate::spec::grid_points(g).count())
                    } else {
                        ("?".into(), 0)
                    };
                    let frozen = match store.load(&format!("{}/{set}", spec.id)) {
                        Ok(_) => "frozen".to_string(),
                        Err(StoreError::NotFrozen { .. }) => "NOT FROZEN".into(),
                        Err(StoreError::Stale { .. }) => "STALE".into(),
                        Err(_) => "CORRUPT".into(),
                    };
                    serde_json::json!({"name": format!("{}/{set}", spec.id), "kind": kind, "size": size,
                        "role": def.role, "status": frozen})
                })
                .collect();
            if *format == Format::Json {
                out(&format!(
                    "{}\n",
                    serde_json::to_string_pretty(&rows).unwrap_or_default()
                ))?;
            } else {
                let mut s = format!(
                    "{:<52} {:<6} {:>6}  {:<11} {}\n",
                    "SET", "ROLE", "SIZE", "STATUS", "KIND"
                );
                for r in &rows {
                    let _ = writeln!(
                        s,
                        "{:<52} {:<6} {:>6}  {:<11} {}",
                        r["name"].as_str().unwrap_or(""),
                        r["role"].as_str().unwrap_or("-"),
                        r["size"].as_u64().unwrap_or(0),
                        r["status"].as_str().unwrap_or(""),
                        r["kind"].as_str().unwrap_or("")
                    );
                }
                out(&s)?;
            }
            Ok(exit::OK)
        }
        InstancesCommand::Show { name, format } => {
            let frozen = store.load(name).map_err(store_failure)?;
            print_set(&frozen, *format)?;
            Ok(exit::OK)
        }
        InstancesCommand::Verify { format } => {
            let problems = store.verify();
            let n = store.declared().len();
            let files = store.checked_files();
            let source = store.bundled_source();
            if *format == Format::Json {
                let v = serde_json::json!({"sets": n, "ok": problems.is_empty(), "problems": problems,
                    "files": files, "bundled_sets_from": source});
                out(&format!("{}\n", serde_json::to_string_pretty(&v).unwrap_or_default()))?;
            } else {
                let mut s = String::new();
                if specs.envs().iter().any(|e| e.origin.starts_with("bundled:")) {
                    let _ = writeln!(s, "bundled sets read from {source}");
                }
                for f in &files {
                    let _ = writeln!(s, "checked {f}");
                }
                for p in &problems {
                    let _ = match format {
                        Format::Github => writeln!(s, "::error file={}::{}: {}", p.file, p.set, p.problem),
                        _ => writeln!(s, "error: {} ({}): {}", p.set, p.file, p.problem),
                    };
                }
                let _ = writeln!(
                    s,
                    "{}: {n} instance set(s) checked, {} problem(s)",
                    if problems.is_empty() { "ok" } else { "FAILED" },
                    problems.len()
                );
                out(&s)?;
            }
            Ok(if problems.is_empty() { exit::OK } else { exit::FAILED })
        }
    }
}

pub fn print_set(frozen: &FrozenSet, format: Format) -> Result<(), Failure> {
    if format == Format::Json {
        return out(&frozen.to_text());
    }
    let mut s = String::new();
    let _ = writeln!(s, "{} — {}", frozen.qualified_name(), frozen.description);
    let _ = writeln!(
        s,
        "  {} instance(s); varies: {}; {} / {}",
        frozen.instances.len(),
        frozen.features.join(", "),
        frozen.provenance.rng,
        frozen.provenance.sampler_version
    );
    let _ = write!(s, "\n  {:>5}  {:<10} {:<20}", "ID", "NAME", "SPLIT");
    for f in &frozen.features {
        let _ = write!(s, " {f:>20}");
    }
    s.push('\n');
    for inst in &frozen.instances {
        let split = match inst.split {
            Some(crate::spec::raw::Split::InDistribution) => "in_distribution",
            Some(crate::spec::raw::Split::OutOfDistribution) => "out_of_distribution",
            None => "",
        };
        let _ = write!(
            s,
            "  {:>5}  {:<10} {:<20}",
            inst.id,
            inst.name.as_deref().unwrap_or(""),
            split
        );
        for f in &frozen.features {
            let _ = write!(s, " {:>20}", inst.context.get(f).map(value_text).unwrap_or_default());
        }
        s.push('\n');
    }
    out(&s)
}

pub fn freeze(cli: &Cli, names: &[String], out_dir: Option<&PathBuf>, force: bool) -> CmdResult {
    let specs = load_specs(cli)?;
    let store = store_here(&specs);
    let outcomes = store
        .freeze(names, out_dir.map(PathBuf::as_path), force)
        .map_err(store_failure)?;
    let mut s = String::new();
    for o in &outcomes {
        let _ = writeln!(s, "{:<9} {} -> {}", o.action, o.set, o.file);
    }
    let _ = writeln!(s, "{} set(s) frozen", outcomes.len());
    out(&s)?;
    Ok(exit::OK)
}

pub fn sample(cli: &Cli, env: &str, distribution: &str, n: u64, seed: u64, format: Format) -> CmdResult {
    let specs = load_specs(cli)?;
    let spec = specs.require(env).map_err(Failure::usage)?;
    let set = sample_adhoc(spec, distribution, n, seed).map_err(|e| match e {
        crate::instances::DeriveError::Sampling { .. } => Failure::failed(e.to_string()),
        _ => Failure::usage(e.to_string()),
    })?;
    print_set(&set, format)?;
    Ok(exit::OK)
}
