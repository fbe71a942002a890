//! Mitsuba's `mesh_attribute` texture in scene files: the attributes a material reads
//! are checked against every object it is given to when the scene is read (an
//! unknown name, a colour where a number is read, a shape without attributes: errors
//! naming the file, line and field).

use irradia_scene::{load_file, Scene, SceneError};
use std::path::PathBuf;

const HEAD: &str = r#"[camera]
eye = [0, 0, 5]
look_at = [0, 0, 0]

[image]
width = 32
height = 32

[render]
integrator = "path"
"#;

/// A square of two triangles (one quad face) with `color_0..2` per vertex and
/// `color_0..2`, `weight_0` per face: `vertex_color`, `face_color`, `face_weight`.
const PLY: &str = "ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
property float color_0
property float color_1
property float color_2
element face 1
property list uchar int vertex_indices
property float color_0
property float color_1
property float color_2
property float weight_0
end_header
-1 -1 0 1 0 0
1 -1 0 0 1 0
1 1 0 0 0 1
-1 1 0 1 1 1
4 0 1 2 3 0.2 0.4 0.6 0.75
";

/// Writes the PLY and `text` in a fresh folder and loads the scene.
fn load(text: &str) -> (Result<Scene, SceneError>, PathBuf, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("square.ply"), PLY).unwrap();
    let path = dir.path().join("s.toml");
    std::fs::write(&path, text).unwrap();
    (load_file(&path), path, dir)
}

fn scene(materials: &str, object: &str) -> String {
    format!("{HEAD}\n{materials}\n[[objects]]\n{object}\n")
}

const MESH: &str = "type = \"mesh\"\npath = \"square.ply\"\nmaterial = \"m\"";

fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.contains(needle)).unwrap() + 1
}

fn fails(text: &str, field: &str, line_needle: &str, needles: &[&str]) {
    let (r, path, _dir) = load(text);
    let e = r.expect_err("the scene must be rejected");
    let shown = e.to_string();
    assert!(e.is_bad_input(), "{shown}");
    assert_eq!(e.file.as_deref(), Some(path.as_path()), "{shown}");
    assert_eq!(e.field, field, "{shown}");
    assert_eq!(e.line, Some(line_of(text, line_needle)), "{shown}");
    for n in needles {
        assert!(shown.contains(n), "{shown:?} should contain {n:?}");
    }
}

#[test]
fn attributes_of_the_mesh_load() {
    for (materials, flat) in [
        (
            "[materials.m]\ntype = \"blendbsdf\"\nweight = { type = \"mesh_attribute\", name = \"face_weight\" }\nbsdfs = [{ type = \"diffuse\" }, { type = \"diffuse\", reflectance = { type = \"mesh_attribute\", name = \"face_color\", scale = 0.5 } }]",
            false,
        ),
        (
            "[materials.m]\ntype = \"diffuse\"\nreflectance = { type = \"mesh_attribute\", name = \"vertex_color\" }",
            true,
        ),
        // A one-channel attribute where a colour is read: a grey.
        (
            "[materials.m]\ntype = \"diffuse\"\nreflectance = { type = \"mesh_attribute\", name = \"face_weight\" }",
            false,
        ),
    ] {
        let object = format!("{MESH}\nface_normals = {flat}");
        let (r, _, _dir) = load(&scene(materials, &object));
        let s = r.unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(s.objects.len(), 1);
    }
}

#[test]
fn an_unknown_attribute_is_an_error_at_the_objects_material() {
    let text = scene(
        "[materials.m]\ntype = \"diffuse\"\nreflectance = { type = \"mesh_attribute\", name = \"face_colour\" }",
        MESH,
    );
    fails(
        &text,
        "objects[0].material",
        "material = \"m\"",
        &[
            "face_colour",
            "diffuse.reflectance",
            "vertex_color (3), face_color (3), face_weight (1)",
        ],
    );
}

#[test]
fn a_colour_attribute_read_as_a_number_is_an_error() {
    let text = scene(
        "[materials.m]\ntype = \"blendbsdf\"\nweight = { type = \"mesh_attribute\", name = \"face_color\" }\nbsdfs = [{ type = \"diffuse\" }, { type = \"diffuse\" }]",
        MESH,
    );
    fails(
        &text,
        "objects[0].material",
        "material = \"m\"",
        &["blendbsdf.weight", "3 channels"],
    );
}

#[test]
fn a_shape_without_attributes_is_an_error() {
    let text = scene(
        "[materials.m]\ntype = \"diffuse\"\nreflectance = { type = \"mesh_attribute\", name = \"vertex_color\" }",
        "type = \"sphere\"\nradius = 1\nmaterial = \"m\"",
    );
    fails(
        &text,
        "objects[0].material",
        "material = \"m\"",
        &["a sphere has no mesh attributes"],
    );
}

#[test]
fn a_name_without_vertex_or_face_is_an_error() {
    let text = scene(
        "[materials.m]\ntype = \"diffuse\"\nreflectance = { type = \"mesh_attribute\", name = \"color\" }",
        MESH,
    );
    fails(
        &text,
        "materials.m.reflectance.name",
        "name = \"color\"",
        &["`vertex_` or `face_`"],
    );
}
