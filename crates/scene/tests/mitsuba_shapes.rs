//! Mitsuba's shapes in scene files: the examples of docs/scene-format.md's "Mitsuba's
//! shapes" load and build what the page says, the example scene loads, and bad fields
//! are refused with file, line and field.

use irradia_scene::{load_file, load_str, SceneSyntax};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The ```toml blocks of the docs' "Mitsuba's shapes" section.
fn examples() -> Vec<String> {
    let doc = std::fs::read_to_string(root().join("docs/scene-format.md")).unwrap();
    let heading = "#### Mitsuba's shapes";
    let start = doc.find(heading).expect("section") + heading.len();
    let rest = &doc[start..];
    let end = ["\n## ", "\n### ", "\n#### ", "\nQuadric clipping"]
        .iter()
        .filter_map(|h| rest.find(h))
        .min()
        .unwrap_or(rest.len());
    rest[..end]
        .split("```toml\n")
        .skip(1)
        .map(|b| b[..b.find("```").unwrap()].to_string())
        .collect()
}

const HEAD: &str = "[camera]\neye = [0, 1, 5]\nlook_at = [0, 0, 0]\n\n";

#[test]
fn the_documented_example_loads_and_builds_mitsubas_shapes() {
    let blocks = examples();
    assert_eq!(blocks.len(), 1);
    let text = format!("{HEAD}{}", blocks[0]);
    let scene = load_str(&text, SceneSyntax::Toml, &root().join("docs/doc.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    let kinds: Vec<&str> = scene
        .accel
        .instances()
        .iter()
        .map(|i| i.shape.kind())
        .collect();
    assert_eq!(kinds, ["rectangle", "rectangle", "cube", "tube", "sdfgrid"]);
    // The sdfgrid example is a closed solid (positive on its boundary).
    assert!(scene.accel.instances()[4].shape.is_solid());
    assert!(!scene.accel.instances()[3].shape.is_solid());
}

#[test]
fn the_example_scene_loads() {
    let scene = load_file(&root().join("docs/examples/mitsuba-shapes.toml")).unwrap();
    assert_eq!(scene.objects.len(), 7);
}

/// Loads `objects` after a camera from a file in a fresh folder; the load must fail
/// at the line holding `line_needle`, in `field`, with `needle` in the message.
fn refused(objects: &str, line_needle: &str, field: &str, needle: &str) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.toml");
    let text = format!("{HEAD}{objects}");
    std::fs::write(&path, &text).unwrap();
    let err = load_file(&path).expect_err("must be refused");
    let shown = err.to_string();
    let line = text
        .lines()
        .position(|l| l.contains(line_needle))
        .expect("needle")
        + 1;
    assert!(err.is_bad_input(), "{shown}");
    assert_eq!(err.line, Some(line), "{shown}");
    assert_eq!(err.field, field, "{shown}");
    assert!(shown.contains(needle), "{shown:?} lacks {needle:?}");
    assert!(
        shown.starts_with(&format!("{}:{line}:", path.display())),
        "{shown}"
    );
}

#[test]
fn bad_fields_are_refused_where_they_are() {
    refused(
        "[[objects]]\ntype = \"tube\"\nradius = -1\n",
        "radius = -1",
        "objects[0].radius",
        "must be positive",
    );
    refused(
        "[[objects]]\ntype = \"tube\"\np0 = [1, 2, 3]\np1 = [1, 2, 3]\n",
        "p1 = ",
        "objects[0].p1",
        "p0 and p1 must differ",
    );
    refused(
        "[[objects]]\ntype = \"rectangle\"\nflip_normals = 1\n",
        "flip_normals",
        "objects[0].flip_normals",
        "expected",
    );
    refused(
        "[[objects]]\ntype = \"cube\"\nradius = 1\n",
        "radius",
        "objects[0].radius",
        "unknown field",
    );
    refused(
        "[[objects]]\ntype = \"sdfgrid\"\ngrid = [[[1, -1], [1, 1]], [[1, 1], [1]]]\n",
        "grid = [",
        "objects[0].grid[1][1]",
        "not box-shaped",
    );
    refused(
        "[[objects]]\ntype = \"sdfgrid\"\ngrid = [[[1, 1], [1, 1]], [[1, 1], [1, 1]]]\n",
        "grid = [",
        "objects[0].grid",
        "no surface",
    );
    refused(
        "[[objects]]\ntype = \"sdfgrid\"\ngrid = [[[1, -1], [1, 1]]]\n",
        "grid = [",
        "objects[0].grid",
        "2 to 256 planes",
    );
    refused(
        "[[objects]]\ntype = \"sdfgrid\"\n",
        "[[objects]]",
        "objects[0]",
        "needs grid",
    );
    refused(
        "[[objects]]\ntype = \"sdfgrid\"\npath = \"missing.nrrd\"\n",
        "path",
        "objects[0].path",
        "cannot read the volume",
    );
    refused(
        "[[objects]]\ntype = \"sdfgrid\"\nnormals = \"smoth\"\ngrid = [[[1, -1], [1, 1]], [[1, 1], [1, 1]]]\n",
        "normals",
        "objects[0].normals",
        "smooth",
    );
}

#[test]
fn a_grid_from_a_raw_volume_is_the_inline_grid() {
    let dir = tempfile::tempdir().unwrap();
    let values: [f32; 8] = [1.0, -1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0];
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(dir.path().join("g.raw"), bytes).unwrap();
    let from_file = format!(
        "{HEAD}[[objects]]\ntype = \"sdfgrid\"\npath = \"g.raw\"\ndims = [2, 2, 2]\nvoxel = \"f32\"\n"
    );
    let inline = format!(
        "{HEAD}[[objects]]\ntype = \"sdfgrid\"\ngrid = [[[1, -1], [1, 1]], [[1, 1], [1, 1]]]\n"
    );
    let a = load_str(&from_file, SceneSyntax::Toml, &dir.path().join("s.toml")).unwrap();
    let b = load_str(&inline, SceneSyntax::Toml, &dir.path().join("s.toml")).unwrap();
    let ray = irradia_core::Ray::new(glam::Vec3::new(0.9, 0.1, 2.0), -glam::Vec3::Z);
    let ha = a.accel.instances()[0]
        .intersect(&ray, f32::INFINITY)
        .unwrap();
    let hb = b.accel.instances()[0]
        .intersect(&ray, f32::INFINITY)
        .unwrap();
    assert_eq!(ha.t, hb.t);
    assert_eq!(ha.normal, hb.normal);
}

/// An `sdfgrid` read from Mitsuba's `.vol` file is the same shape as one given inline.
#[test]
fn an_sdfgrid_from_a_mitsuba_vol_file_equals_the_inline_grid() {
    let n = 6usize;
    let value = |x: usize, y: usize, z: usize| {
        let p = glam::Vec3::new(x as f32, y as f32, z as f32) / (n - 1) as f32;
        (p - glam::Vec3::splat(0.5)).length() - 0.35
    };
    let dir = tempfile::tempdir().unwrap();
    let mut bytes = b"VOL\x03".to_vec();
    for v in [1i32, n as i32, n as i32, n as i32, 1] {
        bytes.extend(v.to_le_bytes());
    }
    for v in [0.0f32, 0.0, 0.0, 1.0, 1.0, 1.0] {
        bytes.extend(v.to_le_bytes());
    }
    let mut planes = Vec::new();
    for z in 0..n {
        let mut rows = Vec::new();
        for y in 0..n {
            let row: Vec<String> = (0..n).map(|x| format!("{}", value(x, y, z))).collect();
            for x in 0..n {
                bytes.extend(value(x, y, z).to_le_bytes());
            }
            rows.push(format!("[{}]", row.join(", ")));
        }
        planes.push(format!("[{}]", rows.join(", ")));
    }
    std::fs::write(dir.path().join("ball.vol"), &bytes).unwrap();
    let scene = |shape: &str| {
        let text = format!("{HEAD}[[objects]]\ntype = \"sdfgrid\"\n{shape}\n");
        load_str(&text, SceneSyntax::Toml, &dir.path().join("s.toml"))
            .unwrap_or_else(|e| panic!("{e}"))
    };
    let from_file = scene("path = \"ball.vol\"");
    let inline = scene(&format!("grid = [{}]", planes.join(", ")));
    let (a, b) = (
        &from_file.accel.instances()[0],
        &inline.accel.instances()[0],
    );
    for i in 0..20 {
        let o = glam::Vec3::new(0.1 + 0.04 * i as f32, 0.5, 3.0);
        let ray = irradia_core::Ray::new(o, -glam::Vec3::Z);
        let (ha, hb) = (
            a.intersect(&ray, f32::INFINITY),
            b.intersect(&ray, f32::INFINITY),
        );
        assert_eq!(ha.map(|h| h.t), hb.map(|h| h.t), "ray {i}");
    }
    assert!(a
        .intersect(
            &irradia_core::Ray::new(glam::Vec3::new(0.5, 0.5, 3.0), -glam::Vec3::Z),
            f32::INFINITY
        )
        .is_some());
}
