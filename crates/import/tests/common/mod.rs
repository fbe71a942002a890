//! Checks every model importer's tests share: the TOML round trip and the framing of
//! a bare model.
#![allow(dead_code)]

use irradia_import::{import, toml_out, Imported, Options};
use irradia_scene::file::tree::{parse_toml, Node, Value};
use std::path::{Path, PathBuf};

pub fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(rel)
}

pub fn imported(path: &Path) -> Imported {
    import(path, &Options::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// `irradia convert`'s promise: import `path` with `opts`, write it as TOML beside it,
/// and the TOML parses back to the same tree, which loads as a scene too. Returns the
/// import.
pub fn round_trip_with(path: &Path, opts: &Options) -> Imported {
    let imported = import(path, opts).unwrap_or_else(|e| panic!("{e}"));
    imported
        .scene()
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let dir = path.parent().unwrap();
    let text = toml_out::to_toml(&imported.tree, dir, dir);
    let back = parse_toml(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    assert_eq!(
        back.canonical(),
        imported.tree.canonical(),
        "{}: the converted TOML reads back differently:\n{text}",
        path.display()
    );
    irradia_scene::load_tree(&back, &text, &dir.join("converted.toml"))
        .unwrap_or_else(|e| panic!("{}: converted scene: {e}\n{text}", path.display()));
    imported
}

/// [`round_trip_with`] for a model file (default options), whose mesh data stays in
/// the model file: the TOML is small.
pub fn assert_round_trip(path: &Path) {
    let dir = path.parent().unwrap();
    let imported = round_trip_with(path, &Options::default());
    let text = toml_out::to_toml(&imported.tree, dir, dir);
    assert!(
        text.len() < 8000,
        "{}: {} bytes of TOML",
        path.display(),
        text.len()
    );
}

pub fn vec3(n: &Node) -> [f32; 3] {
    match &n.value {
        Value::Array(a) => {
            let f = |i: usize| match a[i].value {
                Value::Float(x) => x as f32,
                Value::Int(x) => x as f32,
                _ => panic!("not a number"),
            };
            [f(0), f(1), f(2)]
        }
        _ => panic!("not an array"),
    }
}

/// Every corner of the box `lo`..`hi` projects inside a `w` x `h` image of the tree's
/// (perspective, `fov_axis = "smaller"`) camera.
pub fn assert_frames(tree: &Node, lo: [f32; 3], hi: [f32; 3], w: f32, h: f32) {
    use glam::Vec3;
    let cam = tree.get("camera").expect("a camera");
    let eye = Vec3::from(vec3(cam.get("eye").unwrap()));
    let at = Vec3::from(vec3(cam.get("look_at").unwrap()));
    let fov = match cam.get("fov").unwrap().value {
        Value::Float(f) => f as f32,
        _ => panic!(),
    };
    let fwd = (at - eye).normalize();
    let right = fwd.cross(Vec3::Y).normalize();
    let up = right.cross(fwd);
    // fov spans the shorter side.
    let t = (fov.to_radians() / 2.0).tan();
    let (tx, ty) = if w >= h {
        (t * w / h, t)
    } else {
        (t, t * h / w)
    };
    for k in 0..8 {
        let p = Vec3::new(
            if k & 1 == 0 { lo[0] } else { hi[0] },
            if k & 2 == 0 { lo[1] } else { hi[1] },
            if k & 4 == 0 { lo[2] } else { hi[2] },
        );
        let d = p - eye;
        let z = d.dot(fwd);
        assert!(z > 0.0, "corner {p} behind the camera");
        let (x, y) = (d.dot(right) / z, d.dot(up) / z);
        assert!(
            x.abs() <= tx && y.abs() <= ty,
            "corner {p} outside the image: ({x}, {y}) vs ({tx}, {ty})"
        );
    }
    // And not lost in the middle: the box spans a fair part of the view.
    let c = 0.5 * (Vec3::from(lo) + Vec3::from(hi));
    let r = 0.5 * (Vec3::from(hi) - Vec3::from(lo)).length();
    assert!(r / (c - eye).length() > 0.5 * (fov.to_radians() / 2.0).sin());
}
