//! `carl-spec render` end to end: PNG, GIF and frame directories of a configured instance, the
//! context reaching the picture, and the refusals (existing files, unknown formats, envs without
//! a renderer).

use std::path::Path;
use std::process::Command;

use crate::common::TempDir;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_carl-spec"))
}

fn tmpdir(tag: &str) -> TempDir {
    TempDir::new(&format!("render-{tag}"))
}

fn render(args: &[&str]) -> std::process::Output {
    bin().arg("render").args(args).output().unwrap()
}

fn decode_png(path: &Path) -> (u32, u32, Vec<u8>) {
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut r = dec.read_info().unwrap();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    let info = r.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

#[test]
fn png_of_the_reset_state_and_no_silent_overwrite() {
    let d = tmpdir("png");
    let out = d.join("lander.png");
    let o = out.to_str().unwrap();
    let r = render(&["lunar_lander", "--seed", "4", "--out", o]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let (w, h, px) = decode_png(&out);
    assert_eq!((w, h), (600, 400));
    // Sky (black) above, ground (white) at the bottom, purple lander somewhere.
    assert_eq!(&px[..3], &[0, 0, 0]);
    let bottom = ((h - 1) * w * 3) as usize;
    assert_eq!(&px[bottom..bottom + 3], &[255, 255, 255]);
    assert!(px.chunks(3).any(|p| p == [128, 102, 230]));

    let before = std::fs::read(&out).unwrap();
    let r = render(&["lunar_lander", "--seed", "5", "--out", o]);
    assert_eq!(r.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&r.stderr).contains("--force"));
    assert_eq!(std::fs::read(&out).unwrap(), before, "existing file untouched");
    let r = render(&["lunar_lander", "--seed", "5", "--out", o, "--force"]);
    assert!(r.status.success());
    assert_ne!(std::fs::read(&out).unwrap(), before);
}

#[test]
fn the_context_changes_the_picture() {
    let d = tmpdir("ctx");
    let a = d.join("a.png");
    let b = d.join("b.png");
    assert!(render(&["lunar_lander", "--out", a.to_str().unwrap()]).status.success());
    let r = render(&[
        "lunar_lander",
        "--context",
        "VIEWPORT_W=800",
        "--context",
        "LEG_H=12",
        "--out",
        b.to_str().unwrap(),
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert_eq!(decode_png(&a).0, 600);
    assert_eq!(decode_png(&b).0, 800);
}

#[test]
fn gif_of_a_heuristic_landing_and_frame_directory() {
    let d = tmpdir("gif");
    let gif = d.join("landing.gif");
    let r = render(&[
        "lunar_lander",
        "--instance-set",
        "lunar_lander/landing_in_space_test_planets",
        "--instance",
        "3",
        "--policy",
        "heuristic",
        "--steps",
        "60",
        "--every",
        "6",
        "--out",
        gif.to_str().unwrap(),
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut dec = opts.read_info(std::fs::File::open(&gif).unwrap()).unwrap();
    let mut n = 0;
    while dec.read_next_frame().unwrap().is_some() {
        n += 1;
    }
    assert_eq!(n, 11, "reset frame + every 6th of 60 steps");

    let frames = d.join("frames/");
    let r = render(&[
        "lunar_lander",
        "--steps",
        "4",
        "--every",
        "2",
        "--out",
        frames.to_str().unwrap(),
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let mut names: Vec<String> = std::fs::read_dir(&frames)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["frame_00000.png", "frame_00001.png", "frame_00002.png"]);
    // Again without --force: refused, nothing rewritten.
    let r = render(&[
        "lunar_lander",
        "--steps",
        "4",
        "--every",
        "2",
        "--out",
        frames.to_str().unwrap(),
    ]);
    assert_eq!(r.status.code(), Some(2));
}

#[test]
fn clear_errors_for_bad_requests() {
    let d = tmpdir("err");
    let cases: [(&[&str], &str); 5] = [
        (&["cartpole", "--out", "x.png"], "no renderer"),
        (&["rna_design", "--out", "x.png"], "render works for: lunar_lander"),
        (&["lunar_lander", "--out", "x.jpg"], ".png"),
        (
            &["lunar_lander", "--context", "GRAVITY_Y=5", "--out", "x.png"],
            "bounds",
        ),
        (
            &["ant", "--policy", "heuristic", "--out", "x.png"],
            "no built-in controller",
        ),
    ];
    for (args, needle) in cases {
        let r = bin().current_dir(&d).arg("render").args(args).output().unwrap();
        assert_eq!(r.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!err.contains("panicked"));
        // Only environments that can be drawn are offered.
        if let Some((_, list)) = err.split_once("render works for:") {
            let ids: Vec<&str> = list.trim().split(", ").collect();
            assert!(ids.contains(&"lunar_lander") && ids.contains(&"fetch"), "{err}");
            assert!(
                !ids.iter().any(|i| ["cartpole", "pendulum", "rna_design"].contains(i)),
                "{err}"
            );
        }
    }
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 0, "nothing written");
}

fn names_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Regression: a second run into a frame directory left the first run's later frames beside
/// the new ones. Now an earlier run's frames need --force, which leaves exactly this run's.
#[test]
fn a_frame_directory_holds_exactly_one_run() {
    let d = tmpdir("stale");
    let frames = d.join("frames");
    let f = frames.to_str().unwrap();
    let long = [
        "lunar_lander",
        "--policy",
        "noop",
        "--steps",
        "10",
        "--every",
        "2",
        "--out",
        f,
    ];
    // A path without extension that does not exist yet must end in / to name a directory.
    assert_eq!(render(&long).status.code(), Some(2));
    let slash = format!("{f}/");
    let mut long_slash = long;
    long_slash[8] = &slash;
    let r = render(&long_slash);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert_eq!(names_in(&frames).len(), 6);
    std::fs::write(frames.join("notes.txt"), "mine").unwrap();
    let before = std::fs::read(frames.join("frame_00005.png")).unwrap();

    let short = [
        "lunar_lander",
        "--policy",
        "noop",
        "--steps",
        "4",
        "--every",
        "2",
        "--out",
        f,
    ];
    let r = render(&short);
    assert_eq!(r.status.code(), Some(2));
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(err.contains("earlier run") && err.contains("--force"), "{err}");
    assert_eq!(names_in(&frames).len(), 7, "nothing written or removed");
    assert_eq!(std::fs::read(frames.join("frame_00005.png")).unwrap(), before);

    let r = bin().arg("render").args(short).arg("--force").output().unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert_eq!(
        names_in(&frames),
        ["frame_00000.png", "frame_00001.png", "frame_00002.png", "notes.txt"],
        "the old frames 3..5 are gone, other files kept"
    );
    assert!(String::from_utf8_lossy(&r.stderr).contains("frame_00005.png"));
    assert_eq!(std::fs::read_to_string(frames.join("notes.txt")).unwrap(), "mine");
}

/// Regression: `--out x.png` where x.png is a directory silently wrote frames into it.
#[test]
fn a_png_or_gif_path_that_is_a_directory_is_refused() {
    let d = tmpdir("isdir");
    for name in ["x.png", "y.GIF"] {
        let p = d.join(name);
        std::fs::create_dir(&p).unwrap();
        let r = render(&["lunar_lander", "--steps", "2", "--out", p.to_str().unwrap()]);
        assert_eq!(r.status.code(), Some(2), "{name}");
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(err.contains("is a directory"), "{err}");
        assert!(names_in(&p).is_empty(), "nothing written into {name}");
    }
}

/// One rule for output paths: a missing parent directory is refused, nothing is created.
#[test]
fn missing_parent_directories_are_refused() {
    let d = tmpdir("noparent");
    for out in ["missing/dir/a.png", "missing/dir/a.gif", "missing/dir/frames/"] {
        let p = format!("{}/{out}", d.display());
        let r = render(&["lunar_lander", "--out", &p]);
        assert_eq!(r.status.code(), Some(2), "{out}");
        assert!(String::from_utf8_lossy(&r.stderr).contains("does not exist"), "{out}");
    }
    assert!(names_in(&d).is_empty());
}
