//! Folds each sequence given on the command line (or one per stdin line) and prints the
//! structure, the MFE in kcal/mol and the time the fold took (for scripts/rna_bench.py).
use std::io::BufRead;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let seqs: Vec<String> = if args.is_empty() {
        std::io::stdin()
            .lock()
            .lines()
            .map(|l| l.expect("stdin"))
            .filter(|l| !l.trim().is_empty())
            .collect()
    } else {
        args
    };
    for seq in seqs {
        let start = Instant::now();
        match carl_rna::fold(seq.trim()) {
            Ok(f) => println!(
                "{} {:.2} {:.6}",
                f.structure,
                f.energy_kcal(),
                start.elapsed().as_secs_f64()
            ),
            Err(e) => {
                eprintln!("error: {e}");
                std::process::exit(1);
            }
        }
    }
}
