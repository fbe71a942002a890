//! The wide path kernel against the scalar estimator on Mitsuba's `roughdielectric`
//! and `roughplastic` (GGX, isotropic, visible normals; glossy lobes: light samples on
//! either side of the rough glass weighted against BSDF samples, Russian roulette
//! judging `max(beta) η²` inside it). As in tests/path_wide_rough.rs, the same samples
//! (same random streams) give the same values up to rounding, and a kernel with a
//! wrong roughness disagrees on many more samples.

mod path_common;

use path_common::wide::{assert_builds_agree, both_estimates, Variant};

use glam::Vec3;
use irradia_core::Rgb;
use irradia_geometry::shapes::Sphere;
use irradia_geometry::Instance;
use irradia_render::path::wide::samples_agreeing;
use irradia_render::path::PathParams;
use irradia_scene::bsdf::{
    BsdfDesc, Dielectric, Diffuse, Distribution, Microfacet, Plastic, PlasticRoughness, Roughness,
};
use irradia_scene::texture::FloatTexture;
use irradia_scene::{Material, Scene, Texture};
use std::sync::Arc;

/// A rough glass and a rough plastic in the box.
#[derive(Clone, Copy, Debug)]
struct Layers {
    /// The glass ball's GGX α and `int_ior / ext_ior` (below 1: the ball is the rarer
    /// medium).
    glass_alpha: f32,
    glass_eta: f32,
    /// The plastic's α, `int_ior` (over air), diffuse reflectance and `nonlinear`.
    plastic_alpha: f32,
    plastic_ior: f32,
    plastic_rho: Rgb,
    nonlinear: bool,
}

fn rough_glass(alpha: f32, eta: f32) -> Material {
    Material::from_bsdf(
        "rough glass",
        BsdfDesc::RoughDielectric(
            Dielectric {
                int_ior: eta,
                ext_ior: 1.0,
                specular_reflectance: Rgb::WHITE.into(),
                specular_transmittance: Rgb::new(1.0, 0.95, 0.9).into(),
            },
            Microfacet {
                distribution: Distribution::Ggx,
                alpha: Roughness::Isotropic(FloatTexture::Value(alpha)),
                sample_visible: true,
            },
        ),
    )
}

fn rough_plastic(name: &str, l: &Layers, rho: Rgb) -> Material {
    Material::from_bsdf(
        name,
        BsdfDesc::RoughPlastic(
            Plastic {
                diffuse_reflectance: rho.into(),
                specular_reflectance: Rgb::WHITE.into(),
                int_ior: l.plastic_ior,
                ext_ior: 1.0,
                nonlinear: l.nonlinear,
            },
            PlasticRoughness {
                distribution: Distribution::Ggx,
                alpha: l.plastic_alpha,
                sample_visible: true,
            },
        ),
    )
}

/// The Cornell box with Mitsuba's one-sided `diffuse` walls, its red wall and tall box
/// rough plastic (the red wall's own colour, the tall box `plastic_rho`), a rough
/// glass ball in front and a smaller rough plastic ball.
fn layered_box(width: u32, height: u32, l: Layers) -> Scene {
    let mut scene = irradia_scene::builtin::load("cornell").unwrap();
    scene.settings.width = width;
    scene.settings.height = height;
    let mut materials: Vec<Material> = scene
        .materials
        .iter()
        .map(|m| {
            let color = match &m.color {
                Texture::Solid(c) => *c * m.diffuse,
                other => panic!("the Cornell box is untextured: {other:?}"),
            };
            let mut d = match m.name.as_str() {
                "red" => rough_plastic("red", &l, color),
                _ => Material::from_bsdf(
                    &m.name,
                    BsdfDesc::Diffuse(Diffuse {
                        reflectance: color.into(),
                    }),
                ),
            };
            d.emission = m.emission;
            d.emission_two_sided = m.emission_two_sided;
            d
        })
        .collect();
    let mut objects = scene.objects.clone();
    let mut instances = scene.accel.instances().to_vec();
    materials.push(rough_plastic("tall", &l, l.plastic_rho));
    let tall = materials.len() as u32 - 1;
    for o in &mut objects {
        if o.name == "tall box" {
            o.material = tall;
        }
    }
    materials.push(rough_glass(l.glass_alpha, l.glass_eta));
    objects.push(path_common::object(
        "glass ball",
        materials.len() as u32 - 1,
    ));
    instances.push(Instance::untransformed(Arc::new(Sphere::new(
        Vec3::new(0.3, -0.55, 0.45),
        0.4,
    ))));
    materials.push(rough_plastic("plastic ball", &l, Rgb::new(0.2, 0.5, 0.3)));
    objects.push(path_common::object(
        "plastic ball",
        materials.len() as u32 - 1,
    ));
    instances.push(Instance::untransformed(Arc::new(Sphere::new(
        Vec3::new(-0.5, -0.7, 0.5),
        0.25,
    ))));
    Scene::new(
        scene.camera,
        scene.settings.clone(),
        materials,
        scene.lights.clone(),
        objects,
        instances,
    )
}

/// rough_balls' glass and plastic (BK7-like η, α 0.2 and 0.1, its blue base).
const BALLS: Layers = Layers {
    glass_alpha: 0.2,
    glass_eta: 1.5168,
    plastic_alpha: 0.1,
    plastic_ior: 1.9,
    plastic_rho: Rgb::new(0.1, 0.27, 0.36),
    nonlinear: false,
};

/// Least fraction of agreeing samples (as tests/path_wide_rough.rs).
const AGREE: f64 = 0.999;

#[test]
fn rough_dielectric_and_plastic_samples_equal_scalar_samples_up_to_rounding() {
    let nearly_smooth = Layers {
        glass_alpha: 0.01,
        glass_eta: 1.33,
        plastic_alpha: 0.01,
        plastic_ior: 1.33,
        plastic_rho: Rgb::splat(0.5),
        nonlinear: true,
    };
    let rough = Layers {
        glass_alpha: 0.8,
        glass_eta: 1.7,
        plastic_alpha: 0.8,
        plastic_ior: 1.7,
        plastic_rho: Rgb::new(0.9, 0.2, 0.05),
        nonlinear: false,
    };
    // A ball of the rarer medium (η < 1: total internal reflection from outside).
    let inverted = Layers {
        glass_alpha: 0.3,
        glass_eta: 1.0 / 1.5,
        plastic_alpha: 0.3,
        plastic_ior: 1.5,
        plastic_rho: Rgb::splat(0.8),
        nonlinear: true,
    };
    for (name, layers, size, variant) in [
        ("rough_balls' materials", BALLS, 32, Variant::Default),
        ("nearly smooth", nearly_smooth, 32, Variant::Default),
        ("rough", rough, 32, Variant::Default),
        ("rarer ball", inverted, 32, Variant::Default),
        (
            "rough_balls' materials, lane by lane",
            BALLS,
            24,
            Variant::LaneByLane,
        ),
        (
            "rough_balls' materials, portable",
            BALLS,
            24,
            Variant::Portable,
        ),
        ("rough, portable", rough, 24, Variant::Portable),
    ] {
        let scene = layered_box(size, size, layers);
        let (scalar, wide) = both_estimates(&scene, 2, &PathParams::default(), 0, variant);
        assert!(
            wide.iter().all(|c| c.is_finite()),
            "{name}: unwritten sample"
        );
        let same = samples_agreeing(&scalar, &wide);
        println!("{name}: {:.3}% of samples agree to 1e-4", same * 100.0);
        assert!(same > AGREE, "{name}: only {:.3}% agree", same * 100.0);
        if variant == Variant::Default {
            // The comparison can fail: another stream's samples do not agree.
            let (other, _) = both_estimates(&scene, 2, &PathParams::default(), 7, variant);
            let chance = samples_agreeing(&other, &wide);
            assert!(
                chance < 0.5,
                "{name}: {:.1}% agree by chance",
                chance * 100.0
            );
        }
    }
}

/// A roughness 1% off (the glass's and plastics' α times 1.01) changes enough samples
/// to fail the agreement the cases above hold.
#[test]
fn a_wrong_roughness_of_glass_or_plastic_is_caught() {
    let scene = layered_box(32, 32, BALLS);
    let (scalar, wrong) = both_estimates(
        &scene,
        2,
        &PathParams::default(),
        0,
        Variant::WrongAlpha(1.01),
    );
    let same = samples_agreeing(&scalar, &wrong);
    println!("α × 1.01: {:.2}% of samples agree", same * 100.0);
    assert!(
        same < AGREE - 0.01,
        "{:.2}% agree with a wrong α",
        same * 100.0
    );
}

/// GGX glass and plastic with visible-normal sampling qualify; Beckmann ones, or ones
/// sampling all normals, render with the scalar estimator.
#[test]
fn only_ggx_visible_normal_glass_and_plastic_qualify() {
    use irradia_render::path::flat_scene::FlatScene;
    use irradia_render::path::integrator::PathScene;
    use irradia_render::path::lights::LightSampler;
    use irradia_render::path::wide::WideScene;
    let check = |scene: &Scene| {
        let lights = LightSampler::new(scene);
        let ps = PathScene::new(scene, FlatScene::new(scene), &lights);
        WideScene::new(&ps).is_some()
    };
    assert!(check(&layered_box(8, 8, BALLS)));
    let with = |f: &dyn Fn(&mut BsdfDesc)| {
        let scene = layered_box(8, 8, BALLS);
        let mut materials = scene.materials.clone();
        for m in &mut materials {
            if let Some(b) = m.bsdf.as_mut() {
                f(Arc::make_mut(b));
            }
        }
        Scene::new(
            scene.camera,
            scene.settings.clone(),
            materials,
            scene.lights.clone(),
            scene.objects.clone(),
            scene.accel.instances().to_vec(),
        )
    };
    assert!(!check(&with(&|b| {
        if let BsdfDesc::RoughPlastic(_, r) = b {
            r.distribution = Distribution::Beckmann;
        }
    })));
    assert!(!check(&with(&|b| {
        if let BsdfDesc::RoughDielectric(_, m) = b {
            m.sample_visible = false;
        }
    })));
}

/// The AVX-512 build of the kernel gives the AVX2 build's samples bit for bit (rough_balls' plastic, dielectric and conductor);
/// on a CPU without AVX-512 there is nothing to compare. (Fails when one build's
/// Fresnel reflectance is 1% off: tried.)
#[test]
fn the_avx512_build_equals_the_avx2_build_bit_for_bit() {
    let scene = layered_box(24, 24, BALLS);
    let n = assert_builds_agree("rough_balls' materials", &scene, 4);
    println!("builds compared with AVX2: {n}");
}
