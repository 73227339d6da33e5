//! Instance sets: golden values, bounds, freeze/load/verify round trips and tamper detection.

use std::path::{Path, PathBuf};
use std::process::Command;

use carl_spec::instances::{Store, derive_set};
use carl_spec::spec::SpecSet;
use carl_spec::spec::load::read_inputs;
use carl_spec::spec::model::Value;

fn num(v: &Value) -> f64 {
    match v {
        Value::Number(x) => *x,
        other => panic!("not a number: {other:?}"),
    }
}

/// The Landing-in-Space training gravities, pinned bit for bit (first five) and as a whole.
#[test]
fn landing_in_space_train_golden_vector() {
    let specs = SpecSet::bundled().unwrap();
    let set = Store::new(&specs).load("lunar_lander/landing_in_space_train").unwrap();
    assert_eq!(set.instances.len(), 100);
    let g: Vec<f64> = set.instances.iter().map(|i| num(&i.context["GRAVITY_Y"])).collect();
    let first: Vec<u64> = g[..5].iter().map(|x| x.to_bits()).collect();
    assert_eq!(
        first,
        [
            (-3.7038216476692747f64).to_bits(),
            (-1.8541737510027436f64).to_bits(),
            (-2.737987790924789f64).to_bits(),
            (-3.891993911360996f64).to_bits(),
            GOLDEN_5.to_bits(),
        ]
    );
    // Sum of all 100 values' bits (wrapping), a cheap fingerprint of the whole vector.
    let fp = g
        .iter()
        .fold(0u64, |acc, x| acc.wrapping_mul(31).wrapping_add(x.to_bits()));
    assert_eq!(fp, GOLDEN_FINGERPRINT, "the frozen training set changed");
    // All inside the feature's bounds, and roughly the intended distribution.
    assert!(g.iter().all(|x| (-20.0..=-0.01).contains(x)));
    let mean = g.iter().sum::<f64>() / 100.0;
    assert!((mean - -3.697).abs() < 0.4, "mean {mean}");
    // Loading is deriving: the frozen file equals a fresh derivation.
    let derived = derive_set(specs.get("lunar_lander").unwrap(), "landing_in_space_train").unwrap();
    assert_eq!(derived, set);
}

const GOLDEN_5: f64 = -1.5209869430185945;
const GOLDEN_FINGERPRINT: u64 = 8926183852425690952;

#[test]
fn paper_sets_are_complete_and_in_bounds() {
    let specs = SpecSet::bundled().unwrap();
    let store = Store::new(&specs);
    let planets = store.load("lunar_lander/landing_in_space_test_planets").unwrap();
    let names: Vec<String> = planets.instances.iter().map(|i| i.label()).collect();
    assert_eq!(names, ["Jupiter", "Neptune", "Earth", "Mars", "Moon", "Pluto"]);
    assert_eq!(num(&planets.instances[0].context["GRAVITY_Y"]), -23.143693999999996);
    let grid = store.load("lunar_lander/landing_in_space_test_grid").unwrap();
    let g: Vec<f64> = grid.instances.iter().map(|i| num(&i.context["GRAVITY_Y"])).collect();
    assert_eq!(g.len(), 50);
    assert_eq!((g[0], g[49]), (-25.0, -0.5));
    let two = store.load("lunar_lander/landing_in_space_train_two_intervals").unwrap();
    let v: Vec<f64> = two.instances.iter().map(|i| num(&i.context["GRAVITY_Y"])).collect();
    assert!(v[..50].iter().all(|x| (-20.0..=-15.0).contains(x)));
    assert!(v[50..].iter().all(|x| (-5.0..=-0.01).contains(x)));
    for feat in ["dt", "g", "l", "m", "max_speed"] {
        for sigma in ["0_1", "0_25", "0_5"] {
            let set = store.load(&format!("pendulum/q1_{feat}_sigma_{sigma}")).unwrap();
            assert_eq!(set.instances.len(), 100);
            assert_eq!(set.features, [feat]);
            let f = specs.get("pendulum").unwrap().feature(feat).unwrap();
            assert!(set.instances.iter().all(|i| f.in_bounds(num(&i.context[feat]))));
        }
    }
    assert!(store.verify().is_empty(), "{:?}", store.verify());
}

#[test]
fn unknown_names_get_did_you_mean() {
    let specs = SpecSet::bundled().unwrap();
    let store = Store::new(&specs);
    let e = store
        .load("lunar_lander/landing_in_space_trian")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("did you mean \"lunar_lander/landing_in_space_train\""),
        "{e}"
    );
    let e = store
        .load("lunar_lnder/landing_in_space_train")
        .unwrap_err()
        .to_string();
    assert!(e.contains("did you mean \"lunar_lander\""), "{e}");
    assert!(store.load("lunar_lander").is_err());
}

fn tempdir(tag: &str) -> PathBuf {
    let p = std::env::temp_dir().join(format!("carl-spec-inst-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&p);
    std::fs::create_dir_all(&p).unwrap();
    p
}

fn author_set(dir: &Path) -> SpecSet {
    SpecSet::from_inputs(&read_inputs(&[dir.to_path_buf()]).unwrap()).unwrap()
}

#[test]
fn freeze_verify_and_tamper_detection_in_an_author_dir() {
    let dir = tempdir("tamper");
    std::fs::copy(
        concat!(env!("CARGO_MANIFEST_DIR"), "/../../specs/lunar_lander.json"),
        dir.join("lunar_lander.json"),
    )
    .unwrap();
    let specs = author_set(&dir);
    let store = Store::new(&specs);
    // Not frozen yet: load and verify say so.
    assert!(
        store
            .load("lunar_lander/landing_in_space_train")
            .unwrap_err()
            .to_string()
            .contains("carl-spec freeze")
    );
    let declared = specs.get("lunar_lander").unwrap().instance_sets.len();
    assert!(declared >= 4);
    assert_eq!(store.verify().len(), declared);
    let outcomes = store.freeze(&[], None, false).unwrap();
    assert!(outcomes.iter().all(|o| o.action == "written"));
    assert!(store.verify().is_empty());
    let file = dir.join("instances/lunar_lander/landing_in_space_train.json");
    // No temporary files are left behind.
    let leftovers: Vec<_> = std::fs::read_dir(file.parent().unwrap())
        .unwrap()
        .filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty());

    // A hand edit breaks the content hash.
    let text = std::fs::read_to_string(&file).unwrap();
    let edited = text.replacen("-3.7038216476692747", "-3.70", 1);
    assert_ne!(text, edited);
    std::fs::write(&file, &edited).unwrap();
    let problems = store.verify();
    assert_eq!(problems.len(), 1);
    assert!(problems[0].problem.contains("content hash mismatch"), "{problems:?}");
    assert!(store.load("lunar_lander/landing_in_space_train").is_err());

    // An edit that also recomputes the hash is caught by re-derivation, naming the value.
    let mut set: carl_spec::instances::FrozenSet = serde_json::from_str(&edited).unwrap();
    set = set.with_hash();
    std::fs::write(&file, set.to_text()).unwrap();
    let problems = store.verify();
    assert!(
        problems
            .iter()
            .any(|p| p.problem.contains("instance #0: GRAVITY_Y is -3.7 in the file")),
        "{problems:?}"
    );

    // Freeze refuses to overwrite the differing file without --force, and writes nothing.
    let e = store
        .freeze(&["lunar_lander/landing_in_space_train".into()], None, false)
        .unwrap_err();
    assert!(e.to_string().contains("--force"));
    assert_eq!(std::fs::read_to_string(&file).unwrap(), set.to_text());
    let o = store
        .freeze(&["lunar_lander/landing_in_space_train".into()], None, true)
        .unwrap();
    assert_eq!(o[0].action, "replaced");
    assert!(store.verify().is_empty());

    // Truncated (corrupt) file.
    std::fs::write(&file, &text[..text.len() / 2]).unwrap();
    assert!(
        store
            .load("lunar_lander/landing_in_space_train")
            .unwrap_err()
            .to_string()
            .contains("corrupt")
    );
    let _ = std::fs::remove_dir_all(&dir);
}

fn carl(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_carl-spec"))
        .args(args)
        .current_dir(std::env::temp_dir())
        .output()
        .unwrap()
}

#[test]
fn cli_bad_input_exits_nonzero_with_a_message() {
    for (args, code, needle) in [
        (
            &[
                "sample",
                "lunar_lander",
                "--distribution",
                "landing_in_space",
                "-n",
                "0",
                "--seed",
                "1",
            ][..],
            2,
            "size 0",
        ),
        (
            &[
                "sample",
                "lunar_lander",
                "--distribution",
                "landing_in_space",
                "-n",
                "1000000000000",
                "--seed",
                "1",
            ],
            2,
            "size",
        ),
        (
            &[
                "sample",
                "lunar_lander",
                "--distribution",
                "landing_in_space",
                "-n",
                "5",
                "--seed",
                "abc",
            ],
            2,
            "invalid value",
        ),
        (
            &[
                "sample",
                "lunar_lander",
                "--distribution",
                "landing_in_spac",
                "-n",
                "5",
                "--seed",
                "1",
            ],
            2,
            "did you mean",
        ),
        (&["instances", "show", "lunar_lander/nope"], 2, "no instance set"),
        (&["instances", "show", "no_slash"], 2, "ENV/SET"),
    ] {
        let o = carl(args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(code), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    let o = carl(&["instances", "verify"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stdout));
    let o = carl(&[
        "instances",
        "show",
        "lunar_lander/landing_in_space_train",
        "--format",
        "json",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["instances"].as_array().unwrap().len(), 100);
    assert!(v["provenance"]["rng"].as_str().unwrap().starts_with("pcg64"));
}

/// A copy of the checkout's specs/ (spec files and frozen sets) in a fresh directory.
fn copy_checkout(tag: &str) -> PathBuf {
    let root = tempdir(tag);
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../specs");
    fn copy(from: &Path, to: &Path) {
        std::fs::create_dir_all(to).unwrap();
        for e in std::fs::read_dir(from).unwrap() {
            let e = e.unwrap();
            if e.file_type().unwrap().is_dir() {
                copy(&e.path(), &to.join(e.file_name()));
            } else {
                std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
            }
        }
    }
    copy(&src, &root.join("specs"));
    root
}

fn carl_in(dir: &Path, args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_carl-spec"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

#[test]
fn verify_checks_the_checkouts_files_not_the_binarys_copies() {
    let root = copy_checkout("checkout");
    let o = carl_in(&root, &["instances", "verify"]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{out}");
    assert!(out.contains("(checkout)"), "{out}");
    assert!(
        out.contains("checked specs/instances/lunar_lander/landing_in_space_train.json"),
        "{out}"
    );

    std::fs::write(
        root.join("specs/instances/lunar_lander/landing_in_space_train.json"),
        "garbage",
    )
    .unwrap();
    let o = carl_in(&root, &["instances", "verify"]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{out}");
    assert!(out.contains("landing_in_space_train.json"), "{out}");
    // Outside a checkout the built-in copies are checked, and the output says so.
    let o = carl_in(&std::env::temp_dir(), &["instances", "verify"]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("built into this binary"), "{out}");
    let _ = std::fs::remove_dir_all(&root);
}

/// Author dir with lunar_lander frozen; returns (dir, path of the train set's file).
fn frozen_author_dir(tag: &str) -> (PathBuf, PathBuf) {
    let dir = tempdir(tag);
    std::fs::copy(
        concat!(env!("CARGO_MANIFEST_DIR"), "/../../specs/lunar_lander.json"),
        dir.join("lunar_lander.json"),
    )
    .unwrap();
    let specs = author_set(&dir);
    Store::new(&specs).freeze(&[], None, false).unwrap();
    let file = dir.join("instances/lunar_lander/landing_in_space_train.json");
    (dir, file)
}

#[test]
fn loading_rechecks_every_value_of_a_tampered_file_with_a_recomputed_hash() {
    let (dir, file) = frozen_author_dir("recheck");
    let specs = author_set(&dir);
    let store = Store::new(&specs);
    let good = std::fs::read_to_string(&file).unwrap();
    let tampered: [(&str, serde_json::Value); 3] = [
        ("outside the bounds", serde_json::json!(100.0)),
        ("does not fit a float feature", serde_json::json!("abc")),
        ("unknown", serde_json::Value::Null),
    ];
    for (what, value) in tampered {
        let mut v: serde_json::Value = serde_json::from_str(&good).unwrap();
        let ctx = &mut v["instances"][3]["context"];
        if value.is_null() {
            ctx["NOT_A_FEATURE"] = serde_json::json!(1.0);
        } else {
            ctx["GRAVITY_Y"] = value;
        }
        let mut set: carl_spec::instances::FrozenSet = serde_json::from_value(v).unwrap();
        set = set.with_hash();
        std::fs::write(&file, set.to_text()).unwrap();
        let e = store
            .load("lunar_lander/landing_in_space_train")
            .expect_err(what)
            .to_string();
        assert!(e.contains("corrupt") && e.contains("#3"), "{what}: {e}");
        if what != "unknown" {
            assert!(e.contains(what), "{e}");
        }
    }
    std::fs::write(&file, &good).unwrap();
    assert!(store.load("lunar_lander/landing_in_space_train").is_ok());
    // A set that allows out-of-bounds values still loads them (Jupiter is outside GRAVITY_Y's bounds).
    assert!(store.load("lunar_lander/landing_in_space_test_planets").is_ok());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn freeze_says_what_differs_even_when_only_metadata_does() {
    let (dir, file) = frozen_author_dir("metadiff");
    let specs = author_set(&dir);
    let store = Store::new(&specs);
    let mut set: carl_spec::instances::FrozenSet =
        serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    set.provenance.generator = "carl-spec 0.0.0-old".into();
    std::fs::write(&file, set.with_hash().to_text()).unwrap();
    let e = store
        .freeze(&["lunar_lander/landing_in_space_train".into()], None, false)
        .unwrap_err()
        .to_string();
    assert!(!e.contains("()"), "{e}");
    assert!(e.contains("carl-spec 0.0.0-old"), "{e}");
    // Only the formatting changed: still said.
    let text = std::fs::read_to_string(&file).unwrap();
    store
        .freeze(&["lunar_lander/landing_in_space_train".into()], None, true)
        .unwrap();
    let canonical = std::fs::read_to_string(&file).unwrap();
    std::fs::write(&file, canonical.replace("\n  ", "\n   ")).unwrap();
    let e = store
        .freeze(&["lunar_lander/landing_in_space_train".into()], None, false)
        .unwrap_err()
        .to_string();
    assert!(e.contains("different text"), "{e}");
    assert_ne!(text, canonical);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_multi_set_freeze_failing_on_io_writes_nothing() {
    let dir = tempdir("allornothing");
    for env in ["lunar_lander", "pendulum"] {
        std::fs::copy(
            format!("{}/../../specs/{env}.json", env!("CARGO_MANIFEST_DIR")),
            dir.join(format!("{env}.json")),
        )
        .unwrap();
    }
    let specs = author_set(&dir);
    let store = Store::new(&specs);
    let sets = dir.join("instances/lunar_lander");
    std::fs::create_dir_all(&sets).unwrap();
    // Pendulum's sets (written after lunar_lander's) cannot be written: a file sits where their
    // directory goes.
    let blocker = dir.join("instances/pendulum");
    std::fs::write(&blocker, "").unwrap();
    let e = store.freeze(&[], None, false).unwrap_err().to_string();
    assert!(e.contains("nothing written") && e.contains("pendulum"), "{e}");
    let left: Vec<String> = std::fs::read_dir(&sets)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(left.is_empty(), "written although the freeze failed: {left:?}");
    std::fs::remove_file(&blocker).unwrap();

    // A temporary file of a killed run (its process is gone) is removed by the next freeze.
    let stale = sets.join(".landing_in_space_train.json.4000000000.tmp");
    std::fs::write(&stale, "half a file").unwrap();
    let outcomes = store.freeze(&[], None, false).unwrap();
    assert!(outcomes.len() > 4, "{}", outcomes.len());
    assert!(!stale.exists());
    assert!(store.verify().is_empty());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn sample_refuses_more_values_than_the_documented_limit() {
    let dir = tempdir("limit");
    let spec = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../specs/lunar_lander.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&spec).unwrap();
    v["id"] = "lander_two".into();
    v["aliases"] = serde_json::json!([]);
    v["instance_sets"] = serde_json::json!({});
    v["distributions"]["two"] = serde_json::json!({
        "description": "Two features.",
        "at_bounds": "clip",
        "features": {
            "GRAVITY_Y": { "kind": "uniform", "low": -12, "high": -1 },
            "GRAVITY_X": { "kind": "uniform", "low": -1, "high": 1 }
        }
    });
    std::fs::write(dir.join("lander_two.json"), serde_json::to_string_pretty(&v).unwrap()).unwrap();
    let d = dir.to_string_lossy().into_owned();
    let args = [
        "--specs",
        &d,
        "sample",
        "lander_two",
        "--distribution",
        "two",
        "--seed",
        "1",
        "-n",
    ];
    let o = carl_in(&std::env::temp_dir(), &[&args[..], &["500001"]].concat());
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("1000002 values") && err.contains("1000000"), "{err}");
    let o = carl_in(&std::env::temp_dir(), &[&args[..], &["3"]].concat());
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let _ = std::fs::remove_dir_all(&dir);
}
