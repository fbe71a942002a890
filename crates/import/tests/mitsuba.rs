//! The Mitsuba 3 importer: every construct of the format on a small scene of our
//! own, every scene of Mitsuba's render test suite (when `shared/mitsuba-data` is
//! there), the round trip through `irradia convert`, and bad input (file, line,
//! column; warnings and `--strict`).

mod common;

use irradia_import::{import, mitsuba, Imported, Options};
use irradia_scene::file::tree::{Node, Value};
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/mitsuba")
        .join(name)
}

/// Mitsuba's test data: `$IRRADIA_MITSUBA_DATA`, or `shared/mitsuba-data` beside the
/// repository.
pub fn mitsuba_data() -> Option<PathBuf> {
    if let Some(d) = std::env::var_os("IRRADIA_MITSUBA_DATA") {
        return Some(PathBuf::from(d));
    }
    let d = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/mitsuba-data");
    d.is_dir().then_some(d)
}

use common::round_trip_with as assert_round_trip;

fn num(n: &Node) -> f64 {
    match n.value {
        Value::Float(x) => x,
        Value::Int(i) => i as f64,
        _ => panic!("not a number: {n:?}"),
    }
}

fn vec3(n: &Node) -> [f64; 3] {
    match &n.value {
        Value::Array(a) => [num(&a[0]), num(&a[1]), num(&a[2])],
        _ => panic!("not a vector: {n:?}"),
    }
}

fn close(a: [f64; 3], b: [f64; 3]) {
    for k in 0..3 {
        assert!((a[k] - b[k]).abs() < 1e-9, "{a:?} vs {b:?}");
    }
}

fn parse(xml: &str) -> Result<Imported, irradia_scene::SceneError> {
    mitsuba::parse_str(xml, Path::new("mem.xml"), &Options::default())
}

const CAMERA: &str = r#"<sensor type="perspective"><float name="fov" value="45"/>
<transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform></sensor>"#;

#[test]
fn our_scene_imports_renders_and_round_trips() {
    let imported = assert_round_trip(&data("box.xml"), &Options::default());
    assert!(imported.warnings.is_empty(), "{:?}", imported.warnings);
    let scene = imported.scene().unwrap();
    // Two instances of a group of two shapes, the floor, the lamp, a cube, a disk.
    assert_eq!(scene.objects.len(), 6);
    let Value::Array(groups) = &imported.tree.get("shape_groups").unwrap().value else {
        panic!("no shape_groups")
    };
    assert_eq!(groups.len(), 1);
    assert!(matches!(&groups[0].get("objects").unwrap().value, Value::Array(m) if m.len() == 2));
    let t = &imported.tree;
    // The included camera, its $res from the included <default>, $spp from the main file.
    let cam = t.get("camera").unwrap();
    close(vec3(cam.get("eye").unwrap()), [0.0, 1.0, 6.0]);
    assert_eq!(num(t.get("image").unwrap().get("width").unwrap()), 32.0);
    assert_eq!(num(t.get("render").unwrap().get("spp").unwrap()), 4.0);
    // -D wins over <default>.
    let opts = Options {
        defines: vec![
            ("spp".into(), "9".into()),
            ("integrator".into(), "volpath".into()),
        ],
        strict: true,
    };
    let again = import(&data("box.xml"), &opts).unwrap();
    let render = again.tree.get("render").unwrap();
    assert_eq!(num(render.get("spp").unwrap()), 9.0);
    assert!(matches!(&render.get("integrator").unwrap().value, Value::Str(s) if s == "path"));
    // The area emitter's material is the referenced one plus emission.
    let mats = t.get("materials").unwrap();
    let lamp = mats.get("white_emitter").expect("emissive copy of `white`");
    assert!(lamp.get("emission").is_some());
    assert!(mats.get("white").unwrap().get("emission").is_none());
}

#[test]
fn every_scene_of_mitsubas_test_suite_imports_and_round_trips() {
    let Some(root) = mitsuba_data() else {
        eprintln!("SKIP: shared/mitsuba-data not found (set IRRADIA_MITSUBA_DATA)");
        return;
    };
    let mut n = 0;
    for dir in std::fs::read_dir(root.join("tests/scenes")).unwrap() {
        let dir = dir.unwrap().path();
        for f in std::fs::read_dir(&dir).unwrap() {
            let f = f.unwrap().path();
            if f.extension().is_some_and(|e| e == "xml") {
                let imported = assert_round_trip(&f, &Options::default());
                for w in &imported.warnings {
                    eprintln!("{}: warning: {w}", f.display());
                }
                n += 1;
            }
        }
    }
    assert!(n >= 20, "only {n} scenes found");
}

#[test]
fn the_samplers_seed_reaches_the_scene() {
    let with = |sampler: &str| {
        let xml = format!(
            r#"<scene version="3.0.0"><sensor type="perspective">{sampler}</sensor></scene>"#
        );
        parse(&xml)
    };
    let seeded = with(r#"<sampler type="independent"><integer name="seed" value="7"/></sampler>"#);
    assert_eq!(seeded.unwrap().scene().unwrap().settings.seed, 7);
    let unseeded = with(r#"<sampler type="independent"/>"#);
    assert_eq!(unseeded.unwrap().scene().unwrap().settings.seed, 0);
    let err = with(r#"<sampler type="independent"><integer name="seed" value="-3"/></sampler>"#)
        .unwrap_err()
        .to_string();
    assert!(err.contains("seed must be between 0"), "{err}");
}

#[test]
fn an_emitter_without_a_bsdf_reflects_nothing() {
    // Mitsuba 3 gives a shape without a BSDF a diffuse one of reflectance 0.5, but 0
    // when the shape emits (Shape's constructor); a lamp that reflected its
    // neighbours' light made Veach's MIS scene 1% too bright.
    let xml = r#"<scene version="3.0.0">
        <shape type="sphere"><emitter type="area"><rgb name="radiance" value="2"/></emitter></shape>
        <shape type="sphere"><point name="center" x="3" y="0" z="0"/></shape>
    </scene>"#;
    let imported = parse(xml).unwrap();
    let objects = imported.tree.get("objects").unwrap();
    let Value::Array(objects) = &objects.value else {
        panic!("no objects")
    };
    let material = |k: usize| match &objects[k].get("material").unwrap().value {
        Value::Str(s) => imported
            .tree
            .get("materials")
            .unwrap()
            .get(s)
            .unwrap()
            .clone(),
        v => panic!("material is {v:?}"),
    };
    let lamp = material(0);
    assert!(lamp.get("emission").is_some());
    assert_eq!(
        num(lamp.get("reflectance").expect("black reflectance")),
        0.0
    );
    let plain = material(1);
    assert!(plain.get("emission").is_none());
    assert!(plain.get("reflectance").is_none(), "diffuse's default 0.5");
    let scene = imported.scene().unwrap();
    assert_eq!(scene.objects.len(), 2);
}

#[test]
fn lookat_and_focal_length_give_mitsubas_camera() {
    let xml = r#"<scene version="3.0.0"><sensor type="perspective">
        <transform name="to_world"><lookat origin="1,2,3" target="1,2,0" up="0,1,0"/></transform>
        </sensor></scene>"#;
    let t = parse(xml).unwrap().tree;
    let cam = t.get("camera").unwrap();
    close(vec3(cam.get("eye").unwrap()), [1.0, 2.0, 3.0]);
    close(vec3(cam.get("look_at").unwrap()), [1.0, 2.0, 2.0]);
    // up is re-orthogonalised (here it is already perpendicular).
    close(vec3(cam.get("up").unwrap()), [0.0, 1.0, 0.0]);
    // 50 mm on 35 mm film: the diagonal field of view, 46.79 degrees.
    let fov = num(cam.get("fov").unwrap());
    assert!((fov - 46.7930).abs() < 1e-3, "{fov}");
    assert!(matches!(&cam.get("fov_axis").unwrap().value, Value::Str(s) if s == "diagonal"));
    // Mitsuba's defaults: 768 x 576, Gaussian filter, near clip 0.01.
    let img = t.get("image").unwrap();
    assert_eq!(num(img.get("width").unwrap()), 768.0);
    assert_eq!(num(cam.get("near_clip").unwrap()), 0.01);
}

#[test]
fn transforms_apply_in_the_order_written() {
    let xml = format!(
        r#"<scene version="3.0.0">{CAMERA}<emitter type="point"><transform name="to_world">
        <translate x="1"/><scale value="2"/><rotate z="1" angle="90"/></transform></emitter></scene>"#
    );
    let t = parse(&xml).unwrap().tree;
    let light = &t.get("lights").map(|l| match &l.value {
        Value::Array(a) => a[0].clone(),
        _ => panic!(),
    });
    // (0,0,0) -> (1,0,0) -> (2,0,0) -> rotated 90 degrees about z -> (0,2,0).
    let p = vec3(light.as_ref().unwrap().get("position").unwrap());
    close(p, [0.0, 2.0, 0.0].map(|x: f64| x + 0.0));
}

#[test]
fn emitter_spectra_are_unbounded_and_unweighted() {
    // A flat emitter spectrum of 1 has luminance 1 (no D65 weighting, no clamp at 1).
    let rgb = mitsuba::bsdfs::emitter_spectrum_rgb(&[360.0, 830.0], &[1.0, 1.0]);
    let y = 0.212671 * rgb[0] + 0.715160 * rgb[1] + 0.072169 * rgb[2];
    assert!((y - 1.0).abs() < 2e-3, "{rgb:?} Y = {y}");
    let rgb = mitsuba::bsdfs::emitter_spectrum_rgb(&[360.0, 830.0], &[10.0, 10.0]);
    assert!(rgb.iter().any(|&c| c > 5.0), "{rgb:?}");
}

/// (file text, the line and column the error must name, a word of its message)
const BAD: &[(&str, (usize, usize), &str)] = &[
    ("<scene version=\"3.0.0\">\n  <bsdf type=\"difuse\" id=\"a\"/>\n</scene>", (2, 15), "unknown BSDF `difuse`"),
    ("<scene version=\"3.0.0\">\n  <shape type=\"sphere\">\n    <float name=\"radus\" value=\"1\"/>\n  </shape>\n</scene>", (3, 5), "unknown parameter `radus`"),
    ("<scene version=\"3.0.0\">\n  <shapes type=\"sphere\"/>\n</scene>", (2, 3), "unknown directive <shapes>"),
    ("<scene version=\"3.0.0\">\n  <shape type=\"sphere\">\n    <float name=\"radius\" value=\"$r\"/>\n  </shape>\n</scene>", (3, 33), "undefined scene parameter `$r`"),
    ("<scene version=\"3.0.0\">\n  <shape type=\"sphere\">\n  </shap>\n</scene>", (3, 3), "XML syntax error"),
    ("<scene version=\"3.0.0\">\n  <shape type=\"sphere\">\n    <float name=\"radius\" value=\"one\"/>\n  </shape>\n</scene>", (3, 33), "not a finite number"),
    ("<scene version=\"3.0.0\">\n  <shape type=\"sphere\">\n    <ref id=\"nothing\"/>\n  </shape>\n</scene>", (3, 14), "unknown id `nothing`"),
    ("<scene version=\"3.0.0\">\n  <emitter type=\"laser\"/>\n</scene>", (2, 18), "unknown emitter `laser`"),
    ("<scene version=\"3.0.0\">\n  <shape type=\"obj\"><transform name=\"to_world\"><skew/></transform></shape>\n</scene>", (2, 48), "unknown directive <skew>"),
    ("<scene version=\"3.0.0\">\n  <shape type=\"sphere\"><boolean name=\"flip_normals\" value=\"maybe\"/></shape>\n</scene>", (2, 60), "not a boolean"),
    ("<scene version=\"3.0.0\">\n  <sensor type=\"perspective\"><float name=\"fov\" value=\"30\"/><string name=\"focal_length\" value=\"20mm\"/></sensor>\n</scene>", (2, 30), "either fov or focal_length"),
    ("<scene>\n  <bsdf type=\"blendbsdf\"><bsdf type=\"diffuse\"/></bsdf>\n  <shape type=\"sphere\"><bsdf type=\"blendbsdf\"><bsdf type=\"diffuse\"/></bsdf></shape>\n</scene>", (2, 3), "takes 2 nested BSDFs"),
];

#[test]
fn bad_input_names_file_line_and_column() {
    for (text, (line, col), words) in BAD {
        let e = parse(text)
            .map(|_| ())
            .expect_err(&format!("accepted: {text}"));
        assert!(e.is_bad_input(), "{e}");
        assert_eq!(e.file.as_deref(), Some(Path::new("mem.xml")), "{e}");
        assert_eq!((e.line, e.column), (Some(*line), Some(*col)), "{e}\n{text}");
        assert!(e.to_string().contains(words), "{e}");
    }
}

#[test]
fn an_unrendered_feature_warns_and_strict_refuses_it() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("hair.xml");
    let xml = format!(
        "<scene version=\"3.0.0\">{CAMERA}\n<shape type=\"sphere\">\n  <bsdf type=\"hair\"><float name=\"eumelanin\" value=\"1.3\"/></bsdf>\n</shape>\n<shape type=\"bsplinecurve\"/>\n</scene>"
    );
    std::fs::write(&path, &xml).unwrap();
    let imported = import(&path, &Options::default()).unwrap();
    assert_eq!(imported.warnings.len(), 2, "{:?}", imported.warnings);
    let w = imported.warnings[0].to_string();
    assert!(w.contains("hair") && w.contains(":4:3:"), "{w}");
    imported.scene().unwrap();
    let strict = Options {
        strict: true,
        ..Options::default()
    };
    let e = import(&path, &strict).unwrap_err();
    assert!(
        e.is_bad_input() && e.to_string().contains("--strict"),
        "{e}"
    );
}

#[test]
fn errors_in_an_included_file_name_that_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("main.xml"),
        "<scene version=\"3.0.0\">\n  <include filename=\"part.xml\"/>\n</scene>",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("part.xml"),
        "<scene version=\"3.0.0\">\n\n  <shape type=\"spere\"/>\n</scene>",
    )
    .unwrap();
    let e = import(&dir.path().join("main.xml"), &Options::default()).unwrap_err();
    assert!(e.file.as_ref().unwrap().ends_with("part.xml"), "{e}");
    assert_eq!((e.line, e.column), (Some(3), Some(16)), "{e}");
    // An include of itself stops at the depth limit instead of recursing forever.
    std::fs::write(
        dir.path().join("loop.xml"),
        "<scene version=\"3.0.0\"><include filename=\"loop.xml\"/></scene>",
    )
    .unwrap();
    let e = import(&dir.path().join("loop.xml"), &Options::default()).unwrap_err();
    assert!(e.to_string().contains("nest"), "{e}");
}

#[test]
fn obj_texture_coordinates_are_flipped_as_mitsuba_does() {
    let Some(root) = mitsuba_data() else {
        eprintln!("SKIP: shared/mitsuba-data not found");
        return;
    };
    let xml = format!(
        "<scene version=\"3.0.0\">{CAMERA}<shape type=\"obj\"><string name=\"filename\" value=\"{}\"/></shape>\
         <shape type=\"ply\"><string name=\"filename\" value=\"{}\"/></shape></scene>",
        root.join("tests/obj/rectangle_uv.obj").display(),
        root.join("tests/ply/rectangle_uv.ply").display()
    );
    let t = parse(&xml).unwrap().tree;
    let Value::Array(objs) = &t.get("objects").unwrap().value else {
        panic!()
    };
    assert!(objs[0].get("flip_tex_coords").is_some());
    assert!(objs[1].get("flip_tex_coords").is_none());
}

/// Every prefix of a scene, and the scene with each byte replaced by a few
/// troublesome ones, parses or fails cleanly: never a panic (a quick stand-in for the
/// fuzz target `fuzz/fuzz_targets/mitsuba.rs`, whose corpus is `fuzz/corpus/mitsuba`).
#[test]
fn truncated_and_mutated_scenes_never_panic() {
    let text = std::fs::read_to_string(data("box.xml")).unwrap();
    let opts = Options::default();
    let origin = data("box.xml");
    for cut in (0..text.len()).filter(|&i| text.is_char_boundary(i)) {
        if let Ok(i) = mitsuba::parse_str(&text[..cut], &origin, &opts) {
            let _ = i.scene();
        }
    }
    let bytes = text.as_bytes();
    for i in (0..bytes.len()).step_by(5) {
        for b in [b'"', b'<', b'0', b'$', b'-'] {
            let mut m = bytes.to_vec();
            m[i] = b;
            if let Ok(s) = std::str::from_utf8(&m) {
                if let Ok(i) = mitsuba::parse_str(s, &origin, &opts) {
                    let _ = i.scene();
                }
            }
        }
    }
}

/// Mitsuba's `mesh_attribute` texture is written as the scene format's, with its
/// `name` and `scale` and no warning; a name that starts with neither `vertex_` nor
/// `face_` is refused, as Mitsuba refuses it.
#[test]
fn mesh_attribute_textures_are_imported() {
    let xml = Path::new(env!("CARGO_MANIFEST_DIR")).join(
        "../../tests/mitsuba-data/tests/scenes/mesh_attributes/test_mesh_attributes_1_face_direct.xml",
    );
    let imported = import(&xml, &Options::default()).unwrap();
    assert!(imported.warnings.is_empty(), "{:?}", imported.warnings);
    let weight = imported
        .tree
        .get("materials")
        .and_then(|m| m.get("bsdf"))
        .and_then(|b| b.get("weight"))
        .expect("the blend's weight");
    let s = |n: &Node, k: &str| match &n.get(k).unwrap().value {
        Value::Str(s) => s.clone(),
        v => panic!("{k}: {v:?}"),
    };
    assert_eq!(s(weight, "type"), "mesh_attribute");
    assert_eq!(s(weight, "name"), "face_weight");
    imported.scene().unwrap();

    let bad = "<scene version=\"3.0.0\">\n  <shape type=\"sphere\">\n    <bsdf type=\"diffuse\">\n      <texture type=\"mesh_attribute\" name=\"reflectance\">\n        <string name=\"name\" value=\"color\"/>\n      </texture>\n    </bsdf>\n  </shape>\n</scene>";
    let e = parse(bad)
        .map(|_| ())
        .expect_err("a name without vertex_ or face_");
    assert!(
        e.is_bad_input() && e.to_string().contains("`vertex_` or `face_`"),
        "{e}"
    );
    assert_eq!(e.line, Some(5), "{e}");
}

#[test]
fn an_emitters_sampling_weight_is_accepted_with_a_note() {
    let xml = format!(
        "<scene version=\"3.0.0\">{CAMERA}\n<emitter type=\"point\"><float name=\"sampling_weight\" value=\"3\"/></emitter>\n\
         <shape type=\"sphere\"><emitter type=\"area\"><float name=\"sampling_weight\" value=\"1\"/></emitter></shape>\n</scene>"
    );
    let imp = parse(&xml).unwrap();
    assert!(imp.warnings.is_empty(), "{:?}", imp.warnings);
    let notes: Vec<_> = imp
        .notes
        .iter()
        .filter(|n| n.contains("sampling_weight"))
        .collect();
    assert_eq!(
        notes.len(),
        1,
        "only the weight other than 1: {:?}",
        imp.notes
    );
    imp.scene().unwrap();
    let bad = format!(
        "<scene version=\"3.0.0\">{CAMERA}\n<emitter type=\"point\"><float name=\"sampling_weight\" value=\"-1\"/></emitter>\n</scene>"
    );
    let e = parse(&bad).unwrap_err();
    assert!(
        e.is_bad_input() && e.to_string().contains("sampling_weight"),
        "{e}"
    );
}
