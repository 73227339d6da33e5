//! `carl-spec fold [SEQ]... [--input FILE|-] [--format json]` and
//! `carl-spec fold eval [SEQ STRUCTURE] [--input FILE|-]`: RNAfold/RNAeval-like front end of the
//! carl-rna folding engine (ViennaRNA 2.x default model). Output as RNAfold prints it:
//! `>name`, the sequence, then `STRUCTURE (  MFE)` in kcal/mol.

use std::path::PathBuf;

use clap::{Args, Subcommand};

use super::{CmdResult, Failure, Format, exit, out};
use carl_rna::input::{Record, records};

#[derive(Args, Debug)]
#[command(args_conflicts_with_subcommands = true)]
pub struct FoldArgs {
    #[command(subcommand)]
    pub command: Option<FoldCommand>,
    /// RNA sequences (A, C, G, U or T, any case; at most 4000 nt). None: read --input or stdin.
    pub sequences: Vec<String>,
    #[command(flatten)]
    pub io: FoldIo,
}

#[derive(Args, Debug)]
pub struct FoldIo {
    /// FASTA file (or one sequence per line; `-` for stdin).
    #[arg(long, short = 'i', value_name = "FILE")]
    pub input: Option<PathBuf>,
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub format: Format,
}

#[derive(Subcommand, Debug)]
pub enum FoldCommand {
    /// Free energy of given structures (sequence line then dot-bracket line per record).
    Eval {
        /// The sequence and its structure; none: read --input or stdin.
        #[arg(num_args = 2, value_names = ["SEQ", "STRUCTURE"])]
        pair: Vec<String>,
        #[command(flatten)]
        io: FoldIo,
    },
}

pub fn run(args: &FoldArgs) -> CmdResult {
    match &args.command {
        Some(FoldCommand::Eval { pair, io }) => eval(pair, io),
        None => fold(&args.sequences, &args.io),
    }
}

fn fold(sequences: &[String], io: &FoldIo) -> CmdResult {
    let input = if sequences.is_empty() {
        read_records(io, 1)?
    } else {
        sequences
            .iter()
            .map(|s| Record {
                name: None,
                lines: vec![s.clone()],
            })
            .collect()
    };
    let mut results = Vec::new();
    for (k, record) in input.iter().enumerate() {
        let seq = checked_sequence(k, record, &record.lines.concat())?;
        let folded = carl_rna::fold(&seq).map_err(|e| Failure::usage(format!("{}: {e}", label(k, record))))?;
        results.push((record, seq, folded.structure, folded.energy));
    }
    print_results(&results, io.format)?;
    Ok(exit::OK)
}

fn eval(pair: &[String], io: &FoldIo) -> CmdResult {
    let input = if pair.is_empty() {
        read_records(io, 2)?
    } else {
        vec![Record {
            name: None,
            lines: pair.to_vec(),
        }]
    };
    let mut results = Vec::new();
    for (k, record) in input.iter().enumerate() {
        let [seq, structure] = record.lines.as_slice() else {
            return Err(Failure::usage(format!(
                "{}: expected a sequence line and a structure line, got {} line(s)",
                label(k, record),
                record.lines.len()
            )));
        };
        let seq = checked_sequence(k, record, seq)?;
        // RNAeval-style input may carry an energy after the structure: keep the dot-bracket.
        let structure = structure.split_whitespace().next().unwrap_or_default();
        let energy =
            carl_rna::eval(&seq, structure).map_err(|e| Failure::usage(format!("{}: {e}", label(k, record))))?;
        results.push((record, seq, structure.to_string(), energy));
    }
    print_results(&results, io.format)?;
    Ok(exit::OK)
}

/// The most input `fold` reads from --input or stdin (a sequence is at most 4000 nt, so this
/// is thousands of them): more is an error after this many bytes, not read whole first.
pub const MAX_FOLD_INPUT: u64 = 64 << 20;

fn read_records(io: &FoldIo, lines_per_record: usize) -> Result<Vec<Record>, Failure> {
    const HINT: &str = "split it into several runs";
    let text = match &io.input {
        Some(path) if path.as_os_str() != "-" => crate::input::read_file(path, MAX_FOLD_INPUT, HINT),
        _ => crate::input::read_to_string(std::io::stdin().lock(), MAX_FOLD_INPUT, "stdin", HINT),
    }
    .map_err(|e| Failure::usage(format!("--input: {e}")))?;
    let found = records(&text, lines_per_record);
    if found.is_empty() {
        return Err(Failure::usage("no sequence given (arguments, --input FILE or stdin)"));
    }
    Ok(found)
}

/// The sequence in canonical spelling, or a usage error naming the record.
fn checked_sequence(k: usize, record: &Record, seq: &str) -> Result<String, Failure> {
    if seq.is_empty() {
        return Err(Failure::usage(format!("{}: empty sequence", label(k, record))));
    }
    carl_rna::normalize(seq).map_err(|e| Failure::usage(format!("{}: {e}", label(k, record))))
}

fn label(k: usize, record: &Record) -> String {
    match &record.name {
        Some(name) => format!("sequence {} ({name})", k + 1),
        None => format!("sequence {}", k + 1),
    }
}

fn print_results(results: &[(&Record, String, String, i32)], format: Format) -> Result<(), Failure> {
    if format == Format::Json {
        let items: Vec<serde_json::Value> = results
            .iter()
            .map(|(record, seq, structure, energy)| {
                serde_json::json!({
                    "name": record.name,
                    "sequence": seq,
                    "structure": structure,
                    "energy_kcal_per_mol": f64::from(*energy) / 100.0,
                    "energy_dcal_per_mol": energy,
                })
            })
            .collect();
        return out(&format!("{}\n", serde_json::to_string_pretty(&items).expect("JSON")));
    }
    let mut text = String::new();
    for (record, seq, structure, energy) in results {
        if let Some(name) = &record.name {
            text.push_str(&format!(">{name}\n"));
        }
        text.push_str(&format!("{seq}\n{structure} ({:6.2})\n", f64::from(*energy) / 100.0));
    }
    out(&text)
}
