//! The wide path kernel with emitters at infinity (the constant environment:
//! background and Mitsuba's `constant`; Mitsuba's `envmap`) against the scalar
//! estimator: the same samples (same random streams) agree to 1e-4 (escaped rays with
//! MIS, light samples towards the environment with unbounded shadow rays), another
//! stream's do not, and a kernel that scales the environment's radiance by 2% is caught.

mod path_common;

use path_common::wide::{assert_builds_agree, both_estimates_counted, Variant};

use glam::{Mat3, Vec3};
use irradia_core::{Image, Rgb};
use irradia_geometry::shapes::{Cuboid, Sphere};
use irradia_geometry::Instance;
use irradia_render::path::flat_scene::FlatScene;
use irradia_render::path::integrator::PathScene;
use irradia_render::path::lights::LightSampler;
use irradia_render::path::wide::{samples_agreeing, WideScene};
use irradia_render::path::PathParams;
use irradia_scene::bsdf::{BsdfDesc, Diffuse};
use irradia_scene::{EnvMap, Light, Material, Scene};
use std::sync::Arc;

/// What lights the ball-and-floor scene.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Sky {
    /// A uniform background (the settings').
    Background,
    /// Mitsuba's `constant` emitter.
    Constant,
    /// A small environment map with two bright spots (importance sampling matters).
    Envmap,
    /// The map, a `constant` and a glowing box (facet emitter) together: the light
    /// choice picks among facets and both emitters at infinity.
    Mixed,
}

/// A 16 x 8 lat-long map: a dim sky, a warm sun and a blue patch, turned by a rotation.
fn envmap() -> Arc<EnvMap> {
    let mut image = Image::filled(16, 8, Rgb::new(0.3, 0.35, 0.4)).unwrap();
    for y in 0..8 {
        for x in 0..16 {
            let c = Rgb::new(0.2 + 0.05 * x as f32, 0.3, 0.2 + 0.1 * y as f32);
            image.set(x, y, c);
        }
    }
    image.set(4, 2, Rgb::new(40.0, 30.0, 12.0));
    image.set(5, 2, Rgb::new(20.0, 15.0, 6.0));
    image.set(12, 5, Rgb::new(1.0, 4.0, 9.0));
    Arc::new(EnvMap {
        image: Arc::new(image),
        scale: 0.8,
        to_world: Mat3::from_rotation_y(0.7) * Mat3::from_rotation_x(-0.2),
        path: Default::default(),
    })
}

/// A diffuse floor (a flat box, baked into triangles), an analytic diffuse ball on it
/// (Mitsuba's one-sided `diffuse`, or the lecture's Lambert) and a smaller ball placed
/// by a transform, under `sky`.
fn ball_on_floor(w: u32, h: u32, sky: Sky, lecture: bool) -> Scene {
    let background = if sky == Sky::Background {
        Rgb::new(0.6, 0.7, 0.9)
    } else {
        Rgb::BLACK
    };
    let mut settings = path_common::settings(w, h, 8, background);
    settings.spp = 2;
    let one_sided = |c: Rgb| {
        Material::from_bsdf(
            "diffuse",
            BsdfDesc::Diffuse(Diffuse {
                reflectance: c.into(),
            }),
        )
    };
    let ball_material = if lecture {
        path_common::diffuse(0.7, 0.0)
    } else {
        one_sided(Rgb::new(0.8, 0.5, 0.3))
    };
    let mut materials = vec![one_sided(Rgb::splat(0.6)), ball_material];
    let floor = Cuboid::new(Vec3::new(-3.0, -1.1, -3.0), Vec3::new(3.0, -1.0, 3.0)).unwrap();
    let mut objects = vec![
        path_common::object("floor", 0),
        path_common::object("ball", 1),
    ];
    let mut instances = vec![
        Instance::untransformed(Arc::new(floor)),
        Instance::untransformed(Arc::new(Sphere::new(Vec3::new(0.0, 0.0, 0.0), 1.0))),
        Instance::new(
            Arc::new(Sphere::new(Vec3::ZERO, 1.0)),
            glam::Affine3A::from_scale_rotation_translation(
                Vec3::splat(0.4),
                glam::Quat::from_rotation_y(0.3),
                Vec3::new(1.5, -0.6, 0.8),
            ),
        ),
    ];
    objects.push(path_common::object("small ball", 0));
    let mut lights = Vec::new();
    match sky {
        Sky::Background => {}
        Sky::Constant => lights.push(Light::Constant {
            radiance: Rgb::new(0.5, 0.6, 0.8),
        }),
        Sky::Envmap => lights.push(Light::Envmap(envmap())),
        Sky::Mixed => {
            lights.push(Light::Envmap(envmap()));
            lights.push(Light::Constant {
                radiance: Rgb::new(0.1, 0.1, 0.15),
            });
            materials.push(path_common::diffuse(0.0, 6.0));
            objects.push(path_common::object("lamp", 2));
            let lamp = Cuboid::new(Vec3::new(-2.0, 1.5, -1.0), Vec3::new(-1.5, 1.7, -0.5));
            instances.push(Instance::untransformed(Arc::new(lamp.unwrap())));
        }
    }
    Scene::new(
        path_common::camera(Vec3::new(0.5, 1.0, 5.0), Vec3::new(0.0, -0.3, 0.0), 50.0),
        settings,
        materials,
        lights,
        objects,
        instances,
    )
}

/// Every pixel's `spp` samples by the scalar estimator (stream family `scalar_seed`)
/// and by the wide kernel (family 0); with the scalar samples' own streams, the same
/// number of shadow rays.
fn both_estimates(
    scene: &Scene,
    spp: u32,
    scalar_seed: u32,
    variant: Variant,
) -> (Vec<Rgb>, Vec<Rgb>) {
    let params = PathParams::default();
    let (scalar, out, c, cw) = both_estimates_counted(scene, spp, &params, scalar_seed, variant);
    if scalar_seed == 0 {
        assert_eq!(cw.shadow_rays, c.shadow_rays, "shadow rays");
    }
    (scalar, out)
}

/// The least fraction of samples that must agree (all did when written).
const AGREE: f64 = 0.999;

#[test]
fn wide_samples_under_emitters_at_infinity_equal_scalar_samples() {
    for (sky, lecture, variant) in [
        (Sky::Background, false, Variant::Default),
        (Sky::Background, true, Variant::Default),
        (Sky::Constant, false, Variant::Default),
        (Sky::Constant, true, Variant::Portable),
        (Sky::Envmap, false, Variant::Default),
        (Sky::Envmap, true, Variant::Default),
        (Sky::Envmap, false, Variant::Portable),
        (Sky::Envmap, false, Variant::LaneByLane),
        (Sky::Mixed, false, Variant::Default),
        (Sky::Mixed, true, Variant::LaneByLane),
    ] {
        let name = format!("{sky:?}, lecture Lambert {lecture}, {variant:?}");
        let scene = ball_on_floor(32, 24, sky, lecture);
        let (scalar, wide) = both_estimates(&scene, 2, 0, variant);
        assert!(wide.iter().all(|c| c.is_finite()), "{name}: unwritten");
        let same = samples_agreeing(&scalar, &wide);
        println!("{name}: {:.3}% agree", same * 100.0);
        assert!(same >= AGREE, "{name}: only {:.3}% agree", same * 100.0);
        // Most samples see light (the comparison is not of zeros).
        let lit = scalar.iter().filter(|c| c.mean() > 1e-3).count();
        assert!(lit * 10 > scalar.len() * 9, "{name}: {lit} lit samples");
        if variant == Variant::Default {
            let (other, _) = both_estimates(&scene, 2, 7, variant);
            let chance = samples_agreeing(&other, &wide);
            assert!(chance < 0.5, "{name}: {:.1}% by chance", chance * 100.0);
        }
    }
    // Nothing baked: a lone white ball (albedo 1, long paths) under a background.
    let scene = path_common::white_sphere_in_environment(0.7);
    for variant in [Variant::Default, Variant::Portable] {
        let (scalar, wide) = both_estimates(&scene, 2, 0, variant);
        let same = samples_agreeing(&scalar, &wide);
        println!("lone ball, {variant:?}: {:.3}% agree", same * 100.0);
        assert!(same >= AGREE, "lone ball: only {:.3}% agree", same * 100.0);
    }
}

/// The spheres' lane cull changes no sample (bit for bit): it only spares the exact
/// test the lanes that cannot hit a sphere. (Without the cull the kernel does not
/// finish escaping camera rays ahead either (`wide::escapes`), so this also shows that
/// finishing them ahead changes no sample.)
#[test]
fn the_sphere_cull_changes_no_sample() {
    for sky in [Sky::Background, Sky::Envmap] {
        let scene = ball_on_floor(32, 24, sky, false);
        let (_, culled) = both_estimates(&scene, 2, 0, Variant::Default);
        let (_, exact) = both_estimates(&scene, 2, 0, Variant::NoSphereCull);
        assert_eq!(culled, exact, "{sky:?}");
    }
}

/// The comparison catches a kernel whose environment is 2% too bright (or dark).
#[test]
fn a_wrong_environment_radiance_is_caught() {
    for sky in [Sky::Constant, Sky::Envmap] {
        let scene = ball_on_floor(32, 24, sky, false);
        for scale in [1.02, 0.98] {
            let (scalar, wrong) = both_estimates(&scene, 2, 0, Variant::WrongBackground(scale));
            let same = samples_agreeing(&scalar, &wrong);
            println!("{sky:?} x {scale}: {:.2}% agree", same * 100.0);
            assert!(same < 0.5, "{sky:?} x {scale}: {:.2}% agree", same * 100.0);
        }
    }
}

/// Scenes with emitters at infinity qualify; other lights still do not.
#[test]
fn environments_qualify_other_lights_do_not() {
    let check = |scene: &Scene| {
        let lights = LightSampler::new(scene);
        let ps = PathScene::new(scene, FlatScene::new(scene), &lights);
        WideScene::new(&ps).is_some()
    };
    for sky in [Sky::Background, Sky::Constant, Sky::Envmap, Sky::Mixed] {
        assert!(check(&ball_on_floor(8, 8, sky, false)), "{sky:?}");
    }
    assert!(check(&path_common::white_sphere_in_environment(0.7)));
    let mut with_point = ball_on_floor(8, 8, Sky::Envmap, false);
    with_point.lights.push(Light::Point {
        position: Vec3::new(0.0, 3.0, 0.0),
        intensity: Rgb::splat(5.0),
    });
    let with_point = Scene::new(
        with_point.camera,
        with_point.settings.clone(),
        with_point.materials.clone(),
        with_point.lights.clone(),
        with_point.objects.clone(),
        with_point.accel.instances().to_vec(),
    );
    assert!(!check(&with_point));
}

/// The AVX-512 build of the kernel gives the AVX2 build's samples bit for bit (an environment map's lookups and samples);
/// on a CPU without AVX-512 there is nothing to compare. (Fails when one build's
/// Fresnel reflectance is 1% off: tried.)
#[test]
fn the_avx512_build_equals_the_avx2_build_bit_for_bit() {
    let scene = ball_on_floor(32, 24, Sky::Mixed, false);
    let n = assert_builds_agree("ball under mixed skies", &scene, 4);
    println!("builds compared with AVX2: {n}");
}
