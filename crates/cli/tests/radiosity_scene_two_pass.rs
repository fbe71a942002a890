//! `irradia radiosity SCENE --display two-pass` end to end: in docs/examples/two-pass.toml
//! the mirror sphere's material makes it a traced mirror (it reflects the lit box), while
//! `--display gouraud` solves the same file as diffuse surfaces (the sphere, with no
//! diffuse part, is black).

mod common;
use common::{irradia, mirror_sphere_sum, stderr};

use std::path::Path;

#[test]
fn the_example_scene_file_traces_its_mirror_sphere() {
    let dir = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/examples/two-pass.toml");
    let scene = scene.to_str().unwrap();
    let small = [
        "radiosity",
        scene,
        "--elements",
        "150",
        "--hemicube-resolution",
        "16",
        "--width",
        "40",
        "--height",
        "30",
    ];
    let mut args = small.to_vec();
    args.extend([
        "--display",
        "two-pass",
        "--pixel-samples",
        "1",
        "-o",
        "t.png",
    ]);
    let o = irradia(&args, dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
    let traced = irradia_core::io::load(&dir.path().join("t.png")).unwrap();
    let mut args = small.to_vec();
    args.extend(["-o", "g.png"]);
    let o = irradia(&args, dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let gouraud = irradia_core::io::load(&dir.path().join("g.png")).unwrap();
    // The mirror sphere (lower left of the image; the file's camera is the built-in
    // Cornell view).
    let region = mirror_sphere_sum;
    assert!(region(&gouraud) < 0.02, "{}", region(&gouraud));
    assert!(region(&traced) > 1.0, "{}", region(&traced));
}
