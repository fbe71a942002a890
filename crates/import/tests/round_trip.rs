//! `irradia convert`'s promise for Irradia's own files: the TOML written from an
//! imported tree reads back as the same tree, and as a scene that renders the same.
//! Every importer's test file repeats this check on its own format's files.

use irradia_import::{import, toml_out, Options};
use std::path::Path;

mod common;

/// The round trip of `path` with the default options.
fn assert_round_trip(path: &Path) {
    common::round_trip_with(path, &Options::default());
}

#[test]
fn every_builtin_scene_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    for (name, _) in irradia_scene::builtin::names() {
        let text = irradia_scene::builtin::source(name).unwrap();
        let path = dir.path().join(format!("{name}.toml"));
        std::fs::write(&path, text).unwrap();
        if text.contains("gallery_sky.hdr") {
            // The built-in's environment map is embedded; a file needs it beside it.
            std::fs::write(
                dir.path().join("gallery_sky.hdr"),
                irradia_scene::builtin::asset("gallery_sky.hdr").unwrap(),
            )
            .unwrap();
        }
        assert_round_trip(&path);
    }
}

#[test]
fn paths_are_rebased_to_the_output_folder() {
    let mut tree = irradia_scene::file::tree::Node::table(0);
    let mut obj = irradia_scene::file::tree::Node::table(0);
    obj.put("type", "mesh", 0)
        .put("path", "meshes/bunny.ply", 0);
    tree.push("objects", obj);
    let text = toml_out::to_toml(&tree, Path::new("/data/scenes"), Path::new("/data/out"));
    assert!(
        text.contains("path = \"../scenes/meshes/bunny.ply\""),
        "{text}"
    );
    let text = toml_out::to_toml(&tree, Path::new("/data/scenes"), Path::new("/data/scenes"));
    assert!(text.contains("path = \"meshes/bunny.ply\""), "{text}");
}

#[test]
fn unknown_extension_names_every_format() {
    let e = import(Path::new("x.blend"), &Options::default()).unwrap_err();
    assert!(e.is_bad_input());
    assert!(e.to_string().contains(".toml"), "{e}");
}
