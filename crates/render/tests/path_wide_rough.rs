//! The wide path kernel against the scalar estimator on glossy scenes: Mitsuba's
//! `roughconductor` (GGX, isotropic, visible normals; light samples weighted against
//! BSDF samples) and emissive spheres sampled by their own area sampler. As in
//! tests/path_wide.rs, the same samples (same random streams) give the same values up
//! to rounding, and a kernel with a wrong roughness disagrees on many more samples.

mod path_common;

use path_common::wide::{assert_builds_agree, both_estimates, Variant};

use glam::{Affine3A, Quat, Vec3};
use irradia_core::Rgb;
use irradia_geometry::shapes::Sphere;
use irradia_geometry::Instance;
use irradia_render::path::wide::samples_agreeing;
use irradia_render::path::PathParams;
use irradia_scene::bsdf::{BsdfDesc, Conductor, Diffuse, Distribution, Microfacet, Roughness};
use irradia_scene::texture::FloatTexture;
use irradia_scene::{Material, Object, Scene, Texture};
use std::sync::Arc;

/// Mitsuba's `roughconductor` of aluminium's complex index with GGX roughness `alpha`
/// (`sample_visible`, Mitsuba's default) and `specular_reflectance` `tint`.
fn rough_aluminium(name: &str, alpha: f32, tint: Rgb) -> Material {
    Material::from_bsdf(
        name,
        BsdfDesc::RoughConductor(
            Conductor {
                material: None,
                eta: Rgb::new(1.6574, 0.8803, 0.5212).into(),
                k: Rgb::new(9.2238, 6.2695, 4.837).into(),
                specular_reflectance: tint.into(),
            },
            Microfacet {
                distribution: Distribution::Ggx,
                alpha: Roughness::Isotropic(FloatTexture::Value(alpha)),
                sample_visible: true,
            },
        ),
    )
}

/// What glows in a [`glossy_box`].
#[derive(Clone, Copy, Debug, PartialEq)]
enum Lights {
    /// The box's ceiling light (a rectangle: facet emitter).
    Ceiling,
    /// The ceiling light and three emissive analytic spheres: one untransformed and one
    /// a unit sphere placed by a scale, a rotation and a translation, sampled by the
    /// cones they subtend, and one stretched into an ellipsoid, sampled by area.
    CeilingAndSpheres,
}

/// The Cornell box with Mitsuba's one-sided `diffuse`, its red and green walls and its
/// tall box made rough aluminium (GGX α `alphas[0..3]`, tinted by the walls' colours),
/// an analytic sphere of rough aluminium (α `alphas[3]`) and the given lights.
fn glossy_box(width: u32, height: u32, alphas: [f32; 4], lights: Lights) -> Scene {
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
                "red" => rough_aluminium("red", alphas[0], color),
                "green" => rough_aluminium("green", alphas[1], color),
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
    let instances_base = scene.accel.instances().to_vec();
    materials.push(rough_aluminium("tall", alphas[2], Rgb::WHITE));
    let tall = materials.len() as u32 - 1;
    for o in &mut objects {
        if o.name == "tall box" {
            o.material = tall;
        }
    }
    materials.push(rough_aluminium("ball", alphas[3], Rgb::new(0.9, 0.8, 1.0)));
    let mut instances = instances_base;
    objects.push(path_common::object("ball", materials.len() as u32 - 1));
    instances.push(Instance::untransformed(Arc::new(Sphere::new(
        Vec3::new(0.45, -0.55, 0.35),
        0.3,
    ))));
    if lights == Lights::CeilingAndSpheres {
        let mut glow = |name: &str, e: Rgb, instance: Instance| {
            let mut m = Material::from_bsdf(
                name,
                BsdfDesc::Diffuse(Diffuse {
                    reflectance: Rgb::splat(0.5).into(),
                }),
            );
            m.emission = e;
            materials.push(m);
            objects.push(Object {
                name: name.into(),
                material: materials.len() as u32 - 1,
                leaf_materials: vec![],
            });
            instances.push(instance);
        };
        glow(
            "small glow",
            Rgb::new(40.0, 24.0, 20.0),
            Instance::untransformed(Arc::new(Sphere::new(Vec3::new(-0.6, 0.5, -0.4), 0.08))),
        );
        glow(
            "large glow",
            Rgb::new(2.0, 3.0, 4.0),
            Instance::new(
                Arc::new(Sphere::new(Vec3::ZERO, 1.0)),
                Affine3A::from_scale_rotation_translation(
                    Vec3::splat(0.2),
                    Quat::from_rotation_z(0.4),
                    Vec3::new(0.5, 0.4, -0.5),
                ),
            ),
        );
        glow(
            "stretched glow",
            Rgb::new(6.0, 5.0, 3.0),
            Instance::new(
                Arc::new(Sphere::new(Vec3::ZERO, 1.0)),
                Affine3A::from_scale_rotation_translation(
                    Vec3::new(0.06, 0.12, 0.06),
                    Quat::from_rotation_x(0.3),
                    Vec3::new(0.1, 0.7, 0.3),
                ),
            ),
        );
    }
    Scene::new(
        scene.camera,
        scene.settings.clone(),
        materials,
        scene.lights.clone(),
        objects,
        instances,
    )
}

/// Least fraction of agreeing samples (every sample agreed but a few hundredths of a
/// percent, 2026-12-03: a direction that differs in its last bits meets a light's or a
/// box's edge).
const AGREE: f64 = 0.999;

/// The speed suite's plates' roughnesses (veach_mis) and a rougher ball.
const PLATES: [f32; 4] = [0.005, 0.02, 0.1, 0.3];

#[test]
fn rough_conductor_samples_equal_scalar_samples_up_to_rounding() {
    for (name, scene, variant) in [
        (
            "rough walls",
            glossy_box(32, 32, PLATES, Lights::Ceiling),
            Variant::Default,
        ),
        (
            "rougher walls",
            glossy_box(32, 32, [0.05, 0.2, 0.5, 0.8], Lights::Ceiling),
            Variant::Default,
        ),
        (
            "rough walls, lane by lane",
            glossy_box(24, 24, PLATES, Lights::Ceiling),
            Variant::LaneByLane,
        ),
        (
            "rough walls, portable",
            glossy_box(24, 24, PLATES, Lights::Ceiling),
            Variant::Portable,
        ),
        // Emissive spheres among the lights: sampled by their cones (one placed by a
        // transform) or by area (an ellipsoid), seen directly and in the plates with
        // MIS.
        (
            "rough walls, sphere lights",
            glossy_box(32, 32, PLATES, Lights::CeilingAndSpheres),
            Variant::Default,
        ),
        (
            "rough walls, sphere lights, lane by lane",
            glossy_box(24, 24, PLATES, Lights::CeilingAndSpheres),
            Variant::LaneByLane,
        ),
        (
            "rough walls, sphere lights, portable",
            glossy_box(24, 24, PLATES, Lights::CeilingAndSpheres),
            Variant::Portable,
        ),
    ] {
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

/// A roughness 1% off (the plates' α times 1.01) changes enough samples to fail the
/// agreement the cases above hold.
#[test]
fn a_wrong_roughness_is_caught() {
    let scene = glossy_box(32, 32, PLATES, Lights::Ceiling);
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

/// The AVX-512 build of the kernel gives the AVX2 build's samples bit for bit (rough conductors and sphere lights: the Fresnel reflectance's `f64` lanes);
/// on a CPU without AVX-512 there is nothing to compare. (Fails when one build's
/// Fresnel reflectance is 1% off: tried.)
#[test]
fn the_avx512_build_equals_the_avx2_build_bit_for_bit() {
    let scene = glossy_box(24, 24, PLATES, Lights::CeilingAndSpheres);
    let n = assert_builds_agree("rough walls, sphere lights", &scene, 4);
    println!("builds compared with AVX2: {n}");
}
