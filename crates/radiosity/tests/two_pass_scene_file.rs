//! Two-pass scenes from scene files (`two_pass_scene::from_scene`): materials become
//! mirrors, glass or diffuse surfaces by the documented rule, and the example scene
//! file docs/examples/two-pass.toml (the built-in `cornell-specular` written as a file,
//! its mirror sphere placed by a transform) gives the built-in's two-pass image.

use glam::DVec3;
use irradia_core::Rgb;
use irradia_radiosity::display::View;
use irradia_radiosity::formfactor::{Method, Params};
use irradia_radiosity::mesh::MeshOptions;
use irradia_radiosity::pipeline::{self, Config, NoProgress};
use irradia_radiosity::two_pass::{TwoPass, TwoPassOptions};
use irradia_radiosity::two_pass_scene::{
    self, from_scene, specular_material, SpecularMaterial, SpecularScene, STAND_IN_DETAIL,
};
use irradia_radiosity::PatchSpec;
use irradia_scene::{Material, Texture};
use std::path::Path;

fn example() -> irradia_scene::Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/examples/two-pass.toml");
    irradia_scene::load_file(&path).expect("docs/examples/two-pass.toml loads")
}

/// Solves the scene's patches (hemicube, coarse) and renders its two-pass image with
/// one ray through each pixel centre.
fn two_pass_image(scene: &SpecularScene, view: &View) -> irradia_core::Image {
    let cfg = Config {
        mesh: MeshOptions {
            max_element_area: Some(120.0 * 120.0),
            ..Default::default()
        },
        method: Method::Hemicube,
        params: Params {
            hemicube_resolution: 32,
            ..Default::default()
        },
        ..Default::default()
    };
    let report = pipeline::run(&scene.patches, &cfg, &NoProgress).unwrap();
    let dm = report.display_mesh();
    let keep = |p: u32| !scene.is_stand_in(report.mesh.patches[p as usize].source);
    let tracer = TwoPass::new(&dm, keep, &scene.objects).unwrap();
    let opts = TwoPassOptions {
        samples_per_axis: 1,
        ..Default::default()
    };
    tracer.render(view, &opts).unwrap()
}

/// The built-in `cornell-specular` with its red wall (0.8 mm off planar) split into the
/// two triangles the scene file needs.
fn built_in_with_split_red_wall() -> SpecularScene {
    let mut s = two_pass_scene::cornell_specular();
    let k = s
        .patches
        .iter()
        .position(|p| p.name == "red wall")
        .expect("the built-in has a red wall");
    let wall = s.patches.remove(k);
    let [a, b, c, d] = [0, 1, 2, 3].map(|i| wall.corners[i]);
    for (n, corners) in [("lower", vec![a, b, c]), ("upper", vec![a, c, d])] {
        let t = PatchSpec {
            name: format!("red wall ({n})"),
            corners,
            ..wall.clone()
        };
        s.patches.insert(k + (n == "upper") as usize, t);
    }
    s.first_stand_in += 1;
    s
}

#[test]
fn the_example_file_gives_the_two_pass_image_of_the_built_in() {
    let scene = example();
    let (file, owners, warnings) = from_scene(&scene, STAND_IN_DETAIL).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(owners.len(), file.patches.len());
    let reference = built_in_with_split_red_wall();
    // The same specular objects: the mirror sphere (placed by a transform) and the
    // glass sphere, with the same materials.
    let names: Vec<&str> = file.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["mirror sphere", "glass sphere"]);
    for (f, r) in file.objects.iter().zip(&reference.objects) {
        assert_eq!(f.material, r.material, "{}", f.name);
    }
    // The same patches, in the same order: the walls and the light, then the black
    // stand-in facets of the mirror (the glass is not in the radiosity pass).
    assert_eq!(file.first_stand_in, reference.first_stand_in);
    assert_eq!(file.patches.len(), reference.patches.len());
    for (f, r) in file.patches.iter().zip(&reference.patches) {
        assert_eq!(f.corners.len(), r.corners.len(), "{} / {}", f.name, r.name);
        for (p, q) in f.corners.iter().zip(&r.corners) {
            assert!(p.distance(*q) < 1e-3, "{}: {p} vs {}: {q}", f.name, r.name);
        }
        for c in 0..3 {
            assert!(
                (f.reflectance[c] - r.reflectance[c]).abs() < 1e-6,
                "{}",
                f.name
            );
            assert!((f.emission[c] - r.emission[c]).abs() < 1e-4, "{}", f.name);
        }
    }
    // And the same image: every pixel, including those that see the mirror and the glass.
    let view = View::cornell(64, 48);
    let a = two_pass_image(&file, &view);
    let b = two_pass_image(&reference, &view);
    let brightest = b
        .pixels()
        .iter()
        .map(|p| p.r.max(p.g).max(p.b))
        .fold(0.0f32, f32::max) as f64;
    let diff = |p: &Rgb, q: &Rgb| {
        [(p.r - q.r).abs(), (p.g - q.g).abs(), (p.b - q.b).abs()]
            .into_iter()
            .fold(0.0f32, f32::max) as f64
            / brightest
    };
    let worst = a
        .pixels()
        .iter()
        .zip(b.pixels())
        .map(|(p, q)| diff(p, q))
        .fold(0.0, f64::max);
    println!("scene file vs built-in two-pass image: worst pixel {worst:.2e} of the brightest");
    assert!(worst < 1e-3, "{worst}");
    // The spheres are in the image: the pixel at the mirror sphere's centre differs from
    // the image without specular objects.
    let mut bare = reference.clone();
    bare.objects.clear();
    let c = two_pass_image(&bare, &view);
    let mirror_pixel = pixel_of(&view, DVec3::new(385.0, 100.0, 370.0 - 100.0));
    let (i, j) = mirror_pixel;
    assert!(
        diff(&a.get(i, j), &c.get(i, j)) > 1e-2,
        "mirror not seen at {i}, {j}"
    );
}

/// The pixel whose centre ray passes nearest the point `p`.
fn pixel_of(view: &View, p: DVec3) -> (u32, u32) {
    let want = (p - view.eye).normalize();
    let mut best = (0, 0, f64::MIN);
    for j in 0..view.height {
        for i in 0..view.width {
            let d = view.ray_direction(i as f64 + 0.5, j as f64 + 0.5);
            let c = d.dot(want);
            if c > best.2 {
                best = (i, j, c);
            }
        }
    }
    (best.0, best.1)
}

fn material(f: impl FnOnce(&mut Material)) -> Material {
    let mut m = Material {
        name: "m".into(),
        ..Default::default()
    };
    f(&mut m);
    m
}

#[test]
fn materials_are_mirrors_glass_or_diffuse_by_the_documented_rule() {
    // A perfect mirror: no diffuse part, no notes.
    let (kind, notes) = specular_material(&material(|m| {
        m.diffuse = 0.0;
        m.reflection = Rgb::new(0.9, 0.8, 0.7);
    }));
    assert_eq!(
        kind,
        Some(SpecularMaterial::Mirror {
            reflectance: [0.9f32 as f64, 0.8f32 as f64, 0.7f32 as f64]
        })
    );
    assert!(notes.is_empty(), "{notes:?}");
    // A mirror with a weaker diffuse part (0.8 x 0.1): a mirror, the diffuse part noted.
    let (kind, notes) = specular_material(&material(|m| {
        m.diffuse = 0.1;
        m.reflection = Rgb::splat(0.8);
    }));
    assert!(matches!(kind, Some(SpecularMaterial::Mirror { .. })));
    assert_eq!(notes.len(), 1, "{notes:?}");
    // Shiny plastic, the diffuse part the larger (0.8 x 0.8 > 0.3): diffuse, noted.
    let (kind, notes) = specular_material(&material(|m| m.reflection = Rgb::splat(0.3)));
    assert_eq!(kind, None);
    assert!(
        notes[0].contains("mirror reflection is left out"),
        "{notes:?}"
    );
    // Glass: Fresnel at its ior, refracted rays times transmission x filter.
    let (kind, _) = specular_material(&material(|m| {
        m.diffuse = 0.0;
        m.transmission = 0.5;
        m.ior = 1.33;
        m.filter_color = Some(Rgb::new(1.0, 0.5, 0.25));
    }));
    assert_eq!(
        kind,
        Some(SpecularMaterial::Glass {
            ior: 1.33f32 as f64,
            transmittance: [0.5, 0.25, 0.125]
        })
    );
    // Without a filter colour the base colour filters.
    let (kind, _) = specular_material(&material(|m| {
        m.diffuse = 0.0;
        m.transmission = 1.0;
        m.color = Texture::Solid(Rgb::new(0.5, 1.0, 1.0));
    }));
    assert!(
        matches!(kind, Some(SpecularMaterial::Glass { transmittance, .. }) if transmittance == [0.5, 1.0, 1.0]),
        "{kind:?}"
    );
    // An emitter stays a patch whatever else it does.
    let (kind, notes) = specular_material(&material(|m| {
        m.diffuse = 0.0;
        m.reflection = Rgb::splat(1.0);
        m.emission = Rgb::splat(1.0);
    }));
    assert_eq!(kind, None);
    assert!(notes[0].contains("emits"), "{notes:?}");
    // A plain diffuse material: diffuse, nothing to note.
    let (kind, notes) = specular_material(&Material::default());
    assert_eq!(kind, None);
    assert!(notes.is_empty());
}

#[test]
fn mixed_and_specular_materials_in_a_file_are_reported_and_split() {
    // A closed 1 m box lit by a glowing ceiling, a chrome sphere (mostly mirror, a bit
    // diffuse), a plastic sphere (mostly diffuse, a bit mirror) and a glass box.
    let text = r#"
[camera]
eye = [0.5, 0.5, 0.1]
look_at = [0.5, 0.5, 1]
[materials.wall]
color = 0.5
[materials.lamp]
color = 0.5
emission = 1
[materials.chrome]
diffuse = 0.1
reflection = 0.8
[materials.plastic]
reflection = 0.2
[materials.glass]
diffuse = 0
transmission = 1
ior = 1.5
[[objects]]
type = "box"
min = [-1, -1, -1]
max = [2, 2, 2]
material = "wall"
[[objects]]
type = "polygon"
vertices = [[0.4, 0.99, 0.4], [0.6, 0.99, 0.4], [0.6, 0.99, 0.6], [0.4, 0.99, 0.6]]
material = "lamp"
[[objects]]
name = "chrome ball"
type = "sphere"
center = [0.3, 0.2, 0.5]
radius = 0.1
material = "chrome"
[[objects]]
name = "plastic ball"
type = "sphere"
center = [0.7, 0.2, 0.5]
radius = 0.1
material = "plastic"
[[objects]]
name = "glass block"
type = "box"
min = [0.4, 0, 0.7]
max = [0.6, 0.2, 0.9]
material = "glass"
"#;
    let scene = irradia_scene::load_str(
        text,
        irradia_scene::SceneSyntax::Toml,
        Path::new("mixed.toml"),
    )
    .unwrap();
    let (s, owners, warnings) = from_scene(&scene, 8).unwrap();
    let kinds: Vec<_> = s
        .objects
        .iter()
        .map(|o| (o.name.as_str(), o.material))
        .collect();
    assert_eq!(kinds.len(), 2, "{kinds:?}");
    assert_eq!(kinds[0].0, "chrome ball");
    assert!(matches!(kinds[0].1, SpecularMaterial::Mirror { .. }));
    assert_eq!(kinds[1].0, "glass block");
    assert!(matches!(kinds[1].1, SpecularMaterial::Glass { .. }));
    // Each mixed material is named in a warning.
    assert!(warnings
        .iter()
        .any(|w| w.contains("'chrome ball'") && w.contains("diffuse part")));
    assert!(warnings
        .iter()
        .any(|w| w.contains("'plastic ball'") && w.contains("left out")));
    // Patches: the room, the lamp and the plastic ball are diffuse, the chrome ball's
    // facets are black stand-ins after them, the glass block has none.
    assert!(owners[..s.first_stand_in]
        .iter()
        .all(|&o| o == 0 || o == 1 || o == 3));
    assert!(owners[s.first_stand_in..].iter().all(|&o| o == 2));
    assert!(s.patches[s.first_stand_in..]
        .iter()
        .all(|p| p.reflectance == [0.0; 3] && p.emission == [0.0; 3]));
    assert!(s.first_stand_in < s.patches.len());
    assert!(!owners.contains(&4), "glass has no patches");
}
