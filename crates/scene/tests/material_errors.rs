//! Bad physically based materials and textures: each gets one error naming the file,
//! the line and the field (the reader machinery of `errors.rs`).

use irradia_scene::{load_file, SceneError};
use std::path::{Path, PathBuf};

const HEAD: &str = r#"[camera]
eye = [0, 0, 5]
look_at = [0, 0, 0]
"#;

/// Writes `text` (after [`HEAD`]) as `s.toml` in a fresh folder holding `files`
/// (name, bytes), loads it, and returns the error, the path and the full text.
fn fails_with(text: &str, files: &[(&str, &[u8])]) -> (SceneError, PathBuf, String) {
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes) in files {
        std::fs::write(dir.path().join(name), bytes).unwrap();
    }
    let path = dir.path().join("s.toml");
    let full = format!("{HEAD}\n{text}");
    std::fs::write(&path, &full).unwrap();
    let err = load_file(&path).expect_err("the scene must be rejected");
    (err, path, full)
}

/// The error names `path`, the line holding `at`, `field`, and contains `needle`.
fn check(text: &str, files: &[(&str, &[u8])], at: &str, field: &str, needle: &str) {
    let (err, path, full) = fails_with(text, files);
    let line = full
        .lines()
        .position(|l| l.contains(at))
        .expect("`at` is in the text")
        + 1;
    let shown = err.to_string();
    assert!(err.is_bad_input(), "{shown}");
    assert_eq!(err.file.as_deref(), Some(path.as_path()), "{shown}");
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
}

#[test]
fn unknown_material_type_lists_the_valid_ones() {
    check(
        "[materials.m]\ntype = \"roughconductr\"\n",
        &[],
        "roughconductr",
        "materials.m.type",
        "unknown material type `roughconductr`; did you mean `roughconductor`?",
    );
    check(
        "[materials.m]\ntype = \"blend\"\n",
        &[],
        "\"blend\"",
        "materials.m.type",
        "Mitsuba calls it `blendbsdf`",
    );
}

#[test]
fn unknown_parameter_suggests_mitsubas_name() {
    check(
        "[materials.m]\ntype = \"roughconductor\"\nalpah = 0.1\n",
        &[],
        "alpah",
        "materials.m.alpah",
        "did you mean `alpha`?",
    );
    // A lecture field on a physically based material is not a parameter either.
    check(
        "[materials.m]\ntype = \"diffuse\"\ncolor = 0.5\n",
        &[],
        "color",
        "materials.m.color",
        "unknown field `color`",
    );
    // ... nor inside a nested material.
    check(
        "[materials.m]\ntype = \"blendbsdf\"\nbsdfs = [{ type = \"diffuse\" },\n  { type = \"diffuse\", reflectanse = 1 }]\n",
        &[],
        "reflectanse",
        "materials.m.bsdfs[1].reflectanse",
        "did you mean `reflectance`?",
    );
}

#[test]
fn negative_roughness() {
    check(
        "[materials.m]\ntype = \"roughdielectric\"\nalpha = -0.1\n",
        &[],
        "alpha",
        "materials.m.alpha",
        "must not be negative (got -0.1)",
    );
    check(
        "[materials.m]\ntype = \"roughplastic\"\nalpha = -1\n",
        &[],
        "alpha",
        "materials.m.alpha",
        "must not be negative",
    );
}

#[test]
fn alpha_together_with_alpha_u() {
    check(
        "[materials.m]\ntype = \"roughconductor\"\nalpha = 0.1\nalpha_u = 0.2\nalpha_v = 0.3\n",
        &[],
        "alpha_u",
        "materials.m.alpha_u",
        "give either alpha or alpha_u and alpha_v, not both",
    );
    check(
        "[materials.m]\ntype = \"roughconductor\"\nalpha_u = 0.2\n",
        &[],
        "alpha_u",
        "materials.m.alpha_u",
        "needs both alpha_u and alpha_v",
    );
}

#[test]
fn unknown_ior_and_conductor_names() {
    check(
        "[materials.m]\ntype = \"dielectric\"\nint_ior = \"bk8\"\n",
        &[],
        "bk8",
        "materials.m.int_ior",
        "unknown IOR name `bk8`; did you mean `bk7`?",
    );
    check(
        "[materials.m]\ntype = \"conductor\"\nmaterial = \"Gold\"\n",
        &[],
        "Gold",
        "materials.m.material",
        "unknown conductor `Gold`",
    );
    check(
        "[materials.m]\ntype = \"conductor\"\nmaterial = \"Au\"\neta = 0.2\n",
        &[],
        "eta",
        "materials.m.eta",
        "give either material or eta and k",
    );
}

#[test]
fn unreadable_or_corrupt_texture_file() {
    let text = "[materials.m]\ntype = \"diffuse\"\nreflectance = { type = \"bitmap\", filename = \"wood.png\" }\n";
    check(
        text,
        &[],
        "wood.png",
        "materials.m.reflectance.filename",
        "cannot load the bitmap: cannot open",
    );
    check(
        text,
        &[("wood.png", b"\x89PNG\r\n\x1a\n this is not a PNG")],
        "wood.png",
        "materials.m.reflectance.filename",
        "cannot load the bitmap: cannot decode",
    );
    let truncated: &[u8] = &std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/textures/rgb4x2.png"),
    )
    .unwrap()[..60];
    check(
        text,
        &[("wood.png", truncated)],
        "wood.png",
        "materials.m.reflectance.filename",
        "cannot load the bitmap",
    );
}

#[test]
fn bad_texture_fields() {
    check(
        "[materials.m]\ntype = \"diffuse\"\nreflectance = { type = \"bitmap\", filename = \"a.png\", wrap_mode = \"wrap\" }\n",
        &[],
        "wrap_mode",
        "materials.m.reflectance.wrap_mode",
        "unknown value `wrap`",
    );
    check(
        "[materials.m]\ntype = \"diffuse\"\nreflectance = { type = \"checkerboard\", to_uv = [{ scale = 0 }] }\n",
        &[],
        "to_uv",
        "materials.m.reflectance.to_uv[0].scale",
        "must not be zero",
    );
    check(
        "[materials.m]\ntype = \"diffuse\"\nreflectance = \"400:0.5, 380:0.2\"\n",
        &[],
        "400:0.5",
        "materials.m.reflectance",
        "wavelengths must increase",
    );
    check(
        "[materials.m]\ntype = \"mask\"\nopacity = [1, 1, 1]\nbsdf = { type = \"diffuse\" }\n",
        &[],
        "opacity",
        "materials.m.opacity",
        "expected a number or a texture table",
    );
}

#[test]
fn nested_references_must_exist_be_physically_based_and_acyclic() {
    check(
        "[materials.m]\ntype = \"twosided\"\nbsdf = \"gld\"\n\n[materials.gold]\ntype = \"conductor\"\n",
        &[],
        "\"gld\"",
        "materials.m.bsdf",
        "unknown material `gld`; did you mean `gold`?",
    );
    check(
        "[materials.m]\ntype = \"twosided\"\nbsdf = \"red\"\n\n[materials.red]\ncolor = [1, 0, 0]\n",
        &[],
        "\"red\"",
        "materials.m.bsdf",
        "is a lecture material",
    );
    check(
        "[materials.a]\ntype = \"mask\"\nbsdf = \"b\"\n\n[materials.b]\ntype = \"twosided\"\nbsdf = \"a\"\n",
        &[],
        "bsdf = \"a\"",
        "materials.b.bsdf",
        "cycle: a -> b -> a",
    );
}
