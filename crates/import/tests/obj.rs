//! OBJ with MTL: usemtl groups as objects, the MTL → BSDF rule, textures and bump
//! maps, errors with file:line:col, warnings, --strict, framing, round trips.

mod common;
use common::*;
use irradia_import::{import, Options};
use irradia_scene::file::tree::{Node, Value};

fn s(n: &Node, key: &str) -> String {
    match &n.get(key).unwrap_or_else(|| panic!("no {key}")).value {
        Value::Str(s) => s.clone(),
        v => panic!("{key}: {v:?}"),
    }
}

#[test]
fn every_obj_test_file_round_trips() {
    assert_round_trip(&data("obj/scene.obj"));
    assert_round_trip(&data("obj/bare.obj"));
}

#[test]
fn usemtl_groups_become_objects_with_their_materials() {
    let imp = imported(&data("obj/scene.obj"));
    let Value::Array(objs) = &imp.tree.get("objects").unwrap().value else {
        panic!()
    };
    let groups: Vec<String> = objs.iter().map(|o| s(o, "group")).collect();
    assert_eq!(
        groups,
        ["textured", "red", "shiny", "glass", "leaf", "lamp"]
    );
    for o in objs {
        assert_eq!(s(o, "path"), "scene.obj");
        assert_eq!(s(o, "material"), s(o, "group"));
    }
    // The cube's red half is 3 quads = 6 triangles.
    let scene = imp.scene().unwrap();
    let red =
        irradia_geometry::io::obj::read_obj_group(&data("obj/scene.obj"), Some("red")).unwrap();
    assert_eq!(red.indices.len(), 6);
    assert!(scene.objects.len() >= 6);
    // A group no face uses is an error at the selector.
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(data("obj/scene.obj"), dir.path().join("scene.obj")).unwrap();
    // (without its MTL file: the groups keep their names)
    let p = dir.path().join("s.toml");
    std::fs::write(&p, "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n[[objects]]\ntype = \"mesh\"\npath = \"scene.obj\"\ngroup = \"blue\"\n").unwrap();
    let e = irradia_scene::load_file(&p).unwrap_err().to_string();
    assert!(
        e.contains(":7:") && e.contains("objects[0].group") && e.contains("\"red\""),
        "{e}"
    );
}

#[test]
fn mtl_maps_to_mitsuba_bsdfs_by_the_rule() {
    let imp = imported(&data("obj/scene.obj"));
    let m = imp.tree.get("materials").unwrap();
    assert_eq!(s(m.get("red").unwrap(), "type"), "diffuse");
    let shiny = m.get("shiny").unwrap();
    assert_eq!(s(shiny, "type"), "roughplastic");
    let Value::Float(alpha) = shiny.get("alpha").unwrap().value else {
        panic!()
    };
    assert!((alpha - (2.0f64 / 202.0).sqrt()).abs() < 1e-6, "{alpha}");
    let glass = m.get("glass").unwrap();
    assert_eq!(s(glass, "type"), "dielectric");
    assert_eq!(glass.get("int_ior").unwrap().value, Value::Float(1.5));
    let leaf = m.get("leaf").unwrap();
    assert_eq!(s(leaf, "type"), "mask");
    assert_eq!(leaf.get("opacity").unwrap().value, Value::Float(0.5));
    let tex = m.get("textured").unwrap();
    assert_eq!(s(tex, "type"), "bumpmap");
    assert_eq!(tex.get("scale").unwrap().value, Value::Float(0.02));
    assert_eq!(s(tex.get("texture").unwrap(), "filename"), "height.png");
    let inner = tex.get("bsdf").unwrap();
    assert_eq!(
        s(inner.get("reflectance").unwrap(), "filename"),
        "checker.png"
    );
    let lamp = m.get("lamp").unwrap();
    assert_eq!(lamp.get("emission").unwrap().value, Value::Float(4.0));
    // Emissive materials light the scene: the path tracer, no environment added.
    assert!(imp.tree.get("lights").is_none());
    assert_eq!(s(imp.tree.get("render").unwrap(), "integrator"), "path");
    // `Ka` is known and not rendered: a warning naming the MTL file, line and column.
    let w: Vec<String> = imp.warnings.iter().map(|w| w.to_string()).collect();
    assert!(
        w.iter()
            .any(|w| w.contains("scene.mtl:33:1") && w.contains("Ka")),
        "{w:?}"
    );
    let e = import(
        &data("obj/scene.obj"),
        &Options {
            strict: true,
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("strict"), "{e}");
}

fn obj_error(obj: &str, mtl: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("m.obj"), obj).unwrap();
    std::fs::write(dir.path().join("m.mtl"), mtl).unwrap();
    let e = import(&dir.path().join("m.obj"), &Options::default()).unwrap_err();
    assert!(e.is_bad_input(), "{e}");
    let s = e.to_string();
    s[s.find("m.").unwrap()..].to_string()
}

#[test]
fn text_errors_name_file_line_and_column() {
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    assert!(
        obj_error(&format!("{tri}v 1 x 0\n"), "").starts_with("m.obj:4:5:"),
        "{}",
        obj_error(&format!("{tri}v 1 x 0\n"), "")
    );
    let e = obj_error(&format!("{tri}f 1 2 9\n"), "");
    assert!(
        e.starts_with("m.obj:4:7:") && e.contains("out of range"),
        "{e}"
    );
    let e = obj_error(&format!("{tri}  frob 1\n"), "");
    assert!(
        e.starts_with("m.obj:4:3:") && e.contains("unknown OBJ statement `frob`"),
        "{e}"
    );
    let e = obj_error(
        &format!("mtllib m.mtl\n{tri}usemtl a\nf 1 2 3\n"),
        "newmtl a\nKd 1 0.5\n",
    );
    assert!(
        e.starts_with("m.mtl:2:1:") && e.contains("takes 3 numbers"),
        "{e}"
    );
    let e = obj_error(
        &format!("mtllib m.mtl\n{tri}f 1 2 3\n"),
        "newmtl a\nKd 1 0.5 zz\n",
    );
    assert!(e.starts_with("m.mtl:2:10:") && e.contains("'zz'"), "{e}");
    let e = obj_error(
        &format!("mtllib m.mtl\n{tri}f 1 2 3\n"),
        "newmtl a\n  Kq 1\n",
    );
    assert!(
        e.starts_with("m.mtl:2:3:") && e.contains("unknown MTL directive"),
        "{e}"
    );
    let e = obj_error(
        &format!("mtllib m.mtl\n{tri}f 1 2 3\n"),
        "newmtl a\nillum 2.5\n",
    );
    assert!(e.starts_with("m.mtl:2:7:"), "{e}");
    let e = obj_error("v 0 0 0\n", "");
    assert!(e.contains("no faces"), "{e}");
}

#[test]
fn lines_are_a_warning_and_the_rest_renders() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("l.obj");
    std::fs::write(&p, "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nf 1 2 3\n").unwrap();
    let imp = import(&p, &Options::default()).unwrap();
    assert_eq!(imp.warnings.len(), 1);
    assert!(
        imp.warnings[0].to_string().contains("l.obj:4:1"),
        "{}",
        imp.warnings[0]
    );
    imp.scene().unwrap();
    assert!(import(
        &p,
        &Options {
            strict: true,
            ..Default::default()
        }
    )
    .is_err());
}

#[test]
fn a_bare_obj_is_framed_and_lit() {
    let imp = imported(&data("obj/bare.obj"));
    assert_frames(&imp.tree, [0.0; 3], [1.0; 3], 640.0, 480.0);
    assert_eq!(imp.notes.len(), 2, "{:?}", imp.notes);
    assert!(imp.notes[0].contains("camera") && imp.notes[1].contains("light"));
    assert!(imp.tree.get("materials").is_none());
    let Value::Array(objs) = &imp.tree.get("objects").unwrap().value else {
        panic!()
    };
    assert!(objs[0].get("group").is_none(), "no usemtl: the whole file");
    let imp = imported(&data("obj/scene.obj"));
    assert_frames(&imp.tree, [-3.0, 0.0, -3.0], [3.0, 3.0, 3.0], 640.0, 480.0);
}
