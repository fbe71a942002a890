//! `type = "triangles"`: a triangle mesh written in the scene file (the pbrt
//! importer's `trianglemesh`).

use irradia_scene::{load_str, SceneSyntax};
use std::path::Path;

fn load(objects: &str) -> Result<irradia_scene::Scene, String> {
    let text = format!("[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n\n[[objects]]\ntype = \"triangles\"\n{objects}");
    load_str(&text, SceneSyntax::Toml, Path::new("t.toml")).map_err(|e| e.to_string())
}

#[test]
fn a_square_with_normals_and_uv_loads() {
    let s = load(
        "positions = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]\n\
         indices = [[0, 1, 2], [0, 2, 3]]\n\
         normals = [[0, 0, 1], [0, 0, 1], [0, 0, 1], [0, 0, 1]]\n\
         uv = [[0, 0], [1, 0], [1, 1], [0, 1]]\n",
    )
    .unwrap();
    assert_eq!(s.objects.len(), 1);
}

#[test]
fn bad_triangles_name_the_field() {
    let e =
        load("positions = [[0, 0, 0], [1, 0, 0], [1, 1, 0]]\nindices = [[0, 1, 3]]\n").unwrap_err();
    assert!(
        e.contains("t.toml:8:11") && e.contains("objects[0].indices") && e.contains("out of range"),
        "{e}"
    );
    let e =
        load("positions = [[0, 0, 0], [1, 0, 0], [1, 1, 0]]\nindices = [[0, 1]]\n").unwrap_err();
    assert!(e.contains("expected 3 vertex indices"), "{e}");
    let e = load(
        "positions = [[0, 0, 0], [1, 0, 0], [1, 1, 0]]\nindices = [[0, 1, 2]]\nuv = [[0, 0]]\n",
    )
    .unwrap_err();
    assert!(
        e.contains("objects[0].uv") && e.contains("one entry per position"),
        "{e}"
    );
    let e = load("positions = [[0, 0, 0], [1, 0, 0], [1, 1, 0]]\nindices = [[0, 1, -2]]\n")
        .unwrap_err();
    assert!(e.contains("objects[0].indices[0][2]"), "{e}");
    let e = load("positions = [[0, 0, 0]]\n").unwrap_err();
    assert!(e.contains("indices"), "{e}");
}
