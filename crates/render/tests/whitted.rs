//! Analytic and behavioural checks of the Whitted integrator.

mod common;

use common::*;
use glam::Vec3;
use irradia_core::{Ray, Rgb, Rng};
use irradia_render::{render, AovSample, Integrator, RenderOptions, Stats, Whitted};
use irradia_scene::{Light, Material, Scene, Texture};

/// A point light of intensity I at the centre of a diffuse sphere of radius r and
/// diffuse coefficient k (colour c, no ambient) lights every point of the inside with
/// irradiance I / r² at normal incidence, so every pixel seen from inside has radiance
/// k c I / r² (Irradia's Phong convention has no 1/π in the diffuse term).
#[test]
fn point_light_at_the_centre_of_a_diffuse_sphere_gives_k_c_i_over_r2_everywhere() {
    for &(r, i, k, centre) in &[
        (2.0f32, 5.0f32, 0.7f32, Vec3::ZERO),
        (0.25, 0.3, 0.5, Vec3::new(3.0, -1.0, 2.0)),
        (40.0, 2000.0, 0.9, Vec3::new(-100.0, 5.0, 7.0)),
    ] {
        let c = Rgb::new(0.9, 0.5, 0.25);
        let (objects, instances) = spheres(&[(centre, r, 0, "shell")]);
        let scene = Scene::new(
            // Eye off centre so rays meet the shell at every angle.
            camera(
                centre + Vec3::new(0.3, 0.2, 0.1) * r,
                centre + Vec3::X * r,
                100.0,
            ),
            settings(48, 36),
            vec![diffuse("shell", c, k)],
            vec![Light::Point {
                position: centre,
                intensity: Rgb::splat(i),
            }],
            objects,
            instances,
        );
        let out = render(&scene, &RenderOptions::default()).unwrap();
        let expected = c * (k * i / (r * r));
        for p in out.image.pixels() {
            for ch in 0..3 {
                let rel = (p[ch] - expected[ch]).abs() / expected[ch];
                assert!(rel < 1e-4, "r={r}: pixel {p:?}, expected {expected:?}");
            }
        }
        assert_eq!(out.stats.missed, 0);
        assert_eq!(out.stats.shadow_blocked, 0);
    }
}

/// Ground point (0,0,0) under a light at (0,10,0) with a sphere in between.
fn shadow_scene(blocker: Material) -> Scene {
    let (objects, instances) = spheres(&[
        (Vec3::new(0.0, -1000.0, 0.0), 1000.0, 0, "ground"),
        (Vec3::new(0.0, 5.0, 0.0), 1.0, 1, "ball"),
    ]);
    Scene::new(
        camera(Vec3::new(4.0, 1.0, 0.0), Vec3::ZERO, 40.0),
        settings(16, 16),
        vec![diffuse("ground", Rgb::WHITE, 1.0), blocker],
        vec![Light::Point {
            position: Vec3::new(0.0, 10.0, 0.0),
            intensity: Rgb::splat(100.0),
        }],
        objects,
        instances,
    )
}

fn radiance_at_origin(scene: &Scene) -> (Rgb, Stats) {
    let w = Whitted::new(scene);
    let eye = Vec3::new(4.0, 1.0, 0.0);
    let ray = Ray::new(eye, (Vec3::ZERO - eye).normalize());
    let mut stats = Stats::default();
    let c = w.sample(
        &ray,
        &mut Rng::new(1, 1),
        &mut stats,
        &mut AovSample::default(),
    );
    (c, stats)
}

#[test]
fn shadow_rays_through_a_transparent_sphere_are_filtered_not_blocked() {
    let filter = Rgb::new(0.8, 0.5, 0.25);
    let glass = Material {
        name: "filter".into(),
        color: Texture::Solid(Rgb::WHITE),
        ambient: 0.0,
        diffuse: 0.0,
        transmission: 0.9,
        filter_color: Some(filter),
        ior: 1.5,
        ..Material::default()
    };
    let (c, stats) = radiance_at_origin(&shadow_scene(glass));
    // Lit by I / r² = 100 / 100 = 1, times the filter at each of the two surfaces.
    let per_surface = filter * 0.9;
    let expected = per_surface * per_surface;
    assert!(
        (c - expected).max_component().abs() < 1e-4,
        "{c:?} vs {expected:?}"
    );
    assert!(c.min_component_positive());
    assert_eq!(stats.shadow_blocked, 0);

    let opaque = diffuse("stone", Rgb::WHITE, 0.5);
    let (c, stats) = radiance_at_origin(&shadow_scene(opaque));
    assert_eq!(c, Rgb::BLACK, "an opaque sphere blocks the light");
    assert_eq!(stats.shadow_blocked, 1);
}

trait Positive {
    fn min_component_positive(&self) -> bool;
}
impl Positive for Rgb {
    fn min_component_positive(&self) -> bool {
        self.r > 0.0 && self.g > 0.0 && self.b > 0.0
    }
}

/// The camera inside a sphere that is a perfect half-mirror everywhere: every ray
/// reflects for ever unless weight or depth stops it.
fn hall_of_mirrors(max_depth: u32, min_weight: f32) -> Scene {
    let (objects, instances) = spheres(&[(Vec3::ZERO, 5.0, 0, "mirror ball")]);
    let mut s = settings(8, 6);
    s.max_depth = max_depth;
    s.min_weight = min_weight;
    let m = Material {
        name: "half mirror".into(),
        color: Texture::Solid(Rgb::WHITE),
        ambient: 0.2,
        diffuse: 0.0,
        reflection: Rgb::splat(0.5),
        ..Material::default()
    };
    Scene::new(
        camera(Vec3::new(0.5, 0.0, 0.0), Vec3::new(0.5, 0.0, -1.0), 60.0),
        s,
        vec![m],
        vec![],
        objects,
        instances,
    )
}

#[test]
fn weight_cut_off_stops_rays_and_is_counted() {
    // Weights 1, 0.5, 0.25, 0.125 are traced; 0.0625 < 0.1 is cut.
    let out = render(&hall_of_mirrors(100, 0.1), &RenderOptions::default()).unwrap();
    let st = &out.stats;
    assert_eq!(st.max_level_reached, 4);
    assert_eq!(st.cut_by_weight, 48, "one cut per pixel");
    assert_eq!(st.cut_by_depth, 0);
    assert_eq!(st.reflected_rays, 48 * 3);
    // Each level adds ambient 0.2 times its weight: 0.2 (1 + .5 + .25 + .125).
    let expected = 0.2 * 1.875;
    for p in out.image.pixels() {
        assert!((p.r - expected).abs() < 1e-5, "{p:?}");
    }
}

#[test]
fn depth_cut_off_stops_rays_and_is_counted() {
    let out = render(&hall_of_mirrors(3, 0.0), &RenderOptions::default()).unwrap();
    let st = &out.stats;
    assert_eq!(st.max_level_reached, 3);
    assert_eq!(st.cut_by_depth, 48);
    assert_eq!(st.cut_by_weight, 0);
    assert_eq!(st.camera_rays, 48);
    assert_eq!(st.reflected_rays, 96);
    let expected = 0.2 * 1.75;
    assert!(out
        .image
        .pixels()
        .iter()
        .all(|p| (p.r - expected).abs() < 1e-5));
}

#[test]
fn a_glass_sphere_of_index_one_is_invisible() {
    // No bending, no reflection, white filter: the background shows through unchanged.
    let glass = Material {
        name: "air".into(),
        color: Texture::Solid(Rgb::WHITE),
        ambient: 0.0,
        diffuse: 0.0,
        transmission: 1.0,
        ior: 1.0,
        ..Material::default()
    };
    let (objects, instances) = spheres(&[(Vec3::ZERO, 1.0, 0, "air ball")]);
    let mut s = settings(20, 20);
    s.background = Rgb::new(0.1, 0.6, 0.3);
    let scene = Scene::new(
        camera(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 40.0),
        s,
        vec![glass],
        vec![],
        objects,
        instances,
    );
    let out = render(&scene, &RenderOptions::default()).unwrap();
    assert!(out.stats.refracted_rays > 0);
    for p in out.image.pixels() {
        assert!((*p - Rgb::new(0.1, 0.6, 0.3)).max_component().abs() < 1e-6);
    }
}

#[test]
fn one_thread_and_two_threads_give_identical_images() {
    let mut scene = showcase(64, 48);
    scene.settings.spp = 4;
    let one = render(
        &scene,
        &RenderOptions {
            threads: Some(1),
            ..RenderOptions::default()
        },
    )
    .unwrap();
    let two = render(
        &scene,
        &RenderOptions {
            threads: Some(2),
            tile_size: 7,
            ..RenderOptions::default()
        },
    )
    .unwrap();
    assert_eq!(one.image, two.image);
    assert_eq!(one.stats.total_rays(), two.stats.total_rays());
    let mean = one.image.mean();
    assert!(mean.max_component() > 0.05, "not black: {mean:?}");
    assert!(one.image.pixels().iter().all(|p| p.is_finite()));
}

#[test]
fn adaptive_supersampling_refines_edges_only_and_ignores_tiling() {
    let mut scene = showcase(64, 48);
    scene.settings.spp = 4;
    scene.settings.adaptive_threshold = Some(0.05);
    let a = render(
        &scene,
        &RenderOptions {
            threads: Some(2),
            tile_size: 5,
            ..RenderOptions::default()
        },
    )
    .unwrap();
    let b = render(
        &scene,
        &RenderOptions {
            threads: Some(1),
            tile_size: 64,
            ..RenderOptions::default()
        },
    )
    .unwrap();
    assert_eq!(a.image, b.image);
    let refined = a.stats.refined_pixels;
    assert!(refined > 0 && refined < 64 * 48 / 2, "refined {refined}");
}

#[test]
fn stratified_supersampling_converges_towards_the_high_sample_image() {
    let mut scene = showcase(32, 24);
    scene.settings.spp = 64;
    let reference = render(&scene, &RenderOptions::default()).unwrap().image;
    scene.settings.spp = 1;
    let e1 = render(&scene, &RenderOptions::default())
        .unwrap()
        .image
        .rmse(&reference);
    scene.settings.spp = 9;
    let e9 = render(&scene, &RenderOptions::default())
        .unwrap()
        .image
        .rmse(&reference);
    assert!(e9 < 0.6 * e1, "9 spp error {e9} vs 1 spp {e1}");
}

#[test]
fn aovs_report_the_first_hit() {
    let scene = showcase(32, 24);
    let out = render(
        &scene,
        &RenderOptions {
            aovs: irradia_render::Aov::ALL.to_vec(),
            ..RenderOptions::default()
        },
    )
    .unwrap();
    let get = |a| &out.aovs.iter().find(|(x, _)| *x == a).unwrap().1;
    let ids = get(irradia_render::Aov::ObjectId);
    let depth = get(irradia_render::Aov::Depth);
    let normal = get(irradia_render::Aov::Normal);
    let ray_depth = get(irradia_render::Aov::RayDepth);
    // Bottom row sees the ground (object 0) at a finite distance with an up normal.
    let (x, y) = (16, 23);
    assert_eq!(ids.get(x, y).r, 0.0);
    assert!(depth.get(x, y).r.is_finite() && depth.get(x, y).r > 0.0);
    assert!(normal.get(x, y).g > 0.99);
    assert_eq!(ray_depth.get(x, y).r, 1.0, "the ground does not reflect");
    // Top row sees the sky.
    assert_eq!(ids.get(x, 0).r, -1.0);
    assert!(depth.get(x, 0).r.is_infinite());
    // Some pixel shows the mirror and reflects.
    assert!(ray_depth.pixels().iter().any(|p| p.r >= 2.0));
    let shown = irradia_render::Aov::Depth.display(depth);
    assert!(shown.pixels().iter().all(|p| (0.0..=1.0).contains(&p.r)));
}

/// An image texture on a sphere is looked up at the hit's uv (Mitsuba's sphere
/// parameterisation: u = atan2(y, x) / 2π), so the two halves of a two-texel image
/// show on the two sides of the sphere: the uv the tracer leaves out of untextured
/// objects' hits is still computed for textured ones.
#[test]
fn an_image_texture_on_a_sphere_is_read_at_the_hit_uv() {
    let (objects, instances) = spheres(&[(Vec3::ZERO, 1.0, 0, "ball")]);
    let mut m = diffuse("ball", Rgb::WHITE, 0.0);
    m.ambient = 1.0;
    m.color = Texture::Image {
        image: std::sync::Arc::new(irradia_core::Image::from_pixels(
            2,
            1,
            vec![Rgb::new(1.0, 0.0, 0.0), Rgb::new(0.0, 1.0, 0.0)],
        )),
        scale: glam::Vec2::ONE,
    };
    let scene = Scene::new(
        camera(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 40.0),
        settings(8, 8),
        vec![m],
        Vec::new(),
        objects,
        instances,
    );
    let w = Whitted::new(&scene);
    // From +y the ray meets the sphere where n = +y (u = 1/4: the first texel); from
    // -y where n = -y (u = 3/4: the second).
    for (eye, want) in [
        (Vec3::Y * 4.0, Rgb::new(1.0, 0.0, 0.0)),
        (Vec3::Y * -4.0, Rgb::new(0.0, 1.0, 0.0)),
    ] {
        let got = w.sample(
            &Ray::new(eye, -eye.normalize()),
            &mut Rng::new(1, 1),
            &mut Stats::default(),
            &mut AovSample::default(),
        );
        assert!(
            (got.r - want.r).abs() < 1e-6 && (got.g - want.g).abs() < 1e-6,
            "from {eye}: {got:?}"
        );
    }
}
