//! `carl-spec plot`: the Landing-in-Space figure as SVG and PNG, determinism, and refusals.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const TRAIN: &str = "lunar_lander/landing_in_space_train";
const PLANETS: &str = "lunar_lander/landing_in_space_test_planets";

fn carl(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_carl-spec"))
        .args(args)
        .output()
        .expect("run carl-spec")
}

fn tmpdir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("carl-plot-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn plot(out: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["plot", TRAIN, "--out", out.to_str().unwrap(), "--mark", PLANETS];
    args.extend_from_slice(extra);
    carl(&args)
}

fn ok(o: &Output) {
    assert!(
        o.status.success(),
        "status {:?}\nstdout {}\nstderr {}",
        o.status,
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn landing_in_space_svg() {
    let dir = tmpdir("svg");
    let out = dir.join("fig.svg");
    ok(&plot(&out, &[]));
    let text = std::fs::read_to_string(&out).unwrap();
    let doc = roxmltree::Document::parse(&text).expect("well-formed SVG");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    assert_eq!(root.tag_name().namespace(), Some("http://www.w3.org/2000/svg"));
    let class =
        |c: &str| -> Vec<roxmltree::Node> { doc.descendants().filter(|n| n.attribute("class") == Some(c)).collect() };

    // Title = set name + description.
    let title: Vec<String> = class("title")
        .iter()
        .filter_map(|n| n.text().map(str::to_string))
        .collect();
    assert_eq!(title, vec![TRAIN.to_string()]);
    assert!(
        class("description")
            .iter()
            .any(|n| n.text().unwrap_or("").contains("Landing in Space"))
    );

    // Bars: counts sum to the set's 100 instances, each bar within its bin.
    let bars = class("bar");
    assert!(bars.len() >= 5, "{} bars", bars.len());
    let sum: u64 = bars
        .iter()
        .map(|b| b.attribute("data-count").unwrap().parse::<u64>().unwrap())
        .sum();
    assert_eq!(sum, 100);
    for b in &bars {
        assert_eq!(b.tag_name().name(), "rect");
        let h: f64 = b.attribute("height").unwrap().parse().unwrap();
        assert!(h > 0.0);
    }

    // The six planets as labels, with the paper's split (Mars and Moon in distribution).
    let mut labels: Vec<(String, String)> = class("mark")
        .iter()
        .map(|g| {
            let label = g
                .children()
                .find(|n| n.attribute("class") == Some("mark-label"))
                .and_then(|n| n.text())
                .unwrap()
                .to_string();
            assert_eq!(Some(label.as_str()), g.attribute("data-name"));
            (label, g.attribute("data-split").unwrap().to_string())
        })
        .collect();
    labels.sort();
    let expected = [
        ("Earth", "out_of_distribution"),
        ("Jupiter", "out_of_distribution"),
        ("Mars", "in_distribution"),
        ("Moon", "in_distribution"),
        ("Neptune", "out_of_distribution"),
        ("Pluto", "out_of_distribution"),
    ];
    assert_eq!(
        labels,
        expected
            .iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect::<Vec<_>>()
    );
    assert_eq!(class("mark-label").len(), 6);

    // GRAVITY_Y bounds [-20, -0.01] as two vertical lines.
    let bounds = class("bound");
    let mut sides: Vec<(&str, f64)> = bounds
        .iter()
        .map(|b| {
            assert_eq!(b.tag_name().name(), "line");
            assert_eq!(b.attribute("x1"), b.attribute("x2"));
            (
                b.attribute("data-side").unwrap(),
                b.attribute("data-value").unwrap().parse().unwrap(),
            )
        })
        .collect();
    sides.sort_by(|a, b| a.0.cmp(b.0));
    assert_eq!(sides, vec![("lower", -20.0), ("upper", -0.01)]);

    // Axis label with the unit.
    assert!(
        class("axis-label")
            .iter()
            .any(|n| n.text() == Some("GRAVITY_Y [m/s^2]"))
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn landing_in_space_png_and_determinism() {
    let dir = tmpdir("png");
    let (a, b) = (dir.join("a.png"), dir.join("b.png"));
    ok(&plot(&a, &[]));
    ok(&plot(&b, &[]));
    let bytes = std::fs::read(&a).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    assert_eq!(&bytes[12..16], b"IHDR");
    let w = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
    let h = u32::from_be_bytes(bytes[20..24].try_into().unwrap());
    assert_eq!(w, 1000);
    assert!((300..2000).contains(&h), "height {h}");
    assert_eq!(bytes, std::fs::read(&b).unwrap(), "PNG bytes differ between runs");

    // Decodes, and is not blank: bar colour and mark colours are present.
    let decoder = png::Decoder::new(std::io::Cursor::new(&bytes));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (w, h));
    let px: Vec<&[u8]> = buf[..info.buffer_size()].chunks(3).collect();
    for colour in [[0x4c, 0x78, 0xa8], [0xd7, 0x30, 0x27], [0x1a, 0x8a, 0x4a]] {
        assert!(px.iter().any(|p| *p == colour), "colour {colour:?} missing");
    }

    let (s1, s2) = (dir.join("a.svg"), dir.join("b.svg"));
    ok(&plot(&s1, &[]));
    ok(&plot(&s2, &[]));
    assert_eq!(std::fs::read(&s1).unwrap(), std::fs::read(&s2).unwrap());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn refusals_write_nothing() {
    let dir = tmpdir("refuse");
    // Bad extension.
    let o = plot(&dir.join("fig.jpg"), &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains(".svg or .png")
            || String::from_utf8_lossy(&o.stderr).contains("neither")
    );
    assert_eq!(o.status.code(), plot(&dir.join("fig"), &[]).status.code());
    // Unknown set.
    let o = carl(&[
        "plot",
        "lunar_lander/no_such_set",
        "--out",
        dir.join("x.svg").to_str().unwrap(),
    ]);
    assert_ne!(o.status.code(), Some(0));
    let o = plot(&dir.join("y.svg"), &["--mark", "lunar_lander/nope"]);
    assert_ne!(o.status.code(), Some(0));
    // Missing directory.
    let o = plot(&dir.join("missing/fig.svg"), &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("does not exist"));
    assert!(files_in(&dir).is_empty(), "{:?}", files_in(&dir));

    // An existing file is kept without --force, replaced with it.
    let out = dir.join("fig.svg");
    std::fs::write(&out, "keep me").unwrap();
    let o = plot(&out, &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--force"));
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "keep me");
    ok(&plot(&out, &["--force"]));
    assert!(std::fs::read_to_string(&out).unwrap().starts_with("<?xml"));
    assert_eq!(files_in(&dir), vec!["fig.svg".to_string()], "no temporary files left");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn open_bounds_rugs_and_overlay_checks() {
    let dir = tmpdir("open");
    let out = dir.join("p.svg");
    let o = carl(&[
        "plot",
        "pendulum/q1_max_speed_sigma_0_5",
        "--out",
        out.to_str().unwrap(),
        "--rug",
        "pendulum/q1_max_speed_sigma_0_1",
    ]);
    ok(&o);
    let text = std::fs::read_to_string(&out).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    let open: Vec<_> = doc
        .descendants()
        .filter(|n| n.attribute("class") == Some("bound-open"))
        .collect();
    assert_eq!(open.len(), 2, "max_speed is unbounded on both sides");
    assert!(open.iter().all(|n| n.text().unwrap_or("").contains('∞')));
    let ticks = doc
        .descendants()
        .filter(|n| n.attribute("class") == Some("rug-tick"))
        .count();
    assert_eq!(ticks, 100);
    // Overlaying another environment's set is refused.
    let o = carl(&[
        "plot",
        "pendulum/q1_g_sigma_0_1",
        "--out",
        dir.join("q.svg").to_str().unwrap(),
        "--mark",
        PLANETS,
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(!dir.join("q.svg").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
