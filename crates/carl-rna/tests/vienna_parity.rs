//! Parity with ViennaRNA 2.8.0 (used strictly as a black-box oracle) on the fixtures in
//! ../shared/data/rna/ (generator: scripts/rna_gen_fixtures.py; fields described in that folder's
//! README). Every record must match exactly: energies, per-loop terms and dot-brackets, ties
//! included.

use serde_json::Value;
use std::path::PathBuf;

/// The first `shared/data/rna` beside the repository or one of its parents (CI has `../shared`).
fn data_dir() -> PathBuf {
    let start = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    start
        .ancestors()
        .map(|d| d.join("shared/data/rna"))
        .find(|d| d.join("vienna_fold_fixtures.jsonl").is_file())
        .unwrap_or_else(|| {
            panic!(
                "ViennaRNA fixtures (shared/data/rna) not found beside {} or its parents",
                start.display()
            )
        })
}

fn jsonl(name: &str) -> Vec<Value> {
    let text = std::fs::read_to_string(data_dir().join(name)).unwrap();
    text.lines().map(|l| serde_json::from_str(l).unwrap()).collect()
}

/// Panics listing the first failures (and how many there are) if any.
fn report(what: &str, total: usize, failures: &[String]) {
    if !failures.is_empty() {
        panic!(
            "{what}: {} of {total} records differ from ViennaRNA; first ones:\n{}",
            failures.len(),
            failures.iter().take(15).cloned().collect::<Vec<_>>().join("\n")
        );
    }
    eprintln!("{what}: {total}/{total} identical to ViennaRNA 2.8.0");
}

#[test]
fn eval_fixtures_match_energy_and_every_loop() {
    let records = jsonl("vienna_eval_fixtures.jsonl");
    let mut failures = Vec::new();
    for r in &records {
        let (id, seq, st) = (
            r["id"].as_str().unwrap(),
            r["seq"].as_str().unwrap(),
            r["structure"].as_str().unwrap(),
        );
        let loops = carl_rna::eval_loops(seq, st).unwrap_or_else(|e| panic!("{id}: {e}"));
        let total: i32 = loops.iter().map(|l| l.energy).sum();
        let expected = r["energy_dcal"].as_i64().unwrap() as i32;
        let mut wrong: Vec<String> = Vec::new();
        for term in r["loops"].as_array().unwrap() {
            let t: Vec<i64> = term.as_array().unwrap().iter().map(|v| v.as_i64().unwrap()).collect();
            let closing = if t[0] == 0 {
                None
            } else {
                Some((t[0] as usize, t[1] as usize))
            };
            let ours = loops.iter().find(|l| l.closing == closing).map(|l| l.energy);
            if ours != Some(t[2] as i32) {
                wrong.push(format!("loop {closing:?}: ours {ours:?}, vienna {}", t[2]));
            }
        }
        if total != expected || !wrong.is_empty() {
            failures.push(format!(
                "{id} ({}): ours {total}, vienna {expected}; {}",
                r["kind"],
                wrong.join("; ")
            ));
        }
    }
    report("eval fixtures", records.len(), &failures);
}

#[test]
fn every_interior_loop_table_cell_matches() {
    let text = std::fs::read_to_string(data_dir().join("vienna_interior_tables.tsv")).unwrap();
    let mut failures = Vec::new();
    let mut total = 0;
    for line in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
        let f: Vec<&str> = line.split('\t').collect();
        let (seq, st) = (f[5], f[6]);
        let (energy, interior): (i32, i32) = (f[7].parse().unwrap(), f[8].parse().unwrap());
        let loops = carl_rna::eval_loops(seq, st).unwrap();
        let ours_interior = loops.iter().find(|l| l.closing == Some((1, seq.len()))).unwrap().energy;
        let ours: i32 = loops.iter().map(|l| l.energy).sum();
        total += 1;
        if ours != energy || ours_interior != interior {
            failures.push(format!("{line}: ours {ours} (interior {ours_interior})"));
        }
    }
    assert_eq!(total, 14_400, "interior table rows");
    report("interior-loop table cells", total, &failures);
}

#[test]
fn mfe_energies_and_structures_match_ties_included() {
    let records = jsonl("vienna_fold_fixtures.jsonl");
    let mut failures = Vec::new();
    let (mut tied, mut tied_ok, mut unique, mut unique_ok) = (0, 0, 0, 0);
    for r in &records {
        let (id, seq) = (r["id"].as_str().unwrap(), r["seq"].as_str().unwrap());
        let folded = carl_rna::fold(seq).unwrap();
        let (st, mfe) = (r["structure"].as_str().unwrap(), r["mfe_dcal"].as_i64().unwrap() as i32);
        let ties = r["ties"].as_i64().unwrap();
        let same = folded.structure == st;
        if ties > 1 {
            tied += 1;
            tied_ok += usize::from(same);
        } else {
            unique += 1;
            unique_ok += usize::from(same);
        }
        if folded.energy != mfe || !same {
            let in_ties = r["tied_structures"]
                .as_array()
                .map(|a| a.iter().any(|s| s.as_str() == Some(folded.structure.as_str())));
            failures.push(format!(
                "{id} (n={}, ties {ties}, ours among ties: {in_ties:?}): ours {} {}, vienna {mfe} {st}\n  ours   {}\n  vienna {st}",
                seq.len(),
                folded.energy,
                carl_rna::eval(seq, &folded.structure).unwrap(),
                folded.structure
            ));
        }
    }
    eprintln!("structures: untied {unique_ok}/{unique}, tied {tied_ok}/{tied}");
    report("fold fixtures", records.len(), &failures);
}
