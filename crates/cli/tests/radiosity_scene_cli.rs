//! `irradia radiosity SCENE.toml` end to end: the documented example scene solves (and
//! passes `--closed`); bad scene input exits 2 naming the file, line and field.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn example() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/examples/radiosity-room.toml")
}

fn radiosity(scene: &Path, extra: &[&str], out: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_irradia"))
        .arg("radiosity")
        .arg(scene)
        .args(["--elements", "300", "--width", "64", "--height", "48"])
        .args(extra)
        .arg("-o")
        .arg(out)
        .output()
        .expect("irradia runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn the_example_room_solves_and_is_closed() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("room.png");
    let o = radiosity(&example(), &["--closed"], &png);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(png.exists());
    let o = radiosity(
        &example(),
        &["--solver", "hierarchical", "--quiet"],
        &dir.path().join("room-h.png"),
    );
    assert!(o.status.success(), "{}", stderr(&o));
}

/// The example with one text replacement, written to `dir`; returns its path and the
/// 1-based line of the replacement.
fn edited(dir: &Path, from: &str, to: &str) -> (PathBuf, usize) {
    let text = std::fs::read_to_string(example()).unwrap();
    let line = text.lines().position(|l| l.contains(from)).expect(from) + 1;
    let p = dir.join("edited.toml");
    std::fs::write(&p, text.replacen(from, to, 1)).unwrap();
    (p, line)
}

#[test]
fn bad_radiosity_input_exits_2_naming_file_line_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("x.png");
    // Reflectance at or above 1.
    let (p, line) = edited(
        dir.path(),
        "color = [0.75, 0.75, 0.72]",
        "color = [1.0, 0.75, 0.72]",
    );
    let o = radiosity(&p, &[], &png);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains(&format!("edited.toml:{line}:")),
        "line {line}: {e}"
    );
    assert!(e.contains("materials.white.color"), "{e}");
    // No emitter.
    let (p, _) = edited(
        dir.path(),
        "emission = [6.0, 5.6, 4.8]",
        "emission = [0, 0, 0]",
    );
    let o = radiosity(&p, &[], &png);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("edited.toml") && e.contains("emission"), "{e}");
    // An open room where --closed assumes a closed one: the back wall moved away.
    let (p, _) = edited(
        dir.path(),
        "vertices = [[0, 0, 3], [0, 2.5, 3], [3, 2.5, 3], [3, 0, 3]]",
        "vertices = [[0, 0, 3.2], [0, 2.5, 3.2], [3, 2.5, 3.2], [3, 0, 3.2]]",
    );
    let o = radiosity(&p, &["--closed"], &png);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("edited.toml:") && e.contains("objects["), "{e}");
    assert!(e.contains("open"), "{e}");
    assert!(!png.exists(), "no image after an input error");
}
