//! Physically based materials: every example of docs/scene-format.md loads; Mitsuba's
//! defaults and names arrive in the description; nested materials resolve; the lecture
//! fields follow the documented rule; lecture materials are untouched.

use irradia_core::Rgb;
use irradia_scene::bsdf::lecture::phong_exponent;
use irradia_scene::bsdf::{BsdfDesc, Distribution, PrincipledSpecular, Roughness};
use irradia_scene::texture::{ColorTexture, FloatTexture, TextureMap};
use irradia_scene::{load_file, Material, Scene, Texture};
use std::path::Path;

const HEAD: &str = r#"[camera]
eye = [0, 0, 5]
look_at = [0, 0, 0]

[image]
width = 8
height = 8

[[objects]]
type = "sphere"
radius = 1
"#;

/// Loads `materials` (TOML) after a minimal scene, in a folder where every
/// `filename = "x.png"` it names exists (a copy of the 4 x 2 test image).
fn load(materials: &str) -> Scene {
    let dir = tempfile::tempdir().unwrap();
    let png = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/textures/rgb4x2.png");
    for part in materials.split("filename = \"").skip(1) {
        let name = &part[..part.find('"').unwrap()];
        std::fs::copy(&png, dir.path().join(name)).unwrap();
    }
    let path = dir.path().join("s.toml");
    std::fs::write(&path, format!("{HEAD}\n{materials}")).unwrap();
    load_file(&path).unwrap_or_else(|e| panic!("{e}\n{materials}"))
}

fn material<'a>(s: &'a Scene, name: &str) -> &'a Material {
    s.materials.iter().find(|m| m.name == name).unwrap()
}

fn bsdf<'a>(s: &'a Scene, name: &str) -> &'a BsdfDesc {
    material(s, name)
        .bsdf
        .as_deref()
        .expect("a physically based material")
}

/// The fenced TOML blocks of the physically based section of docs/scene-format.md.
fn doc_examples() -> Vec<String> {
    let doc = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/scene-format.md"),
    )
    .unwrap();
    let start = doc.find("### Physically based materials").unwrap();
    let end = start + doc[start..].find("\n## ").unwrap();
    doc[start..end]
        .split("```toml\n")
        .skip(1)
        .map(|b| b[..b.find("```").unwrap()].to_string())
        .collect()
}

#[test]
fn every_documented_example_loads() {
    let examples = doc_examples();
    assert!(examples.len() >= 5, "found {} examples", examples.len());
    let mut types = std::collections::BTreeSet::new();
    for ex in &examples {
        let s = load(ex);
        for m in &s.materials {
            if m.name != "default" {
                let b = m
                    .bsdf
                    .as_deref()
                    .unwrap_or_else(|| panic!("{} has no bsdf", m.name));
                types.insert(b.type_name());
            }
        }
    }
    // Every BSDF type is shown at top level somewhere in the docs.
    for t in irradia_scene::bsdf::BSDF_TYPES {
        assert!(types.contains(t), "no documented example of {t}");
    }
}

#[test]
fn defaults_and_names_are_mitsubas() {
    let s = load(
        r#"
[materials.glass]
type = "dielectric"

[materials.water]
type = "dielectric"
int_ior = "water"
ext_ior = 1.0

[materials.gold]
type = "roughconductor"
material = "Au"
distribution = "ggx"
alpha = 0.1

[materials.mirror]
type = "conductor"

[materials.p]
type = "principled"
"#,
    );
    let BsdfDesc::Dielectric(d) = bsdf(&s, "glass") else {
        panic!()
    };
    // Mitsuba 3.9.1: traverse(load_dict({'type': 'dielectric'}))['eta'] = 1.5041833.
    assert!((d.eta() - 1.504_183_3).abs() < 1e-6, "{}", d.eta());
    let BsdfDesc::Dielectric(w) = bsdf(&s, "water") else {
        panic!()
    };
    assert!((w.int_ior - 1.333).abs() < 1e-3, "{}", w.int_ior);
    let BsdfDesc::RoughConductor(c, m) = bsdf(&s, "gold") else {
        panic!()
    };
    assert_eq!(m.distribution, Distribution::Ggx);
    assert_eq!(m.alpha, Roughness::Isotropic(FloatTexture::Value(0.1)));
    assert!(m.sample_visible);
    assert_eq!(c.material.as_deref(), Some("Au"));
    // Mitsuba 3.9.1, conductor material "Au": eta [0.143036, 0.375307, 1.44205],
    // k [3.983, 2.38556, 1.60336].
    let ColorTexture::Value(eta) = c.eta else {
        panic!()
    };
    let ColorTexture::Value(k) = c.k else {
        panic!()
    };
    assert!(
        (eta.r - 0.143).abs() < 0.01 && (eta.b - 1.442).abs() < 0.01,
        "{eta:?}"
    );
    assert!(
        (k.r - 3.983).abs() < 0.01 && (k.b - 1.603).abs() < 0.01,
        "{k:?}"
    );
    let BsdfDesc::Conductor(mirror) = bsdf(&s, "mirror") else {
        panic!()
    };
    assert_eq!(mirror.eta, ColorTexture::Value(Rgb::BLACK));
    assert_eq!(mirror.k, ColorTexture::Value(Rgb::WHITE));
    let BsdfDesc::Principled(p) = bsdf(&s, "p") else {
        panic!()
    };
    assert_eq!(p.specular, PrincipledSpecular::Specular(0.5));
    assert_eq!(p.roughness, FloatTexture::Value(0.5));
}

#[test]
fn nested_materials_resolve_by_name_in_any_order() {
    let s = load(
        r#"
[materials.mix]
type = "blendbsdf"
weight = 0.25
bsdfs = ["later", { type = "diffuse", reflectance = 0.2 }]

[materials.later]
type = "mask"
opacity = 0.6
bsdf = { type = "conductor" }
"#,
    );
    let BsdfDesc::Blend { weight, bsdfs } = bsdf(&s, "mix") else {
        panic!()
    };
    assert_eq!(*weight, FloatTexture::Value(0.25));
    assert_eq!(&bsdfs[0], bsdf(&s, "later"));
    assert!(matches!(bsdfs[1], BsdfDesc::Diffuse(_)));
    assert_eq!(s.materials.len(), 3, "mix, later, default");
}

#[test]
fn spectra_and_textures_arrive_as_written() {
    let s = load(
        r#"
[materials.rose]
type = "diffuse"
reflectance = "400:0.1, 500:0.2, 600:0.3, 700:0.4"

[materials.floor]
type = "diffuse"
reflectance = { type = "bitmap", filename = "wood.png", filter_type = "nearest", to_uv = [{ scale = [2, 3] }] }

[materials.rough]
type = "roughdielectric"
alpha_u = { type = "checkerboard", color0 = 0.1, color1 = 0.3 }
alpha_v = 0.2
"#,
    );
    let BsdfDesc::Diffuse(d) = bsdf(&s, "rose") else {
        panic!()
    };
    let ColorTexture::Value(c) = d.reflectance else {
        panic!()
    };
    // Mitsuba 3.9.1 scalar_rgb gives [0.340779, 0.242912, 0.140304].
    assert!(
        (c.r - 0.340779).abs() < 2e-5 && (c.b - 0.140304).abs() < 2e-5,
        "{c:?}"
    );
    let BsdfDesc::Diffuse(f) = bsdf(&s, "floor") else {
        panic!()
    };
    let ColorTexture::Map(TextureMap::Bitmap(b)) = &f.reflectance else {
        panic!()
    };
    assert_eq!((b.texels.width, b.texels.height), (4, 2));
    // The lecture colour is the same image, rows flipped (the lecture's v runs up).
    let Texture::Image { image, scale } = &material(&s, "floor").color else {
        panic!()
    };
    assert_eq!(*scale, glam::Vec2::new(2.0, 3.0));
    for (u, v) in [(0.1, 0.1), (0.6, 0.3), (0.9, 0.45)] {
        let uv = glam::Vec2::new(u, v);
        assert_eq!(
            irradia_scene::image_texel(image, uv * *scale),
            b.eval(uv),
            "at {uv}"
        );
    }
    let BsdfDesc::RoughDielectric(_, m) = bsdf(&s, "rough") else {
        panic!()
    };
    assert!(matches!(m.alpha, Roughness::Anisotropic { .. }));
}

#[test]
fn lecture_fields_follow_the_documented_rule() {
    let s = load(
        r#"
[materials.white]
type = "diffuse"
reflectance = [0.2, 0.4, 0.6]

[materials.metal]
type = "conductor"
eta = 2
k = 1

[materials.satin]
type = "roughconductor"
eta = 2
k = 1
alpha = 0.5

[materials.glass]
type = "dielectric"
int_ior = 1.5
ext_ior = 1
specular_transmittance = [0.9, 1, 1]

[materials.coat]
type = "plastic"
diffuse_reflectance = 0.3
int_ior = 1.5
ext_ior = 1

[materials.half]
type = "blendbsdf"
weight = 0.5
bsdfs = ["white", "metal"]
"#,
    );
    let w = material(&s, "white");
    assert!(matches!(w.color, Texture::Solid(c) if c == Rgb::new(0.2, 0.4, 0.6)));
    assert_eq!(
        (w.diffuse, w.specular, w.reflection),
        (1.0, 0.0, Rgb::BLACK)
    );
    // F0 = ((2-1)² + 1) / ((2+1)² + 1) = 0.2.
    let m = material(&s, "metal");
    assert!(
        (m.reflection.r - 0.2).abs() < 1e-6 && m.diffuse == 0.0,
        "{:?}",
        m.reflection
    );
    let r = material(&s, "satin");
    assert_eq!(r.reflection, Rgb::BLACK);
    assert!((r.specular - 0.2).abs() < 1e-6);
    assert_eq!(r.shininess, 6.0, "2/0.25 - 2");
    assert_eq!(phong_exponent(0.5), 6.0);
    let g = material(&s, "glass");
    assert_eq!((g.transmission, g.ior, g.fresnel), (1.0, 1.5, true));
    assert_eq!(g.filter_color, Some(Rgb::new(0.9, 1.0, 1.0)));
    let c = material(&s, "coat");
    assert_eq!(
        (c.diffuse, c.reflection, c.fresnel, c.ior),
        (1.0, Rgb::WHITE, true, 1.5)
    );
    let h = material(&s, "half");
    assert!((h.diffuse - 0.5).abs() < 1e-6 && (h.reflection.g - 0.1).abs() < 1e-6);
    assert_eq!(h.ambient, Material::default().ambient);
}

#[test]
fn lecture_materials_are_unchanged() {
    let s = load("[materials.red]\ncolor = [0.9, 0.1, 0.1]\nspecular = 0.5\n");
    let m = material(&s, "red");
    assert!(m.bsdf.is_none());
    assert_eq!((m.diffuse, m.specular, m.shininess), (0.8, 0.5, 20.0));
}
