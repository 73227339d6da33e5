//! `carl-spec fold` / `fold eval`: RNAfold-like output, JSON, FASTA from stdin, and bad input
//! refused with a message and exit status 2.

use std::io::Write;
use std::process::{Command, Stdio};

fn carl_spec(args: &[&str], stdin: &str) -> (i32, String, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_carl-spec"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(stdin.as_bytes()).unwrap();
    let out = child.wait_with_output().unwrap();
    (
        out.status.code().unwrap(),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

#[test]
fn folds_arguments_like_rnafold() {
    let (code, out, _) = carl_spec(&["fold", "GGGGAAACCCC", "acgu"], "");
    assert_eq!(code, 0);
    assert_eq!(out, "GGGGAAACCCC\n((((...)))) ( -4.50)\nACGU\n.... (  0.00)\n");
}

#[test]
fn folds_fasta_from_stdin_as_json() {
    let (code, out, _) = carl_spec(&["fold", "--format", "json"], ">hairpin one\nGGGGAAA\nCCCC\n");
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v[0]["name"], "hairpin one");
    assert_eq!(v[0]["structure"], "((((...))))");
    assert_eq!(v[0]["energy_dcal_per_mol"], -450);
}

#[test]
fn evaluates_given_structures() {
    let (code, out, _) = carl_spec(&["fold", "eval", "GGGGAAACCCC", "(((.....)))"], "");
    assert_eq!(code, 0);
    let expected = carl_rna::eval("GGGGAAACCCC", "(((.....)))").unwrap();
    assert_eq!(
        out,
        format!("GGGGAAACCCC\n(((.....))) ({:6.2})\n", f64::from(expected) / 100.0)
    );
    let (code, out, _) = carl_spec(&["fold", "eval"], "GGGGAAACCCC\n((((...)))) (-4.50)\n");
    assert_eq!((code, out.as_str()), (0, "GGGGAAACCCC\n((((...)))) ( -4.50)\n"));
}

#[test]
fn bad_input_exits_2_with_a_located_message() {
    let long = "A".repeat(carl_rna::MAX_LEN + 1);
    for (args, stdin, message) in [
        (vec!["fold", "GGXA"], "", "position 3: 'X' is not a nucleotide"),
        (vec!["fold", ""], "", "empty sequence"),
        (vec!["fold"], "\n\n", "no sequence given"),
        (
            vec!["fold", long.as_str()],
            "",
            "longer than the supported maximum of 4000 nt",
        ),
        (
            vec!["fold", "eval", "GGGGAAACCCC", "((((...)))"],
            "",
            "structure has 10 characters",
        ),
        (
            vec!["fold", "eval", "GGGGAAACCCC", "((((...))))x"],
            "",
            "structure has 12 characters",
        ),
        (
            vec!["fold", "eval", "GAGGAAACCCC", "((((...))))"],
            "",
            "not a canonical pair",
        ),
        (
            vec!["fold", "--input", "/nonexistent/x.fa"],
            "",
            "cannot read /nonexistent/x.fa",
        ),
    ] {
        let (code, out, err) = carl_spec(&args, stdin);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(out.is_empty(), "{args:?} printed {out}");
        assert!(err.contains(message), "{args:?}: {err}");
    }
}
