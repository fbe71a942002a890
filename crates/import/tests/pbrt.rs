//! The pbrt-v4 importer: directives, transforms, materials, textures, scoping,
//! includes, errors with line:col, warnings, the TOML round trip and renders.

mod common;

use irradia_import::pbrt::{coverage_str, parse_str, Status};
use irradia_import::{import, Imported, Options};
use irradia_scene::file::tree::{Node, Value};
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/pbrt")
        .join(name)
}

/// The round trip of `path` with the default options.
fn assert_round_trip(path: &Path) -> Imported {
    common::round_trip_with(path, &Options::default())
}

/// Writes `text` as `scene.pbrt` in a fresh folder and imports it.
fn import_text(
    text: &str,
) -> (
    tempfile::TempDir,
    Result<Imported, irradia_scene::SceneError>,
) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.pbrt");
    std::fs::write(&path, text).unwrap();
    let r = import(&path, &Options::default());
    (dir, r)
}

fn ok(text: &str) -> Imported {
    let (_d, r) = import_text(text);
    r.unwrap_or_else(|e| panic!("{e}"))
}

fn err(text: &str) -> String {
    let (_d, r) = import_text(text);
    match r {
        Ok(_) => panic!("expected an error"),
        Err(e) => {
            assert!(e.is_bad_input());
            e.to_string()
        }
    }
}

fn objects(i: &Imported) -> Vec<Node> {
    match i.tree.get("objects").map(|o| &o.value) {
        Some(Value::Array(a)) => a.clone(),
        _ => Vec::new(),
    }
}

fn num(n: &Node) -> f64 {
    match n.value {
        Value::Float(x) => x,
        Value::Int(x) => x as f64,
        _ => panic!("not a number: {n:?}"),
    }
}

fn nums(n: &Node) -> Vec<f64> {
    match &n.value {
        Value::Array(a) => a
            .iter()
            .flat_map(|x| match &x.value {
                Value::Array(_) => nums(x),
                _ => vec![num(x)],
            })
            .collect(),
        _ => vec![num(n)],
    }
}

fn string(n: &Node) -> String {
    match &n.value {
        Value::Str(s) => s.clone(),
        v => panic!("not a string: {v:?}"),
    }
}

/// The 3x4 matrix step of an object's transform (identity when absent), row-major
/// (a sphere's first step, its uv turn `scale [1, 1, -1]`, is not part of it).
fn matrix(o: &Node) -> [f64; 12] {
    match o.get("transform") {
        None => [1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0.],
        Some(t) => {
            let Value::Array(steps) = &t.value else {
                panic!()
            };
            match steps.iter().find_map(|s| s.get("matrix")) {
                Some(m) => nums(m).try_into().unwrap(),
                None => [1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0.],
            }
        }
    }
}

fn assert_close(a: &[f64], b: &[f64]) {
    assert_eq!(a.len(), b.len(), "{a:?} vs {b:?}");
    for (x, y) in a.iter().zip(b) {
        assert!((x - y).abs() < 1e-9, "{a:?} vs {b:?}");
    }
}

const HEAD: &str = "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n";

// ---- transforms ---------------------------------------------------------------

#[test]
fn transforms_against_hand_computed_matrices() {
    // With a plain LookAt, Irradia's world is pbrt's with z negated: M' = F M.
    let i = ok(&format!(
        "{HEAD}\
        AttributeBegin Translate 1 2 3 Shape \"sphere\" AttributeEnd\n\
        AttributeBegin Scale 2 3 4 Shape \"sphere\" AttributeEnd\n\
        AttributeBegin Rotate 90 0 0 1 Shape \"sphere\" AttributeEnd\n\
        AttributeBegin Translate 1 0 0 Rotate 90 0 1 0 Shape \"sphere\" AttributeEnd\n\
        AttributeBegin Transform [1 0 0 0  0 1 0 0  0 0 1 0  5 6 7 1] Shape \"sphere\" AttributeEnd\n\
        AttributeBegin Translate 1 0 0 ConcatTransform [2 0 0 0  0 2 0 0  0 0 2 0  0 0 1 1] Shape \"sphere\" AttributeEnd\n\
        AttributeBegin Translate 9 9 9 Identity Shape \"sphere\" AttributeEnd\n\
        Shape \"sphere\"\n"
    ));
    let o = objects(&i);
    assert_eq!(o.len(), 8);
    assert_close(
        &matrix(&o[0]),
        &[1., 0., 0., 1., 0., 1., 0., 2., 0., 0., -1., -3.],
    );
    assert_close(
        &matrix(&o[1]),
        &[2., 0., 0., 0., 0., 3., 0., 0., 0., 0., -4., 0.],
    );
    // Rotate 90 about z: x -> y, y -> -x.
    assert_close(
        &matrix(&o[2]),
        &[0., -1., 0., 0., 1., 0., 0., 0., 0., 0., -1., 0.],
    );
    // T(1,0,0) R_y(90): z -> x, x -> -z; then z negated.
    assert_close(
        &matrix(&o[3]),
        &[0., 0., 1., 1., 0., 1., 0., 0., 1., 0., 0., 0.],
    );
    assert_close(
        &matrix(&o[4]),
        &[1., 0., 0., 5., 0., 1., 0., 6., 0., 0., -1., -7.],
    );
    assert_close(
        &matrix(&o[5]),
        &[2., 0., 0., 1., 0., 2., 0., 0., 0., 0., -2., -1.],
    );
    assert_close(
        &matrix(&o[6]),
        &[1., 0., 0., 0., 0., 1., 0., 0., 0., 0., -1., 0.],
    );
    assert_close(
        &matrix(&o[7]),
        &[1., 0., 0., 0., 0., 1., 0., 0., 0., 0., -1., 0.],
    );
}

#[test]
fn coordinate_systems_and_transform_blocks() {
    let i = ok(&format!(
        "{HEAD}\
        Translate 1 0 0 CoordinateSystem \"a\" Identity\n\
        TransformBegin Translate 0 5 0 TransformEnd\n\
        CoordSysTransform \"a\" Shape \"sphere\"\n\
        CoordSysTransform \"camera\" Shape \"sphere\"\n"
    ));
    let o = objects(&i);
    assert_close(
        &matrix(&o[0]),
        &[1., 0., 0., 1., 0., 1., 0., 0., 0., 0., -1., 0.],
    );
    // The camera's frame: at (0, 0, -5) in pbrt, looking along +z: (0, 0, 5) here.
    let m = matrix(&o[1]);
    assert_close(&[m[3], m[7], m[11]], &[0., 0., 5.]);
}

#[test]
fn camera_film_sampler_integrator() {
    let i = ok("LookAt 1 2 3  1 2 4  0 1 0\n\
        Camera \"perspective\" \"float fov\" 30 \"float lensradius\" 0.1 \"float focaldistance\" 4\n\
        Film \"rgb\" \"integer xresolution\" 200 \"integer yresolution\" 100 \"string filename\" \"x.exr\"\n\
        Sampler \"zsobol\" \"integer pixelsamples\" 64\n\
        Integrator \"path\" \"integer maxdepth\" 7\n\
        WorldBegin\n");
    let c = i.tree.get("camera").unwrap();
    assert_eq!(string(c.get("type").unwrap()), "thinlens");
    assert_close(&nums(c.get("eye").unwrap()), &[1., 2., -3.]);
    assert_close(&nums(c.get("look_at").unwrap()), &[1., 2., -4.]);
    assert_eq!(num(c.get("fov").unwrap()), 30.0);
    assert_eq!(string(c.get("fov_axis").unwrap()), "smaller");
    assert_eq!(num(c.get("aperture_radius").unwrap()), 0.1);
    assert_eq!(num(c.get("focus_distance").unwrap()), 4.0);
    let img = i.tree.get("image").unwrap();
    assert_eq!(num(img.get("width").unwrap()), 200.0);
    assert_eq!(num(img.get("height").unwrap()), 100.0);
    let r = i.tree.get("render").unwrap();
    assert_eq!(num(r.get("spp").unwrap()), 64.0);
    // pbrt's maxdepth counts bounces; Irradia's (Mitsuba's) path segments.
    assert_eq!(num(r.get("max_depth").unwrap()), 8.0);
    assert!(i.notes.iter().any(|n| n.contains("x.exr")), "{:?}", i.notes);
    i.scene().unwrap();

    let o = ok("Camera \"orthographic\"\nFilm \"rgb\" \"integer xresolution\" 100 \"integer yresolution\" 200\nWorldBegin\n");
    let c = o.tree.get("camera").unwrap();
    assert_eq!(string(c.get("type").unwrap()), "orthographic");
    assert_eq!(num(c.get("height").unwrap()), 4.0);
    o.scene().unwrap();
}

// ---- handedness ---------------------------------------------------------------

/// Renders an emitting sphere at pbrt's world (x, 0, 0) and returns the image
/// column of its centroid, as a fraction of the width.
fn sphere_column(camera_prefix: &str, x: f64) -> f64 {
    let i = ok(&format!(
        "{camera_prefix}LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n\
        Film \"rgb\" \"integer xresolution\" 40 \"integer yresolution\" 20\n\
        Sampler \"independent\" \"integer pixelsamples\" 1\nIntegrator \"path\" \"integer maxdepth\" 0\n\
        WorldBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\nTranslate {x} 0 0\nShape \"sphere\" \"float radius\" 0.5\n"
    ));
    let scene = i.scene().unwrap();
    let out = irradia_render::render(&scene, &irradia_render::RenderOptions::default()).unwrap();
    let img = out.image;
    let (mut sum, mut w) = (0.0, 0.0);
    for y in 0..img.height() {
        for xx in 0..img.width() {
            let v = img.get(xx, y).r as f64;
            sum += v * (xx as f64 + 0.5);
            w += v;
        }
    }
    assert!(w > 0.0, "the sphere is not in the image");
    sum / w / img.width() as f64
}

#[test]
fn an_object_on_pbrts_right_stays_on_the_right() {
    // pbrt's LookAt camera at z = -5 looking along +z has +x on its right.
    let right = sphere_column("", 1.5);
    let left = sphere_column("", -1.5);
    assert!(right > 0.6 && left < 0.4, "right {right}, left {left}");
    // With Scale -1 1 1 before LookAt (exporters from right-handed tools), pbrt
    // shows +x on the left; so does the import, without mirroring the world.
    let flipped = sphere_column("Scale -1 1 1\n", 1.5);
    assert!(flipped < 0.4, "{flipped}");
    let i = ok("Scale -1 1 1\nLookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\nTranslate 1 2 3\nShape \"sphere\"\n");
    assert_close(
        &matrix(&objects(&i)[0]),
        &[1., 0., 0., 1., 0., 1., 0., 2., 0., 0., 1., 3.],
    );
}

// ---- the Cornell box: import, round trip, render against the TOML ------------

fn render(scene: &irradia_scene::Scene) -> irradia_core::Image {
    irradia_render::render(scene, &irradia_render::RenderOptions::default())
        .unwrap()
        .image
}

#[test]
fn cornell_box_renders_as_the_same_scene_written_in_toml() {
    let imp = assert_round_trip(&data("cornell.pbrt"));
    let a = render(&imp.scene().unwrap());
    let b = render(&irradia_scene::load_file(&data("cornell.toml")).unwrap());
    assert_eq!((a.width(), a.height()), (b.width(), b.height()));
    let (mut diff, mut total) = (0.0f64, 0.0f64);
    let mut worst = 0.0f64;
    for (p, q) in a.pixels().iter().zip(b.pixels()) {
        for (x, y) in [(p.r, q.r), (p.g, q.g), (p.b, q.b)] {
            diff += (x - y).abs() as f64;
            total += y.abs() as f64;
            worst = worst.max((x - y).abs() as f64);
        }
    }
    assert!(total > 0.0);
    assert!(
        diff / total < 1e-4,
        "relative difference {} (worst pixel {worst})",
        diff / total
    );
}

// ---- materials and textures ---------------------------------------------------

/// Material `name`'s BSDF (inside the `twosided` that reflective ones are wrapped in).
fn material(i: &Imported, name: &str) -> Node {
    let m = i
        .tree
        .get("materials")
        .unwrap()
        .get(name)
        .cloned()
        .unwrap_or_else(|| panic!("no material {name}"));
    if m.get("type").map(string).as_deref() == Some("twosided") {
        let mut inner = m.get("bsdf").unwrap().clone();
        if let Some(e) = m.get("emission") {
            inner.set("emission", e.clone());
        }
        if let Some(e) = m.get("emission_two_sided") {
            inner.set("emission_two_sided", e.clone());
        }
        inner
    } else {
        m
    }
}

#[test]
fn named_materials_and_textures() {
    let i = ok(&format!(
        "{HEAD}\
        Texture \"wood\" \"spectrum\" \"imagemap\" \"string filename\" \"wood.png\" \"float uscale\" 2 \"float vscale\" 3 \"string filter\" \"point\"\n\
        Texture \"check\" \"spectrum\" \"checkerboard\" \"rgb tex1\" [1 0 0] \"rgb tex2\" [0 0 1] \"float uscale\" 4 \"float vscale\" 4\n\
        Texture \"fcheck\" \"float\" \"checkerboard\" \"float tex1\" 0.2 \"float tex2\" 0.6\n\
        Texture \"half\" \"float\" \"scale\" \"float tex\" 0.5 \"float scale\" 0.5\n\
        Texture \"blend\" \"spectrum\" \"mix\" \"rgb tex1\" [0 0 0] \"rgb tex2\" [1 1 1] \"float amount\" 0.25\n\
        MakeNamedMaterial \"floor\" \"string type\" \"diffuse\" \"texture reflectance\" \"wood\"\n\
        MakeNamedMaterial \"board\" \"string type\" \"diffuse\" \"texture reflectance\" \"check\"\n\
        MakeNamedMaterial \"gold\" \"string type\" \"conductor\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\"\n\
        MakeNamedMaterial \"brushed\" \"string type\" \"conductor\" \"float uroughness\" 0.04 \"float vroughness\" 0.16 \"bool remaproughness\" false\n\
        MakeNamedMaterial \"glass\" \"string type\" \"dielectric\" \"float eta\" 1.33 \"float roughness\" 0.25\n\
        MakeNamedMaterial \"window\" \"string type\" \"thindielectric\"\n\
        MakeNamedMaterial \"paint\" \"string type\" \"coateddiffuse\" \"rgb reflectance\" [0.8 0.1 0.1] \"float roughness\" 0.01\n\
        MakeNamedMaterial \"mixed\" \"string type\" \"mix\" \"string materials\" [\"gold\" \"floor\"] \"texture amount\" \"half\"\n\
        MakeNamedMaterial \"grey\" \"string type\" \"diffuse\" \"texture reflectance\" \"blend\"\n\
        MakeNamedMaterial \"patchy\" \"string type\" \"mix\" \"string materials\" [\"gold\" \"floor\"] \"texture amount\" \"fcheck\"\n\
        NamedMaterial \"board\" Shape \"sphere\"\n"
    ));
    let floor = material(&i, "floor");
    let r = floor.get("reflectance").unwrap();
    assert_eq!(string(r.get("type").unwrap()), "bitmap");
    assert_eq!(string(r.get("filter_type").unwrap()), "nearest");
    // pbrt reads (s, 1 - t): uv' = (2u, 1 - 3v).
    let to_uv = r.get("to_uv").unwrap();
    let Value::Array(steps) = &to_uv.value else {
        panic!()
    };
    assert_close(&nums(steps[0].get("scale").unwrap()), &[2., -3.]);
    assert_close(&nums(steps[1].get("translate").unwrap()), &[0., 1.]);
    let board = material(&i, "board").get("reflectance").cloned().unwrap();
    assert_close(&nums(board.get("color0").unwrap()), &[1., 0., 0.]);
    assert_close(&nums(board.get("color1").unwrap()), &[0., 0., 1.]);
    let Value::Array(steps) = &board.get("to_uv").unwrap().value else {
        panic!()
    };
    assert_close(&nums(steps[0].get("scale").unwrap()), &[2., 2.]);
    assert_eq!(string(material(&i, "gold").get("material").unwrap()), "Au");
    let brushed = material(&i, "brushed");
    assert_eq!(string(brushed.get("type").unwrap()), "roughconductor");
    assert_eq!(string(brushed.get("material").unwrap()), "Cu");
    assert_close(
        &[
            num(brushed.get("alpha_u").unwrap()),
            num(brushed.get("alpha_v").unwrap()),
        ],
        &[0.04, 0.16],
    );
    let glass = material(&i, "glass");
    assert_eq!(string(glass.get("type").unwrap()), "roughdielectric");
    assert_close(
        &[
            num(glass.get("alpha").unwrap()),
            num(glass.get("int_ior").unwrap()),
        ],
        &[0.5, 1.33],
    );
    assert_eq!(
        string(material(&i, "window").get("type").unwrap()),
        "thindielectric"
    );
    let paint = material(&i, "paint");
    assert_eq!(string(paint.get("type").unwrap()), "roughplastic");
    assert_close(&[num(paint.get("alpha").unwrap())], &[0.1]);
    let mixed = material(&i, "mixed");
    assert_eq!(string(mixed.get("type").unwrap()), "blendbsdf");
    assert_eq!(num(mixed.get("weight").unwrap()), 0.25);
    assert_eq!(num(material(&i, "grey").get("reflectance").unwrap()), 0.25);
    // As a number Mitsuba's checkerboard is the other way round: tex1 is color1.
    let w = material(&i, "patchy").get("weight").cloned().unwrap();
    assert_eq!(
        (num(w.get("color0").unwrap()), num(w.get("color1").unwrap())),
        (0.6, 0.2)
    );
    assert!(i
        .warnings
        .iter()
        .any(|w| w.to_string().contains("coateddiffuse")));
    assert_eq!(string(objects(&i)[0].get("material").unwrap()), "board");
}

#[test]
fn spectra_become_rgb() {
    let i = ok(&format!(
        "{HEAD}\
        LightSource \"point\" \"blackbody I\" 2700 \"float scale\" 3\n\
        LightSource \"distant\" \"spectrum L\" \"stdillum-D65\" \"point3 from\" [0 0 0] \"point3 to\" [0 -1 1]\n\
        LightSource \"spot\" \"rgb I\" [1 2 3] \"point3 from\" [0 4 0] \"point3 to\" [0 0 0] \"float coneangle\" 20 \"float conedelta\" 5\n\
        LightSource \"infinite\" \"rgb L\" [0.1 0.2 0.3]\n"
    ));
    let Value::Array(l) = &i.tree.get("lights").unwrap().value else {
        panic!()
    };
    let warm = nums(l[0].get("intensity").unwrap());
    let lum = 0.2126 * warm[0] + 0.7152 * warm[1] + 0.0722 * warm[2];
    assert!((lum - 3.0).abs() < 0.05 && warm[0] > warm[2], "{warm:?}");
    assert_eq!(string(l[1].get("type").unwrap()), "directional");
    let d = nums(l[1].get("direction").unwrap());
    let s = 0.5f64.sqrt();
    assert_close(&d, &[0., -s, -s]);
    assert_eq!(num(l[1].get("irradiance").unwrap()), 1.0);
    assert_close(
        &[
            num(l[2].get("outer_angle").unwrap()),
            num(l[2].get("inner_angle").unwrap()),
        ],
        &[20., 15.],
    );
    assert_eq!(string(l[3].get("type").unwrap()), "constant");
    i.scene().unwrap();
}

// ---- attribute scoping, area lights, orientation ---------------------------------

#[test]
fn attributes_scope_the_material_the_area_light_and_the_ctm() {
    let i = ok(&format!(
        "{HEAD}\
        Material \"diffuse\" \"rgb reflectance\" [0.1 0.2 0.3]\n\
        AttributeBegin\n\
          Material \"conductor\"\n\
          AreaLightSource \"diffuse\" \"rgb L\" [4 4 4] \"bool twosided\" true\n\
          Translate 0 1 0\n\
          ReverseOrientation\n\
          Shape \"sphere\"\n\
        AttributeEnd\n\
        Shape \"sphere\"\n"
    ));
    let o = objects(&i);
    let lit = string(o[0].get("material").unwrap());
    let plain = string(o[1].get("material").unwrap());
    assert_eq!(plain, "material#1");
    let m = material(&i, &lit);
    assert_eq!(string(m.get("type").unwrap()), "conductor");
    assert_eq!(num(m.get("emission").unwrap()), 4.0);
    assert_eq!(
        m.get("emission_two_sided").map(|b| b.value.clone()),
        Some(Value::Bool(true))
    );
    assert_eq!(
        o[0].get("flip_normals").map(|b| b.value.clone()),
        Some(Value::Bool(true))
    );
    assert!(o[1].get("flip_normals").is_none());
    assert_close(
        &matrix(&o[1]),
        &[1., 0., 0., 0., 0., 1., 0., 0., 0., 0., -1., 0.],
    );
    i.scene().unwrap();
}

#[test]
fn reverse_orientation_turns_a_triangle_without_normals() {
    let i = ok(&format!(
        "{HEAD}ReverseOrientation\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2]\n"
    ));
    assert_close(&nums(objects(&i)[0].get("indices").unwrap()), &[0., 2., 1.]);
}

// ---- object instancing -----------------------------------------------------------

#[test]
fn object_instances_become_shape_groups() {
    let i = ok(&format!(
        "{HEAD}\
        ObjectBegin \"tree\"\n  Material \"diffuse\"\n  Shape \"sphere\" \"float radius\" 0.5\n  Translate 0 1 0 Shape \"cylinder\"\nObjectEnd\n\
        AttributeBegin Translate 2 0 0 ObjectInstance \"tree\" AttributeEnd\n\
        ObjectInstance \"tree\"\n"
    ));
    let Value::Array(groups) = &i.tree.get("shape_groups").unwrap().value else {
        panic!()
    };
    assert_eq!(groups.len(), 1);
    assert_eq!(string(groups[0].get("name").unwrap()), "tree");
    let Value::Array(members) = &groups[0].get("objects").unwrap().value else {
        panic!()
    };
    // Members keep pbrt's coordinates; the instance carries the mirror.
    assert_close(
        &matrix(&members[1]),
        &[1., 0., 0., 0., 0., 1., 0., 1., 0., 0., 1., 0.],
    );
    let o = objects(&i);
    assert_eq!(string(o[0].get("type").unwrap()), "instance");
    assert_close(
        &matrix(&o[0]),
        &[1., 0., 0., 2., 0., 1., 0., 0., 0., 0., -1., 0.],
    );
    i.scene().unwrap();
    let e = err(&format!("{HEAD}ObjectInstance \"nope\"\n"));
    assert!(e.contains("scene.pbrt:4:16") && e.contains("nope"), "{e}");
}

// ---- include, meshes -------------------------------------------------------------

#[test]
fn include_and_import_read_other_files_and_errors_name_them() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("geometry")).unwrap();
    std::fs::write(
        dir.path().join("geometry/ball.pbrt"),
        "# the ball\nShape \"sphere\" \"float radius\" 2\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("geometry/bad.pbrt"),
        "Shape \"sphere\"\n  Shape \"cube\"\n",
    )
    .unwrap();
    let main = dir.path().join("main.pbrt");
    std::fs::write(
        &main,
        format!("{HEAD}Include \"geometry/ball.pbrt\"\nImport \"geometry/ball.pbrt\"\n"),
    )
    .unwrap();
    let i = import(&main, &Options::default()).unwrap();
    assert_eq!(objects(&i).len(), 2);
    assert_eq!(num(objects(&i)[0].get("radius").unwrap()), 2.0);
    std::fs::write(&main, format!("{HEAD}Include \"geometry/bad.pbrt\"\n")).unwrap();
    let e = import(&main, &Options::default()).unwrap_err().to_string();
    assert!(
        e.contains("bad.pbrt:2:3") && e.contains("unknown shape \"cube\""),
        "{e}"
    );
    std::fs::write(&main, format!("{HEAD}Include \"geometry/missing.pbrt\"\n")).unwrap();
    let e = import(&main, &Options::default()).unwrap_err().to_string();
    assert!(
        e.contains("main.pbrt:4:1") && e.contains("missing.pbrt"),
        "{e}"
    );
}

#[test]
fn plymesh_and_gzipped_plymesh_load() {
    use std::io::Write;
    let dir = tempfile::tempdir().unwrap();
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    std::fs::write(dir.path().join("tri.ply"), ply).unwrap();
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    gz.write_all(ply.as_bytes()).unwrap();
    std::fs::write(dir.path().join("tri.ply.gz"), gz.finish().unwrap()).unwrap();
    let main = dir.path().join("main.pbrt");
    std::fs::write(
        &main,
        format!("{HEAD}Shape \"plymesh\" \"string filename\" \"tri.ply\"\nShape \"plymesh\" \"string filename\" \"tri.ply.gz\"\n"),
    )
    .unwrap();
    let i = assert_round_trip(&main);
    assert_eq!(string(objects(&i)[1].get("path").unwrap()), "tri.ply.gz");
}

// ---- errors and warnings ---------------------------------------------------------

#[test]
fn errors_name_the_line_and_column() {
    let e = err("WorldBegin\n  Shap \"sphere\"\n");
    assert!(
        e.contains("scene.pbrt:2:3")
            && e.contains("unknown directive `Shap`; did you mean `Shape`?"),
        "{e}"
    );
    let e = err("WorldBegin\nShape \"sphere\" \"flaot radius\" 1\n");
    assert!(
        e.contains("scene.pbrt:2:16") && e.contains("unknown parameter type `flaot`"),
        "{e}"
    );
    let e = err("WorldBegin\nShape \"cube\"\n");
    assert!(
        e.contains("scene.pbrt:2:1") && e.contains("unknown shape \"cube\""),
        "{e}"
    );
    let e = err("WorldBegin\nShape \"sphere\" \"float radus\" 1\n");
    assert!(
        e.contains("scene.pbrt:2:16") && e.contains("unknown parameter \"float radus\""),
        "{e}"
    );
    let e = err("WorldBegin\nShape \"sphere\" \"float radius\" \"big\"\n");
    assert!(e.contains("scene.pbrt:2:31"), "{e}");
    let e = err("WorldBegin\nNamedMaterial \"nope\"\n");
    assert!(e.contains("scene.pbrt:2:15"), "{e}");
    let e = err("WorldBegin\nMaterial \"plastik\"\n");
    assert!(e.contains("unknown material type \"plastik\""), "{e}");
    let e = err("Translate 1 2\n");
    assert!(
        e.contains("scene.pbrt:2:1") || e.contains("scene.pbrt:1:"),
        "{e}"
    );
    let e = err("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 3]\n");
    assert!(e.contains("out of range"), "{e}");
    let e = err("WorldBegin\nAttributeEnd\n");
    assert!(e.contains("scene.pbrt:2:1"), "{e}");
    let e = err("Shape \"sphere\" \"string s\" \"unterminated\n");
    assert!(
        e.contains("scene.pbrt:1:27") && e.contains("unterminated"),
        "{e}"
    );
}

#[test]
fn unrendered_features_warn_and_strict_refuses_them() {
    let text = format!(
        "{HEAD}MakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\nMaterial \"coateddiffuse\"\nShape \"sphere\" \"float zmax\" 0.5\nShape \"curve\" \"point3 P\" [0 0 0 1 1 1 2 2 2 3 3 3]\n"
    );
    let i = ok(&text);
    let all: Vec<String> = i.warnings.iter().map(|w| w.to_string()).collect();
    for needle in ["media", "coateddiffuse", "partial", "curve"] {
        assert!(all.iter().any(|w| w.contains(needle)), "{needle}: {all:#?}");
    }
    assert!(all.iter().all(|w| w.contains("scene.pbrt:")), "{all:#?}");
    assert_eq!(objects(&i).len(), 1);
    i.scene().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.pbrt");
    std::fs::write(&path, &text).unwrap();
    let e = import(
        &path,
        &Options {
            strict: true,
            ..Options::default()
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("--strict"), "{e}");
}

// ---- in memory, coverage, real files -----------------------------------------------

#[test]
fn parse_str_touches_no_files() {
    let i = parse_str(
        &format!("{HEAD}Include \"nowhere.pbrt\"\nShape \"sphere\"\n"),
        Path::new("mem.pbrt"),
    )
    .unwrap();
    assert_eq!(objects(&i).len(), 1);
    assert!(i.notes.iter().any(|n| n.contains("nowhere.pbrt")));
}

#[test]
fn coverage_counts_and_goes_on_after_errors() {
    let c = coverage_str(
        &format!("{HEAD}Shape \"sphere\"\nShape \"cube\"\nMaterial \"coateddiffuse\"\nShape \"sphere\"\n"),
        Path::new("c.pbrt"),
    );
    assert_eq!(c.total("shape", "sphere"), 2);
    assert_eq!(
        c.counts[&("shape".to_string(), "cube".to_string())].get(&Status::Refused),
        Some(&1)
    );
    assert_eq!(
        c.counts[&("material".to_string(), "coateddiffuse".to_string())].get(&Status::Warned),
        Some(&1)
    );
    assert_eq!(c.errors.len(), 1);
}

/// Excerpts of real scenes from mmp/pbrt-v4-scenes (each file names its source).
#[test]
fn real_scene_excerpts_import() {
    for entry in std::fs::read_dir(data("real")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("pbrt") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let i = parse_str(&text, &path).unwrap_or_else(|e| panic!("{e}"));
        assert!(i.tree.get("camera").is_some());
        let c = coverage_str(&text, &path);
        assert!(c.errors.is_empty(), "{}: {:?}", path.display(), c.errors);
    }
}

// ---- environment maps ---------------------------------------------------------

/// The brightest image column's position (fraction of the width) of a render of a
/// pbrt-v4 equal-area environment map with one bright patch, seen by pbrt's default
/// camera (at the origin, looking along +z) after `camera_prefix`.
fn envmap_patch_column(camera_prefix: &str) -> f64 {
    let dir = tempfile::tempdir().unwrap();
    // The patch at the square's (0.683, 0.5): pbrt's direction (sin 30°, 0, cos 30°),
    // 30° to the right of the view axis (+x is pbrt's right for this camera).
    let n = 64u32;
    let img = image::RgbImage::from_fn(n, n, |x, y| {
        let (u, v) = ((x as f64 + 0.5) / n as f64, (y as f64 + 0.5) / n as f64);
        if (u - 0.683).abs() < 0.04 && (v - 0.5).abs() < 0.04 {
            image::Rgb([255, 255, 255])
        } else {
            image::Rgb([2, 2, 2])
        }
    });
    img.save(dir.path().join("sky.png")).unwrap();
    let path = dir.path().join("scene.pbrt");
    std::fs::write(
        &path,
        format!(
            "{camera_prefix}Camera \"perspective\" \"float fov\" 90\n\
            Film \"rgb\" \"integer xresolution\" 48 \"integer yresolution\" 48\n\
            Sampler \"independent\" \"integer pixelsamples\" 4\nIntegrator \"path\" \"integer maxdepth\" 0\n\
            WorldBegin\nLightSource \"infinite\" \"string filename\" \"sky.png\"\n"
        ),
    )
    .unwrap();
    let i = import(&path, &Options::default()).unwrap();
    let Value::Array(l) = &i.tree.get("lights").unwrap().value else {
        panic!()
    };
    assert_eq!(string(l[0].get("mapping").unwrap()), "equal_area");
    let img = render(&i.scene().unwrap());
    // The centroid of the bright pixels.
    let (mut sum, mut count) = (0.0, 0.0);
    for y in 0..img.height() {
        for x in 0..img.width() {
            if img.get(x, y).g > 0.5 {
                sum += x as f64 + 0.5;
                count += 1.0;
            }
        }
    }
    assert!(count > 0.0, "the patch is not in view");
    sum / count / img.width() as f64
}

#[test]
fn equal_area_environment_maps_keep_pbrts_orientation() {
    // tan 30° / tan 45° = 0.577: the patch is near 0.79 of the width.
    let right = envmap_patch_column("");
    assert!((right - 0.79).abs() < 0.06, "{right}");
    let flipped = envmap_patch_column("Scale -1 1 1\n");
    assert!((flipped - 0.21).abs() < 0.06, "{flipped}");
}

#[test]
fn spheres_are_turned_over_for_pbrts_texture_coordinates() {
    // pbrt: v = 1 − θ/π (θ from +z); Irradia: θ/π. The object-space turn z → −z
    // makes the sphere's v pbrt's, leaving its surface and normals as they were.
    let i = ok(&format!(
        "{HEAD}Translate 1 0 0 Shape \"sphere\"\nShape \"cylinder\"\n"
    ));
    let o = objects(&i);
    let Value::Array(steps) = &o[0].get("transform").unwrap().value else {
        panic!()
    };
    assert_close(&nums(steps[0].get("scale").unwrap()), &[1., 1., -1.]);
    assert_close(
        &matrix(&o[0]),
        &[1., 0., 0., 1., 0., 1., 0., 0., 0., 0., -1., 0.],
    );
    let Value::Array(steps) = &o[1].get("transform").unwrap().value else {
        panic!()
    };
    assert_eq!(steps.len(), 1, "only spheres are turned");
    i.scene().unwrap();
}

/// pbrt-v4's photometric parameters: an area light's `power` is what each shape
/// emits (L π A per side, so L = power / (π · sides · A)); `illuminance` sets a distant
/// light's irradiance and what a uniform infinite light gives a surface facing up (π L).
#[test]
fn power_and_illuminance_scale_lights_as_pbrt_v4() {
    use std::f64::consts::PI;
    let i = ok(&format!(
        "{HEAD}\
        AttributeBegin\n\
          AreaLightSource \"diffuse\" \"rgb L\" [1 1 1] \"float power\" 100\n\
          Shape \"sphere\" \"float radius\" 2\n\
        AttributeEnd\n\
        AttributeBegin\n\
          AreaLightSource \"diffuse\" \"rgb L\" [1 0.5 1] \"float power\" 10 \"bool twosided\" true\n\
          Shape \"disk\" \"float radius\" 1\n\
        AttributeEnd\n\
        AttributeBegin\n\
          AreaLightSource \"diffuse\" \"rgb L\" [1 1 1] \"float power\" 5\n\
          Scale 2 2 2\n\
          Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 1 1 0 0 1 0] \"integer indices\" [0 1 2 0 2 3]\n\
        AttributeEnd\n\
        LightSource \"distant\" \"rgb L\" [1 1 1] \"float illuminance\" 3\n\
        LightSource \"infinite\" \"rgb L\" [1 1 1] \"float illuminance\" 6.283185307179586\n"
    ));
    assert!(i.warnings.is_empty(), "{:?}", i.warnings);
    let o = objects(&i);
    let emission = |k: usize| {
        material(&i, &string(o[k].get("material").unwrap()))
            .get("emission")
            .unwrap()
            .clone()
    };
    assert!((num(&emission(0)) - 100.0 / (PI * 16.0 * PI)).abs() < 1e-9);
    let disk = nums(&emission(1));
    assert_close(
        &disk,
        &[
            10.0 / (2.0 * PI * PI),
            5.0 / (2.0 * PI * PI),
            10.0 / (2.0 * PI * PI),
        ],
    );
    // Two triangles of area 2 each after the scale: each emits 5 W.
    assert!((num(&emission(2)) - 5.0 / (PI * 2.0)).abs() < 1e-9);
    let Value::Array(l) = &i.tree.get("lights").unwrap().value else {
        panic!()
    };
    assert_eq!(num(l[0].get("irradiance").unwrap()), 3.0);
    assert!((num(l[1].get("radiance").unwrap()) - 2.0).abs() < 1e-12);
    i.scene().unwrap();
    // Unequal triangles: the mean area, with a warning.
    let i = ok(&format!(
        "{HEAD}\
        AreaLightSource \"diffuse\" \"rgb L\" [1 1 1] \"float power\" 1\n\
        Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 3 0 0 0 3 0] \"integer indices\" [0 1 2 0 3 4]\n"
    ));
    assert_eq!(i.warnings.len(), 1, "{:?}", i.warnings);
    assert!(i.warnings[0].to_string().contains("unequal"));
}
