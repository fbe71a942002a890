//! The pbrt-v4 importer: directives, transforms, materials, textures, scoping,
//! includes, errors with line:col, warnings, the TOML round trip and renders.

use irradia_import::{import, toml_out, Options};
use irradia_scene::file::tree::{parse_toml, Node, Value};
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/pbrt").join(name)
}

/// Imports `path`, writes it as TOML beside it, and checks both trees are equal.
fn assert_round_trip(path: &Path) -> irradia_import::Imported {
    let imported = import(path, &Options::default()).unwrap_or_else(|e| panic!("{e}"));
    imported.scene().unwrap_or_else(|e| panic!("{e}"));
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

#[test]
fn cornell_box_imports_and_round_trips() {
    let imp = assert_round_trip(&data("cornell.pbrt"));
    let text = toml_out::to_toml(&imp.tree, Path::new("."), Path::new("."));
    println!("{text}");
    for w in &imp.warnings {
        println!("warning: {w}");
    }
}
