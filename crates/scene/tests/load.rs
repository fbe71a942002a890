//! Loading: TOML and JSON give the same scene; every built-in loads; transforms compose
//! in the order written; settings and defaults arrive where the renderer reads them.

use glam::Vec3;
use irradia_core::Ray;
use irradia_scene::{builtin, load_file, load_str, Light, Projection, Scene, SceneSyntax};
use std::path::Path;

const TOML: &str = r#"
[image]
width = 64
height = 48

[camera]
eye = [0, 1, 6]
look_at = [0, 0.5, 0]
fov = 40
fov_axis = "vertical"

[render]
max_depth = 7
min_weight = 0.01
spp = 4
adaptive_threshold = 0.05
background = [0.1, 0.2, 0.3]
ambient_light = 0.5
integrator = "path"

[materials.red]
color = [0.9, 0.1, 0.1]
specular = 0.5
shininess = 30
model = "povray"

[materials.floor]
color = { type = "checker", colors = [0.2, 0.8], scale = 0.5 }

[[lights]]
type = "point"
position = [1, 5, 2]
intensity = [10, 9, 8]

[[lights]]
type = "rect"
corner = [-1, 4, -1]
edge_u = [2, 0, 0]
edge_v = [0, 0, 2]
radiance = 5
samples = 9

[[objects]]
type = "sphere"
radius = 0.5
material = "red"
transform = [{ scale = 2 }, { translate = [1, 0, 0] }]

[[objects]]
type = "plane"
normal = [0, 1, 0]
material = "floor"
"#;

const JSON: &str = r#"{
  "image": {"width": 64, "height": 48},
  "camera": {"eye": [0, 1, 6], "look_at": [0, 0.5, 0], "fov": 40, "fov_axis": "vertical"},
  "render": {"max_depth": 7, "min_weight": 0.01, "spp": 4, "adaptive_threshold": 0.05,
             "background": [0.1, 0.2, 0.3], "ambient_light": 0.5, "integrator": "path"},
  "materials": {
    "red": {"color": [0.9, 0.1, 0.1], "specular": 0.5, "shininess": 30, "model": "povray"},
    "floor": {"color": {"type": "checker", "colors": [0.2, 0.8], "scale": 0.5}}
  },
  "lights": [
    {"type": "point", "position": [1, 5, 2], "intensity": [10, 9, 8]},
    {"type": "rect", "corner": [-1, 4, -1], "edge_u": [2, 0, 0], "edge_v": [0, 0, 2],
     "radiance": 5, "samples": 9}
  ],
  "objects": [
    {"type": "sphere", "radius": 0.5, "material": "red",
     "transform": [{"scale": 2}, {"translate": [1, 0, 0]}]},
    {"type": "plane", "normal": [0, 1, 0], "material": "floor"}
  ]
}"#;

/// Everything observable about a scene, as text (materials hold textures that are not
/// comparable directly).
fn fingerprint(s: &Scene) -> String {
    let mut out = format!("{:?}\n{:?}\n{:?}\n", s.camera, s.settings, s.lights);
    for m in &s.materials {
        out += &format!("{m:?}\n");
    }
    for (o, i) in s.objects.iter().zip(s.accel.instances()) {
        out += &format!(
            "{} {} {:?} {} {:?}\n",
            o.name,
            o.material,
            o.leaf_materials,
            i.shape.kind(),
            i.to_world()
        );
    }
    out
}

#[test]
fn toml_and_json_load_identically() {
    let a = load_str(TOML, SceneSyntax::Toml, Path::new("a.toml")).unwrap();
    let b = load_str(JSON, SceneSyntax::Json, Path::new("a.json")).unwrap();
    assert_eq!(fingerprint(&a), fingerprint(&b));
    // And the values are the ones written.
    assert_eq!(a.settings.width, 64);
    assert_eq!(a.settings.max_depth, 7);
    assert_eq!(a.settings.spp, 4);
    assert_eq!(a.settings.adaptive_threshold, Some(0.05));
    assert_eq!(a.settings.integrator, irradia_scene::Integrator::Path);
    assert_eq!(a.settings.ambient_light, irradia_core::Rgb::splat(0.5));
    assert!(matches!(
        a.camera.projection,
        Projection::Perspective { fov_degrees, axis: irradia_scene::FovAxis::Vertical } if fov_degrees == 40.0
    ));
    assert!(matches!(a.lights[1], Light::Rect { samples: 9, .. }));
    assert_eq!(a.materials[0].model, irradia_scene::ShadingModel::PovRay);
    // Rays hit the same things in both.
    let ray = Ray::new(Vec3::new(1.0, 0.0, 5.0), -Vec3::Z);
    let ha = a.accel.intersect(&ray, f32::INFINITY).unwrap();
    let hb = b.accel.intersect(&ray, f32::INFINITY).unwrap();
    assert_eq!(ha.hit.t, hb.hit.t);
    assert!(
        (ha.hit.t - 4.0).abs() < 1e-4,
        "scaled sphere of radius 1 at x = 1"
    );
}

#[test]
fn transforms_apply_in_the_order_written() {
    let scene = |steps: &str| {
        let text = format!(
            "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n[[objects]]\ntype = \"sphere\"\nradius = 1\ntransform = {steps}\n"
        );
        load_str(&text, SceneSyntax::Toml, Path::new("t.toml")).unwrap()
    };
    let map = |s: &Scene, p: Vec3| s.accel.instances()[0].to_world().transform_point3(p);
    let p = Vec3::new(1.0, 0.0, 0.0);
    // Scale, then translate: 2p + t.
    let s = scene("[{ scale = 2 }, { translate = [0, 3, 0] }]");
    assert!((map(&s, p) - Vec3::new(2.0, 3.0, 0.0)).length() < 1e-6);
    // Translate, then scale: 2(p + t).
    let s = scene("[{ translate = [0, 3, 0] }, { scale = 2 }]");
    assert!((map(&s, p) - Vec3::new(2.0, 6.0, 0.0)).length() < 1e-6);
    // Rotate 90 degrees about z (counter-clockwise), then translate.
    let s = scene("[{ rotate = { axis = [0, 0, 1], angle = 90 } }, { translate = [5, 0, 0] }]");
    assert!((map(&s, p) - Vec3::new(5.0, 1.0, 0.0)).length() < 1e-6);
    // Euler angles: x first, then y, then z. x by 90 takes +y to +z; y by 90 takes +z to +x.
    let s = scene("[{ rotate = [90, 90, 0] }]");
    assert!(
        (map(&s, Vec3::Y) - Vec3::X).length() < 1e-6,
        "{}",
        map(&s, Vec3::Y)
    );
    // A matrix (rows), then a translation.
    let s = scene(
        "[{ matrix = [[0, -1, 0, 1], [1, 0, 0, 2], [0, 0, 1, 3]] }, { translate = [1, 1, 1] }]",
    );
    assert!((map(&s, p) - Vec3::new(2.0, 4.0, 4.0)).length() < 1e-6);
}

#[test]
fn every_builtin_loads() {
    let names = builtin::names();
    for want in ["default", "whitted"] {
        assert!(
            names.iter().any(|(n, _)| *n == want),
            "missing built-in {want}"
        );
    }
    for (name, description) in names {
        assert!(!description.is_empty());
        let s = builtin::load(name).unwrap_or_else(|e| panic!("built-in {name}: {e}"));
        assert!(!s.objects.is_empty(), "{name} has objects");
        assert!(!s.lights.is_empty() || s.materials.iter().any(|m| !m.emission.is_black()));
    }
}

#[test]
fn builtin_files_on_disk_load_too() {
    // The built-ins are the format's examples: they load as ordinary files (the files
    // they name, such as the gallery's environment map, lie beside them).
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut scenes = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml" || e == "json") {
            load_file(&path).unwrap_or_else(|e| panic!("{e}"));
            scenes += 1;
        }
    }
    assert_eq!(scenes, builtin::names().len());
}

#[test]
fn objects_without_material_get_the_default_one() {
    let text = "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n[[objects]]\ntype = \"sphere\"\nradius = 1\n";
    let s = load_str(text, SceneSyntax::Toml, Path::new("d.toml")).unwrap();
    assert_eq!(s.materials.len(), 1);
    assert_eq!(s.materials[s.objects[0].material as usize].name, "default");
}

#[test]
fn relative_mesh_paths_resolve_against_the_scene_file() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/meshes/scene.toml");
    // Load from another working directory's point of view: the path is absolute, the
    // mesh paths inside are relative to the scene file's folder.
    let s = load_file(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.objects.len(), 2);
    let kinds: Vec<&str> = s.accel.instances().iter().map(|i| i.shape.kind()).collect();
    assert_eq!(kinds[0], kinds[1]);
    // Both tetrahedra are where the scene puts them: a ray down -z through (0.2, 0.2)
    // hits the OBJ one on its slanted face x + y + z = 1; the PLY one is moved by -1.5.
    let hit = |x: f32| {
        s.accel
            .intersect(&Ray::new(Vec3::new(x, 0.2, 5.0), -Vec3::Z), f32::INFINITY)
            .map(|h| (h.instance, h.hit.point))
    };
    let (i, p) = hit(0.2).unwrap();
    assert_eq!(i, 0);
    assert!((p.z - 0.6).abs() < 1e-5, "{p}");
    let (i, p) = hit(-1.3).unwrap();
    assert_eq!(i, 1);
    assert!((p.z - 0.6).abs() < 1e-5, "{p}");
}

#[test]
fn csg_leaves_get_their_own_materials_depth_first() {
    let text = r#"
[camera]
eye = [0, 0, 5]
look_at = [0, 0, 0]
[materials.a]
[materials.b]
[materials.c]
[[objects]]
type = "difference"
material = "a"
children = [
  { type = "box", min = [-1, -1, -1], max = [1, 1, 1] },
  { type = "union", material = "b", children = [
      { type = "sphere", radius = 1.2 },
      { type = "sphere", radius = 0.2, center = [3, 0, 0], material = "c" },
  ] },
]
"#;
    let s = load_str(text, SceneSyntax::Toml, Path::new("c.toml")).unwrap();
    assert_eq!(s.objects[0].leaf_materials, vec![0, 1, 2]);
    assert_eq!(s.objects[0].material_for_leaf(1), 1);
    // A ray along the x axis enters the box at a corner region outside the sphere? No:
    // along a diagonal the box corner lies outside the sphere of radius 1.2.
    let d = Vec3::new(-1.0, -1.0, -1.0).normalize();
    let h = s
        .accel
        .intersect(&Ray::new(-d * 5.0, d), f32::INFINITY)
        .unwrap();
    assert!((h.hit.point - Vec3::ONE).length() < 1e-4, "{}", h.hit.point);
    assert_eq!(h.hit.leaf, 0);
}

#[test]
fn every_object_type_loads_and_sits_where_it_is_put() {
    // One object of each type, each moved to x = 10 * i; a ray straight down at the
    // object's centre must hit object i (and nothing else).
    let objects = [
        r#"type = "sphere"
radius = 1"#,
        r#"type = "box"
min = [-1, -1, -1]
max = [1, 1, 1]"#,
        r#"type = "polyhedron"
platonic = "octahedron""#,
        r#"type = "polygon"
vertices = [[-1, 0, -1], [1, 0, -1], [0, 0, 1]]"#,
        r#"type = "disk"
radius = 1"#,
        r#"type = "quadric"
coefficients = [1, 1, 1, 0, 0, 0, 0, 0, 0, -1]"#,
        r#"type = "ellipsoid"
radii = [1, 0.5, 1]"#,
        r#"type = "cylinder"
from = [0, -1, 0]
to = [0, 1, 0]
radius = 0.5"#,
        r#"type = "cone"
from = [0, -1, 0]
to = [0, 1, 0]
radius_from = 1
radius_to = 0.2"#,
        r#"type = "paraboloid"
curvature = 1
clip_box = { min = [-2, -2, -2], max = [2, 1, 2] }"#,
        r#"type = "hyperboloid"
a = 0.5
c = 1
clip_box = { min = [-2, -1, -2], max = [2, 1, 2] }"#,
        r#"type = "torus"
major = 1
minor = 0.3
transform = [{ rotate = [90, 0, 0] }]"#,
        r#"type = "teapot"
level = 4"#,
        r#"type = "bezier"
level = 2
patches = [[[-1, 0, -1], [-0.3, 0, -1], [0.3, 0, -1], [1, 0, -1],
            [-1, 0, -0.3], [-0.3, 0.5, -0.3], [0.3, 0.5, -0.3], [1, 0, -0.3],
            [-1, 0, 0.3], [-0.3, 0.5, 0.3], [0.3, 0.5, 0.3], [1, 0, 0.3],
            [-1, 0, 1], [-0.3, 0, 1], [0.3, 0, 1], [1, 0, 1]]]"#,
        r#"type = "implicit"
expr = "x^2 + y^2 + z^2 - 1"
bounds = { min = [-1.1, -1.1, -1.1], max = [1.1, 1.1, 1.1] }"#,
        r#"type = "parametric"
x = "cos(u)*sin(v)"
y = "cos(v)"
z = "sin(u)*sin(v)"
u = [0, "2*pi"]
v = [0, "pi"]
resolution = [32, 16]"#,
        r#"type = "union"
children = [{ type = "sphere", radius = 1 }, { type = "box", min = [-0.5, -2, -0.5], max = [0.5, 0.5, 0.5] }]"#,
        r#"type = "gyroid_mesh"
grid = 16"#,
        r#"type = "mesh"
path = "tests/data/meshes/tetra.obj"
transform = [{ translate = [-0.25, -0.25, -0.25] }]"#,
    ];
    let mut text = String::from("[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n");
    for (i, o) in objects.iter().enumerate() {
        text += &format!("\n[[objects]]\n{o}\n");
        // Place each object by appending a translation (after its own transform).
        if o.contains("transform") {
            let last = text.rfind("}]").unwrap();
            text.insert_str(last + 1, &format!(", {{ translate = [{}, 0, 0] }}", 10 * i));
        } else {
            text += &format!("transform = [{{ translate = [{}, 0, 0] }}]\n", 10 * i);
        }
    }
    let origin = Path::new(env!("CARGO_MANIFEST_DIR")).join("scene.toml");
    let s = load_str(&text, SceneSyntax::Toml, &origin).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.objects.len(), objects.len());
    for (i, object) in objects.iter().enumerate() {
        let x = 10.0 * i as f32;
        // The teapot's body is off-centre of its origin less than 1.5; aim at y = 1 on it.
        let y0 = if object.contains("teapot") { 1.0 } else { 0.0 };
        let ray = Ray::new(Vec3::new(x + 0.01, 20.0, 0.013), -Vec3::Y);
        let ray = if y0 > 0.0 {
            Ray::new(Vec3::new(x + 0.01, y0, 20.0), -Vec3::Z)
        } else {
            ray
        };
        let h = s
            .accel
            .intersect(&ray, f32::INFINITY)
            .unwrap_or_else(|| panic!("object {i} ({}) not hit", object));
        assert_eq!(h.instance as usize, i, "{}", object);
    }
}

#[test]
fn json_copies_of_the_povray_builtins_load_identically() {
    // tests/data/{whitted,csg}.json were written from the TOML built-ins by a generic
    // TOML-to-JSON conversion (Python's tomllib + json).
    for name in ["whitted", "csg"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("tests/data/{name}.json"));
        let json = load_file(&path).unwrap_or_else(|e| panic!("{e}"));
        let toml = builtin::load(name).unwrap();
        assert_eq!(fingerprint(&json), fingerprint(&toml), "{name}");
    }
}

#[test]
fn every_light_type_and_the_orthographic_camera() {
    let text = r#"
[camera]
type = "orthographic"
eye = [0, 0, 5]
look_at = [0, 0, 0]
height = 4

[[lights]]
type = "directional"
direction = [0, -2, 0]
irradiance = [1, 2, 3]

[[lights]]
type = "spot"
position = [0, 5, 0]
look_at = [0, 0, 0]
inner_angle = 20
outer_angle = 30
intensity = 7

[[lights]]
type = "sphere"
center = [1, 4, 1]
radius = 0.5
radiance = 3
samples = 4
"#;
    let s = load_str(text, SceneSyntax::Toml, Path::new("l.toml")).unwrap();
    assert_eq!(
        s.camera.projection,
        Projection::Orthographic { height: 4.0 }
    );
    match s.lights[0] {
        Light::Directional {
            direction,
            irradiance,
        } => {
            assert_eq!(direction, -Vec3::Y);
            assert_eq!(irradiance, irradia_core::Rgb::new(1.0, 2.0, 3.0));
        }
        ref l => panic!("{l:?}"),
    }
    match s.lights[1] {
        Light::Spot {
            direction,
            cos_inner,
            cos_outer,
            ..
        } => {
            assert_eq!(direction, -Vec3::Y);
            assert!((cos_inner - 20f32.to_radians().cos()).abs() < 1e-6);
            assert!((cos_outer - 30f32.to_radians().cos()).abs() < 1e-6);
        }
        ref l => panic!("{l:?}"),
    }
    assert!(matches!(s.lights[2], Light::Sphere { radius, samples: 4, .. } if radius == 0.5));
}

#[test]
fn image_texture_loads_relative_to_the_scene() {
    let dir = tempfile::tempdir().unwrap();
    // A 2x1 image: red on the left, blue on the right (PFM keeps the values exact).
    let img = irradia_core::Image::from_pixels(
        2,
        1,
        vec![
            irradia_core::Rgb::new(1.0, 0.0, 0.0),
            irradia_core::Rgb::new(0.0, 0.0, 1.0),
        ],
    );
    std::fs::create_dir(dir.path().join("tex")).unwrap();
    irradia_core::io::save(&img, &dir.path().join("tex/two.pfm")).unwrap();
    let scene = dir.path().join("s.toml");
    std::fs::write(
        &scene,
        "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n[materials.t]\ncolor = { type = \"image\", path = \"tex/two.pfm\" }\n",
    )
    .unwrap();
    let s = load_file(&scene).unwrap_or_else(|e| panic!("{e}"));
    let tex = &s.materials[0].color;
    let left = tex.eval(Vec3::ZERO, glam::Vec2::new(0.25, 0.5));
    let right = tex.eval(Vec3::ZERO, glam::Vec2::new(0.75, 0.5));
    assert_eq!(left, irradia_core::Rgb::new(1.0, 0.0, 0.0));
    assert_eq!(right, irradia_core::Rgb::new(0.0, 0.0, 1.0));
}
