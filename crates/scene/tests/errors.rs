//! Every kind of bad input gets one error naming the file, the line and the field.

use irradia_scene::{load_file, SceneError};
use std::path::PathBuf;

const HEAD: &str = r#"[camera]
eye = [0, 0, 5]
look_at = [0, 0, 0]

[image]
width = 64
height = 48
"#;

/// Writes `text` to `name` in a fresh folder and loads it; the load must fail.
fn fails(name: &str, text: &str) -> (SceneError, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    let err = load_file(&path).expect_err("the scene must be rejected");
    // Keep the folder alive for callers that look at it? Not needed: path is informative.
    (err, path)
}

/// The error names `file` and `line` and `field`, and its message contains `needle`.
fn check(err: &SceneError, path: &std::path::Path, line: usize, field: &str, needle: &str) {
    let shown = err.to_string();
    assert!(err.is_bad_input(), "{shown}");
    assert_eq!(err.file.as_deref(), Some(path), "{shown}");
    assert_eq!(err.line, Some(line), "{shown}");
    assert_eq!(err.field, field, "{shown}");
    assert!(
        shown.contains(needle),
        "{shown:?} should contain {needle:?}"
    );
    assert!(
        shown.starts_with(&format!("{}:{line}:", path.display())),
        "{shown}"
    );
    if !field.is_empty() {
        assert!(shown.contains(&format!(": {field}: ")), "{shown}");
    }
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .expect("needle in text")
        + 1
}

#[test]
fn toml_syntax_error() {
    let text = format!("{HEAD}\n[[objects]]\ntype = \"sphere\"\nradius = = 1\n");
    let (e, p) = fails("s.toml", &text);
    check(&e, &p, line_of(&text, "= ="), "", "TOML syntax error");
}

#[test]
fn json_syntax_error() {
    let text = "{\n  \"camera\": {\"eye\": [0, 0, 5], \"look_at\": [0, 0, 0]},\n  \"objects\": [\n    {\"type\": \"sphere\" \"radius\": 1}\n  ]\n}\n";
    let (e, p) = fails("s.json", text);
    check(&e, &p, 4, "", "JSON syntax error");
}

#[test]
fn unknown_field_suggests_the_closest_name() {
    let text = format!("{HEAD}\n[[objects]]\ntype = \"sphere\"\nradus = 1\n");
    let (e, p) = fails("s.toml", &text);
    check(
        &e,
        &p,
        line_of(&text, "radus"),
        "objects[0].radus",
        "did you mean `radius`?",
    );
    assert_eq!(e.column, Some(1));
}

#[test]
fn unknown_top_level_table() {
    let text = format!("{HEAD}\n[renderr]\nspp = 4\n");
    let (e, p) = fails("s.toml", &text);
    check(
        &e,
        &p,
        line_of(&text, "renderr"),
        "renderr",
        "did you mean `render`?",
    );
}

#[test]
fn wrong_type() {
    let text = format!("{HEAD}\n[[objects]]\ntype = \"sphere\"\nradius = \"big\"\n");
    let (e, p) = fails("s.toml", &text);
    check(
        &e,
        &p,
        line_of(&text, "\"big\""),
        "objects[0].radius",
        "expected a number, found a string",
    );
}

#[test]
fn wrong_type_in_json_names_line_and_field() {
    let text =
        "{\n  \"camera\": {\n    \"eye\": [0, 0, 5],\n    \"look_at\": [0, 0, \"x\"]\n  }\n}\n";
    let (e, p) = fails("s.json", text);
    check(&e, &p, 4, "camera.look_at[2]", "expected a number");
}

#[test]
fn nan_and_infinity_are_rejected() {
    for bad in ["nan", "inf", "-inf"] {
        let text =
            format!("{HEAD}\n[[objects]]\ntype = \"sphere\"\ncenter = [0, {bad}, 0]\nradius = 1\n");
        let (e, p) = fails("s.toml", &text);
        check(
            &e,
            &p,
            line_of(&text, "center"),
            "objects[0].center[1]",
            "finite",
        );
    }
    let text = "{\"camera\": {\"eye\": [0, 0, 1e999], \"look_at\": [0, 0, 0]}}";
    // Valid JSON syntax, but beyond f64: named as a non-finite field, not a syntax error.
    let (e, p) = fails("s.json", text);
    check(
        &e,
        &p,
        1,
        "camera.eye[2]",
        "must be a finite number (got inf)",
    );
    assert_eq!(e.column, Some(27), "{e}");
    // ... and a syntax error after it is still reported.
    let (e, p) = fails(
        "s.json",
        "{\"camera\": {\"eye\": [0, 0, 1e999], \"look_at\": [0, 0, ]}}",
    );
    check(&e, &p, 1, "", "expected a value");
}

#[test]
fn non_positive_radius_toml_and_json() {
    let text = format!("{HEAD}\n[[objects]]\ntype = \"sphere\"\nradius = 2\n\n[[objects]]\ntype = \"sphere\"\nradius = -1\n");
    let (e, p) = fails("s.toml", &text);
    check(
        &e,
        &p,
        line_of(&text, "radius = -1"),
        "objects[1].radius",
        "must be positive (got -1)",
    );
    assert_eq!(e.column, Some(10));

    let json = "{\n \"camera\": {\"eye\": [0, 0, 5], \"look_at\": [0, 0, 0]},\n \"objects\": [\n  {\"type\": \"sphere\", \"radius\": 1},\n  {\"type\": \"sphere\",\n   \"radius\": 0}\n ]\n}\n";
    let (e, p) = fails("s.json", json);
    check(&e, &p, 6, "objects[1].radius", "must be positive (got 0)");
    assert_eq!(e.column, Some(14));
}

#[test]
fn missing_radius_names_the_object() {
    let text = format!("{HEAD}\n[[objects]]\ntype = \"sphere\"\n");
    let (e, p) = fails("s.toml", &text);
    check(
        &e,
        &p,
        line_of(&text, "[[objects]]"),
        "objects[0].radius",
        "missing required field",
    );
}

#[test]
fn unknown_material_lists_the_defined_ones() {
    let text = format!("{HEAD}\n[materials.glass]\nior = 1.5\n\n[[objects]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"glas\"\n");
    let (e, p) = fails("s.toml", &text);
    check(
        &e,
        &p,
        line_of(&text, "\"glas\""),
        "objects[0].material",
        "did you mean `glass`?",
    );
}

#[test]
fn unknown_object_type() {
    let text = format!("{HEAD}\n[[objects]]\ntype = \"spehre\"\nradius = 1\n");
    let (e, p) = fails("s.toml", &text);
    check(
        &e,
        &p,
        line_of(&text, "spehre"),
        "objects[0].type",
        "did you mean `sphere`?",
    );
}

#[test]
fn image_too_large_is_refused_before_allocation() {
    let text = "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n\n[image]\nwidth = 4000000000\nheight = 4000000000\n";
    let (e, p) = fails("s.toml", text);
    check(&e, &p, 6, "image.width", "more than can be allocated");
    let text = "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n\n[image]\nwidth = 0\n";
    let (e, p) = fails("s.toml", text);
    check(&e, &p, 6, "image.width", "at least 1");
}

#[test]
fn degenerate_camera() {
    let text = "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nup = [0, 0, 1]\n";
    let (e, p) = fails("s.toml", text);
    check(&e, &p, 4, "camera.up", "parallel");
    let text = "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 180\n";
    let (e, p) = fails("s.toml", text);
    check(&e, &p, 4, "camera.fov", "between 0 and 180");
}

#[test]
fn singular_transform() {
    let text = format!("{HEAD}\n[[objects]]\ntype = \"sphere\"\nradius = 1\ntransform = [{{ scale = [1, 0, 1] }}]\n");
    let (e, p) = fails("s.toml", &text);
    check(
        &e,
        &p,
        line_of(&text, "scale"),
        "objects[0].transform[0].scale",
        "must not be zero",
    );
}

#[test]
fn missing_scene_file_is_bad_input_with_the_path() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("nope.toml");
    let e = load_file(&path).unwrap_err();
    assert!(e.is_bad_input());
    assert!(e.to_string().contains("nope.toml"), "{e}");
}

#[test]
fn unknown_builtin_lists_the_valid_names() {
    let e = irradia_scene::builtin::load("nosuch").unwrap_err();
    assert!(e.is_bad_input());
    assert!(e.to_string().contains("default"), "{e}");
}

#[test]
fn missing_mesh_file_names_the_scene_line_and_the_mesh() {
    let text = format!("{HEAD}\n[[objects]]\ntype = \"mesh\"\npath = \"nowhere/bunny.obj\"\n");
    let (e, p) = fails("s.toml", &text);
    check(
        &e,
        &p,
        line_of(&text, "bunny"),
        "objects[0].path",
        "bunny.obj",
    );
    assert!(e.to_string().contains("cannot load the mesh"), "{e}");
}

#[test]
fn ply_header_claiming_more_data_than_the_file_holds() {
    let data =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/meshes/truncated.ply");
    let text = format!(
        "{HEAD}\n[[objects]]\ntype = \"mesh\"\npath = {:?}\n",
        data.display().to_string()
    );
    let (e, p) = fails("s.toml", &text);
    check(
        &e,
        &p,
        line_of(&text, "truncated.ply"),
        "objects[0].path",
        "truncated.ply",
    );
}

#[test]
fn malformed_obj_is_reported_with_the_mesh_line() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("bad.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 x 0\nf 1 2 3\n",
    )
    .unwrap();
    let path = dir.path().join("s.toml");
    let text = format!("{HEAD}\n[[objects]]\ntype = \"mesh\"\npath = \"bad.obj\"\n");
    std::fs::write(&path, &text).unwrap();
    let e = load_file(&path).unwrap_err();
    check(
        &e,
        &path,
        line_of(&text, "bad.obj"),
        "objects[0].path",
        "bad.obj:3",
    );
}

#[test]
fn degenerate_polygon() {
    let text = format!(
        "{HEAD}\n[[objects]]\ntype = \"polygon\"\nvertices = [[0, 0, 0], [1, 1, 1], [2, 2, 2]]\n"
    );
    let (e, p) = fails("s.toml", &text);
    check(
        &e,
        &p,
        line_of(&text, "vertices"),
        "objects[0].vertices",
        "zero area",
    );
}

#[test]
fn open_surface_in_csg_is_refused_at_the_child() {
    let text = format!(
        "{HEAD}\n[[objects]]\ntype = \"union\"\nchildren = [\n  {{ type = \"sphere\", radius = 1 }},\n  {{ type = \"disk\", radius = 1 }},\n]\n"
    );
    let (e, p) = fails("s.toml", &text);
    check(
        &e,
        &p,
        line_of(&text, "disk"),
        "objects[0].children[1].type",
        "closed solid",
    );
}

#[test]
fn bad_radius_deep_inside_csg() {
    let text = format!(
        "{HEAD}\n[[objects]]\ntype = \"difference\"\nchildren = [\n  {{ type = \"box\", min = [-1, -1, -1], max = [1, 1, 1] }},\n  {{ type = \"union\", children = [\n    {{ type = \"sphere\", radius = 1 }},\n    {{ type = \"sphere\", radius = -2 }},\n  ] }},\n]\n"
    );
    let (e, p) = fails("s.toml", &text);
    check(
        &e,
        &p,
        line_of(&text, "radius = -2"),
        "objects[0].children[1].children[1].radius",
        "must be positive (got -2)",
    );
}

#[test]
fn expression_error_points_at_its_character() {
    let text = format!(
        "{HEAD}\n[[objects]]\ntype = \"implicit\"\nexpr = \"x^2 + y^2 + $ - 1\"\nbounds = {{ min = [-1, -1, -1], max = [1, 1, 1] }}\n"
    );
    let (e, p) = fails("s.toml", &text);
    check(
        &e,
        &p,
        line_of(&text, "expr"),
        "objects[0].expr",
        "unexpected character '$' (at character 13 of the expression)",
    );
    // The opening quote is column 8 and `$` is the 13th character of the expression.
    assert_eq!(e.column, Some(8 + 13), "{e}");
    assert!(e.to_string().contains("'$'"), "{e}");
}

#[test]
fn implicit_needs_a_proper_box() {
    let text = format!(
        "{HEAD}\n[[objects]]\ntype = \"implicit\"\nexpr = \"x^2 + y^2 + z^2 - 1\"\nbounds = {{ min = [-1, -1, -1], max = [1, -2, 1] }}\n"
    );
    let (e, p) = fails("s.toml", &text);
    check(
        &e,
        &p,
        line_of(&text, "bounds"),
        "objects[0].bounds.max",
        "must exceed min",
    );
}

#[test]
fn json_errors_deep_in_csg_name_their_line() {
    let text = r#"{
  "camera": {"eye": [0, 0, 5], "look_at": [0, 0, 0]},
  "objects": [
    {"type": "difference", "children": [
      {"type": "box", "min": [-1, -1, -1], "max": [1, 1, 1]},
      {"type": "sphere",
       "radius": -0.5}
    ]}
  ]
}"#;
    let (e, p) = fails("s.json", text);
    check(
        &e,
        &p,
        7,
        "objects[0].children[1].radius",
        "must be positive",
    );
}

#[test]
fn duplicate_json_key() {
    let text =
        "{\n \"camera\": {\"eye\": [0, 0, 5], \"look_at\": [0, 0, 0],\n  \"eye\": [0, 0, 4]}\n}\n";
    let (e, p) = fails("s.json", text);
    check(&e, &p, 3, "camera.eye", "more than once");
}

#[test]
fn missing_image_texture() {
    let text = format!(
        "{HEAD}\n[materials.wood]\ncolor = {{ type = \"image\", path = \"no/wood.png\" }}\n"
    );
    let (e, p) = fails("s.toml", &text);
    check(
        &e,
        &p,
        line_of(&text, "wood.png"),
        "materials.wood.color.path",
        "wood.png",
    );
}

#[test]
fn out_of_range_material_and_light_values() {
    let text = format!("{HEAD}\n[materials.glass]\ntransmission = 1.5\n");
    let (e, p) = fails("s.toml", &text);
    check(
        &e,
        &p,
        line_of(&text, "transmission"),
        "materials.glass.transmission",
        "between 0 and 1",
    );
    let text = format!("{HEAD}\n[materials.m]\ncolor = [1, -0.5, 0]\n");
    let (e, p) = fails("s.toml", &text);
    check(
        &e,
        &p,
        line_of(&text, "color"),
        "materials.m.color",
        "must not be negative",
    );
    let text = format!(
        "{HEAD}\n[[lights]]\ntype = \"spot\"\nposition = [0, 5, 0]\nlook_at = [0, 0, 0]\nouter_angle = 120\n"
    );
    let (e, p) = fails("s.toml", &text);
    check(
        &e,
        &p,
        line_of(&text, "outer_angle"),
        "lights[0].outer_angle",
        "90 degrees",
    );
    let text = format!(
        "{HEAD}\n[[lights]]\ntype = \"rect\"\ncorner = [0, 5, 0]\nedge_u = [1, 0, 0]\nedge_v = [2, 0, 0]\n"
    );
    let (e, p) = fails("s.toml", &text);
    check(
        &e,
        &p,
        line_of(&text, "edge_v"),
        "lights[0].edge_v",
        "non-zero area",
    );
}

#[test]
fn wrong_extension_is_refused() {
    let (e, _) = fails("s.yaml", "camera: {}\n");
    assert!(e.is_bad_input());
    assert!(e.to_string().contains(".toml or .json"), "{e}");
}
