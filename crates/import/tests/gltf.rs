//! glTF 2.0, with files written by trimesh and pygltflib (tests/data/gltf/make.py):
//! a textured box (GLB, embedded image), a node hierarchy (data-URI buffers, TRS and
//! matrix nodes, a primitive without indices and with COLOR_0), a camera and punctual
//! lights (external .bin buffer), an orthographic camera; errors; round trips.

mod common;
use common::*;
use irradia_import::{import, Options};
use irradia_scene::file::tree::{Node, Value};

const FILES: &[&str] = &[
    "gltf/textured_box.glb",
    "gltf/hierarchy.gltf",
    "gltf/camera_lights.gltf",
    "gltf/ortho.gltf",
    "gltf/extensions.gltf",
];

fn s(n: &Node, key: &str) -> String {
    match &n.get(key).unwrap_or_else(|| panic!("no {key}")).value {
        Value::Str(s) => s.clone(),
        v => panic!("{key}: {v:?}"),
    }
}

fn f(n: &Node, key: &str) -> f64 {
    match n.get(key).unwrap_or_else(|| panic!("no {key}")).value {
        Value::Float(x) => x,
        Value::Int(x) => x as f64,
        ref v => panic!("{key}: {v:?}"),
    }
}

fn objects(n: &Node) -> Vec<Node> {
    match &n.get("objects").unwrap().value {
        Value::Array(a) => a.clone(),
        _ => panic!(),
    }
}

#[test]
fn every_gltf_test_file_round_trips() {
    for file in FILES {
        assert_round_trip(&data(file));
    }
}

#[test]
fn textured_box_refers_to_the_glb_for_mesh_and_image() {
    let imp = imported(&data("gltf/textured_box.glb"));
    let objs = objects(&imp.tree);
    assert_eq!(objs.len(), 1);
    assert_eq!(s(&objs[0], "path"), "textured_box.glb");
    assert_eq!(f(&objs[0], "mesh"), 0.0);
    assert_eq!(f(&objs[0], "primitive"), 0.0);
    let mat = imp
        .tree
        .get("materials")
        .unwrap()
        .get(&s(&objs[0], "material"))
        .unwrap();
    assert_eq!(s(mat, "type"), "principled");
    let tex = mat.get("base_color").unwrap();
    assert_eq!(s(tex, "filename"), "textured_box.glb");
    assert_eq!(f(tex, "image"), 0.0);
    let scene = imp.scene().unwrap();
    // 24 vertices, 12 triangles, with uv: the texture's red and white texels both show.
    assert_eq!(scene.objects.len(), 1);
    let file = irradia_geometry::io::gltf::GltfFile::open(&data("gltf/textured_box.glb")).unwrap();
    let prim = file.primitive(0, 0).unwrap();
    assert_eq!((prim.positions.len(), prim.indices.len()), (24, 12));
    assert!(prim.uvs.is_some());
    let png = file.embedded_image(0).unwrap().unwrap();
    assert_eq!(&png[1..4], b"PNG");
    assert_frames(&imp.tree, [-0.5; 3], [0.5; 3], 640.0, 480.0);
}

#[test]
fn node_hierarchy_composes_trs_and_matrices() {
    let imp = imported(&data("gltf/hierarchy.gltf"));
    let objs = objects(&imp.tree);
    assert_eq!(objs.len(), 2, "two primitives of one mesh");
    let Value::Array(steps) = &objs[0].get("transform").unwrap().value else {
        panic!()
    };
    let Value::Array(rows) = &steps[0].get("matrix").unwrap().value else {
        panic!()
    };
    let row = |r: usize| -> Vec<f64> {
        match &rows[r].value {
            Value::Array(a) => a
                .iter()
                .map(|x| match x.value {
                    Value::Float(v) => v,
                    Value::Int(v) => v as f64,
                    _ => panic!(),
                })
                .collect(),
            _ => panic!(),
        }
    };
    // parent: rotate y 90°, translate (2, 0, 0); child: scale 0.5, translate (0, 1, 0).
    // x → -z: world = T(2,0,0) R_y(90) T(0,1,0) S(0.5).
    let expect = [
        [0.0, 0.0, 0.5, 2.0],
        [0.0, 0.5, 0.0, 1.0],
        [-0.5, 0.0, 0.0, 0.0],
    ];
    for (r, e) in expect.iter().enumerate() {
        for (a, b) in row(r).iter().zip(e) {
            assert!((a - b).abs() < 1e-6, "row {r}: {:?} vs {e:?}", row(r));
        }
    }
    let mats = imp.tree.get("materials").unwrap();
    let brushed = mats.get("brushed").unwrap();
    assert_eq!(s(brushed, "type"), "twosided", "doubleSided");
    let p = brushed.get("bsdf").unwrap();
    assert!((f(p, "metallic") - 0.7).abs() < 1e-9 && (f(p, "roughness") - 0.3).abs() < 1e-9);
    // The second primitive has COLOR_0 and no indices: vertex colours as base colour.
    let vc = mats.get(&s(&objs[1], "material")).unwrap();
    assert_eq!(s(vc.get("base_color").unwrap(), "type"), "mesh_attribute");
    let file = irradia_geometry::io::gltf::GltfFile::open(&data("gltf/hierarchy.gltf")).unwrap();
    let tri = file.primitive(0, 1).unwrap();
    assert_eq!(tri.indices, vec![[0, 1, 2]]);
    let colors = tri.attributes.get("vertex_color").unwrap();
    assert_eq!(colors.row(2).unwrap(), &[0.0, 0.0, 1.0]);
    imp.scene().unwrap();
}

#[test]
fn camera_and_punctual_lights() {
    let imp = imported(&data("gltf/camera_lights.gltf"));
    assert!(imp.notes.is_empty(), "{:?}", imp.notes);
    let cam = imp.tree.get("camera").unwrap();
    assert_eq!(vec3(cam.get("eye").unwrap()), [0.0, 1.0, 5.0]);
    assert_eq!(vec3(cam.get("look_at").unwrap()), [0.0, 1.0, 4.0]);
    assert!((f(cam, "fov") - 45.0).abs() < 1e-4);
    assert_eq!(s(cam, "fov_axis"), "y");
    let img = imp.tree.get("image").unwrap();
    assert_eq!((f(img, "width"), f(img, "height")), (720.0, 480.0));
    let Value::Array(lights) = &imp.tree.get("lights").unwrap().value else {
        panic!()
    };
    assert_eq!(lights.len(), 3);
    assert_eq!(s(&lights[0], "type"), "point");
    assert_eq!(
        vec3(lights[0].get("intensity").unwrap()),
        [100.0, 90.0, 80.0]
    );
    assert_eq!(vec3(lights[0].get("position").unwrap()), [0.0, 3.0, 0.0]);
    assert_eq!(s(&lights[1], "type"), "spot");
    assert!((f(&lights[1], "outer_angle") - 30.0).abs() < 1e-4);
    assert!((f(&lights[1], "inner_angle") - 10.0).abs() < 1e-4);
    let d = vec3(lights[1].get("direction").unwrap());
    assert!((d[1] + 1.0).abs() < 1e-6, "points down: {d:?}");
    assert_eq!(s(&lights[2], "type"), "directional");
    assert_eq!(f(&lights[2], "irradiance"), 3.0);
    imp.scene().unwrap();
}

#[test]
fn orthographic_camera() {
    let imp = imported(&data("gltf/ortho.gltf"));
    let cam = imp.tree.get("camera").unwrap();
    assert_eq!(s(cam, "type"), "orthographic");
    assert_eq!(f(cam, "height"), 4.0);
    assert_eq!(
        imp.notes.len(),
        1,
        "a light is added, not a camera: {:?}",
        imp.notes
    );
}

#[test]
fn errors_name_the_file_and_the_accessor() {
    let dir = tempfile::tempdir().unwrap();
    // An accessor claiming more elements than its buffer view holds.
    let text = std::fs::read_to_string(data("gltf/ortho.gltf")).unwrap();
    let bad = text.replacen("\"count\": 3", "\"count\": 300", 1);
    assert_ne!(bad, text);
    let p = dir.path().join("bad.gltf");
    std::fs::write(&p, &bad).unwrap();
    let e = import(&p, &Options::default()).unwrap_err().to_string();
    assert!(
        e.contains("bad.gltf") && e.contains("POSITION (accessor 0)"),
        "{e}"
    );
    // Not JSON at all.
    std::fs::write(&p, "{ nope").unwrap();
    let e = import(&p, &Options::default()).unwrap_err();
    assert!(
        e.is_bad_input() && e.to_string().contains("bad.gltf"),
        "{e}"
    );
    // A mesh index past the file's meshes, at the selector of a scene file.
    std::fs::copy(data("gltf/ortho.gltf"), dir.path().join("o.gltf")).unwrap();
    let s = dir.path().join("s.toml");
    std::fs::write(&s, "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n[[objects]]\ntype = \"mesh\"\npath = \"o.gltf\"\nmesh = 4\n").unwrap();
    let e = irradia_scene::load_file(&s).unwrap_err().to_string();
    assert!(
        e.contains(":7:") && e.contains("mesh 4 does not exist"),
        "{e}"
    );
    // Truncated GLB and garbage never panic.
    let glb = std::fs::read(data("gltf/textured_box.glb")).unwrap();
    for cut in (0..glb.len()).step_by(7) {
        let _ = irradia_import::gltf::parse_bytes(&glb[..cut], &dir.path().join("cut.glb"));
    }
}

/// Findings of `cargo fuzz run gltf`, kept as regression tests: what the fuzz target
/// does (import; read every primitive and embedded image) ends in errors, not panics.
#[test]
fn fuzz_findings_do_not_panic() {
    let dir = data("gltf/fuzz");
    for entry in std::fs::read_dir(&dir).unwrap() {
        let p = entry.unwrap().path();
        let bytes = std::fs::read(&p).unwrap();
        let imported = irradia_import::gltf::parse_bytes(&bytes, &p);
        let mut failed = imported.is_err();
        if let Ok(file) = irradia_import::gltf::GltfFile::from_bytes(&bytes, &p) {
            for m in 0..file.document.meshes().len() {
                failed |= file.primitive(m, 0).is_err();
            }
            for i in 0..file.document.images().len() {
                failed |= file.embedded_image(i).is_err();
            }
        }
        assert!(failed, "{}: no error found", p.display());
    }
}

fn nums(n: &Node) -> Vec<f64> {
    match &n.value {
        Value::Array(a) => a.iter().flat_map(nums).collect(),
        Value::Float(x) => vec![*x],
        Value::Int(x) => vec![*x as f64],
        v => panic!("{v:?}"),
    }
}

/// KHR_texture_transform, KHR_materials_emissive_strength, _transmission and _ior
/// (pygltflib's file): factors multiply their textures, the uv transform is the
/// extension's `T · R · S`, and none of them is a warning.
#[test]
fn material_extensions_are_read() {
    let imp = imported(&data("gltf/extensions.gltf"));
    let ext: Vec<String> = imp.warnings.iter().map(|w| w.to_string()).collect();
    assert!(ext.is_empty(), "{ext:?}");
    let objs = objects(&imp.tree);
    let m = imp
        .tree
        .get("materials")
        .unwrap()
        .get(&s(&objs[0], "material"))
        .unwrap();
    assert_eq!(s(m, "type"), "principled");
    assert!((f(m, "spec_trans") - 0.8).abs() < 1e-6 && (f(m, "eta") - 1.33).abs() < 1e-6);
    let base = m.get("base_color").unwrap();
    assert_eq!(nums(base.get("scale").unwrap()), [0.5, 1.0, 1.0]);
    // The extension's GLSL: uv' = T(offset) R(rotation) S(scale) uv, its mat3 given by
    // columns (cos, sin), (-sin, cos).
    let (r, sx, sy, ox, oy) = (0.3f64, 2.0, 3.0, 0.5, 0.25);
    let spec = |u: f64, v: f64| {
        let (a, b) = (sx * u, sy * v);
        (
            r.cos() * a - r.sin() * b + ox,
            r.sin() * a + r.cos() * b + oy,
        )
    };
    let Value::Array(steps) = &base.get("to_uv").unwrap().value else {
        panic!()
    };
    assert_eq!(steps.len(), 1);
    let mtx = nums(steps[0].get("matrix").unwrap());
    for (u, v) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (0.3, 0.7)] {
        let got = (
            mtx[0] * u + mtx[1] * v + mtx[2],
            mtx[3] * u + mtx[4] * v + mtx[5],
        );
        let want = spec(u, v);
        assert!(
            (got.0 - want.0).abs() < 1e-6 && (got.1 - want.1).abs() < 1e-6,
            "{got:?} {want:?}"
        );
    }
    let e = m.get("emission").unwrap();
    assert_eq!(s(e, "type"), "bitmap");
    assert_eq!(nums(e.get("scale").unwrap()), [4.0, 2.0, 1.0]);
    // It loads: the bitmap's scale multiplies the texels.
    let scene = imp.scene().unwrap();
    assert!(!scene.materials.is_empty());
}
