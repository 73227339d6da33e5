//! The Eterna100 V1 and V2 sample solutions designed for ViennaRNA 2 fold exactly into their
//! targets (81 V1 and 99 V2 solutions; `(unsolved)`/`(undisclosed)` placeholders are skipped).

use std::path::PathBuf;

fn puzzles() -> String {
    let start = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let path = start
        .ancestors()
        .map(|d| d.join("shared/data/rna/eterna100_puzzles.tsv"))
        .find(|p| p.is_file())
        .unwrap_or_else(|| {
            panic!(
                "shared/data/rna/eterna100_puzzles.tsv not found beside {}",
                start.display()
            )
        });
    std::fs::read_to_string(path).unwrap()
}

#[test]
fn vienna2_solutions_fold_into_their_targets() {
    let text = puzzles();
    let header = text.lines().next().unwrap().split('\t');
    let col = |name: &str| {
        header
            .clone()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("column {name}"))
    };
    let columns = [
        (
            "V1",
            col("Secondary Structure V1"),
            col("Sample Solution (V1/Vienna2)"),
            81,
        ),
        (
            "V2",
            col("Secondary Structure V2"),
            col("Sample Solution (V2/Vienna2)"),
            99,
        ),
    ];
    for (version, target_col, solution_col, expected_count) in columns {
        let mut failures = Vec::new();
        let mut count = 0;
        for line in text.lines().skip(1) {
            let f: Vec<&str> = line.split('\t').collect();
            let (target, solution) = (f[target_col], f[solution_col]);
            if solution.starts_with('(') {
                continue; // "(unsolved)" / "(undisclosed)"
            }
            count += 1;
            let folded = carl_rna::fold(solution).unwrap();
            if folded.structure != target {
                failures.push(format!(
                    "puzzle {} ({}): folds into\n{}\nnot\n{target}",
                    f[0], f[1], folded.structure
                ));
            }
        }
        assert_eq!(count, expected_count, "{version} Vienna2 solutions");
        assert!(
            failures.is_empty(),
            "{version}: {} of {count} differ:\n{}",
            failures.len(),
            failures.join("\n")
        );
    }
}
