//! Every light type against its closed-form irradiance on a white diffuse floor
//! (k_d = 1, so the radiance equals the irradiance in Irradia's Phong convention).

mod common;

use common::{camera, diffuse, settings};
use glam::Vec3;
use irradia_core::{Ray, Rgb, Rng};
use irradia_geometry::shapes::Plane;
use irradia_geometry::Instance;
use irradia_render::{AovSample, Integrator, Stats, Whitted};
use irradia_scene::{Light, Object, Scene};
use std::f32::consts::PI;
use std::sync::Arc;

/// Radiance seen at the floor point `p` (on y = 0) lit by `light` alone.
fn floor_radiance(light: Light, p: Vec3) -> Rgb {
    let floor = Plane::new(Vec3::Y, 0.0).unwrap();
    let objects = vec![Object {
        name: "floor".into(),
        material: 0,
        leaf_materials: Vec::new(),
    }];
    let instances = vec![Instance::untransformed(Arc::new(floor))];
    let scene = Scene::new(
        camera(Vec3::new(0.0, 1.0, 5.0), Vec3::ZERO, 40.0),
        settings(8, 8),
        vec![diffuse("white", Rgb::WHITE, 1.0)],
        vec![light],
        objects,
        instances,
    );
    let eye = p + Vec3::new(0.3, 0.2, 0.1);
    let ray = Ray::new(eye, (p - eye).normalize());
    let w = Whitted::new(&scene);
    let mut stats = Stats::default();
    // Average a few independent samples so area-light noise averages out further.
    let n = 16;
    let mut sum = Rgb::BLACK;
    for s in 0..n {
        sum += w.sample(
            &ray,
            &mut Rng::new(s, 7),
            &mut stats,
            &mut AovSample::default(),
        );
    }
    sum / n as f32
}

#[test]
fn point_and_directional_lights_follow_cosine_and_inverse_square() {
    let p = Vec3::new(0.5, 0.0, -0.25);
    let pos = Vec3::new(2.0, 3.0, 1.0);
    let d = pos - p;
    let e = 7.0 * (d.normalize().y) / d.length_squared();
    let got = floor_radiance(
        Light::Point {
            position: pos,
            intensity: Rgb::splat(7.0),
        },
        p,
    );
    assert!((got.r - e).abs() < 1e-5 * e.max(1.0), "{got:?} vs {e}");

    let dir = Vec3::new(-1.0, -2.0, 0.5).normalize();
    let got = floor_radiance(
        Light::Directional {
            direction: dir,
            irradiance: Rgb::splat(3.0),
        },
        p,
    );
    assert!((got.g - 3.0 * -dir.y).abs() < 1e-5, "{got:?}");
}

#[test]
fn spot_lights_are_full_inside_the_inner_cone_and_dark_outside_the_outer() {
    let spot = |p| {
        floor_radiance(
            Light::Spot {
                position: Vec3::new(0.0, 4.0, 0.0),
                direction: -Vec3::Y,
                intensity: Rgb::splat(16.0),
                cos_inner: 20f32.to_radians().cos(),
                cos_outer: 30f32.to_radians().cos(),
                profile: irradia_scene::SpotProfile::Smooth,
                texture: None,
            },
            p,
        )
    };
    let centre = spot(Vec3::ZERO);
    assert!((centre.r - 1.0).abs() < 1e-5, "16 / 4² = 1: {centre:?}");
    let outside = spot(Vec3::new(4.0 * 35f32.to_radians().tan(), 0.0, 0.0));
    assert_eq!(outside, Rgb::BLACK);
    let between = spot(Vec3::new(4.0 * 25f32.to_radians().tan(), 0.0, 0.0));
    assert!(between.r > 0.0 && between.r < 1.0);
}

#[test]
fn a_sphere_light_gives_pi_l_sin2_alpha() {
    // A sphere of radius r straight above at distance h subtends half-angle α with
    // sin α = r / h; a facing surface receives E = π L sin²α.
    let (r, h, l) = (0.5f32, 3.0f32, 2.0f32);
    let got = floor_radiance(
        Light::Sphere {
            center: Vec3::new(0.0, h, 0.0),
            radius: r,
            radiance: Rgb::splat(l),
            samples: 64,
        },
        Vec3::ZERO,
    );
    let e = PI * l * (r / h).powi(2);
    assert!((got.r - e).abs() < 0.01 * e, "{got:?} vs {e}");
}

#[test]
fn a_rect_light_matches_the_closed_form_for_a_parallel_square() {
    // Irradiance under the centre of a parallel emitting square of side 2a at height
    // h (Lambertian emitter, radiance L): by symmetry four times the corner formula
    //   E_corner = (L / 2) [ X/√(1+X²) atan(Y/√(1+X²)) + Y/√(1+Y²) atan(X/√(1+Y²)) ]
    // with X = a/h, Y = a/h (Howell's catalogue, configuration C-11, times π L).
    let (a, h, l) = (1.0f32, 2.0f32, 3.0f32);
    let x = a / h;
    let s = (1.0 + x * x).sqrt();
    let corner = 0.5 * l * 2.0 * (x / s) * (x / s).atan();
    let e = 4.0 * corner;
    let got = floor_radiance(
        Light::Rect {
            corner: Vec3::new(-a, h, -a),
            edge_u: Vec3::new(2.0 * a, 0.0, 0.0),
            edge_v: Vec3::new(0.0, 0.0, 2.0 * a),
            radiance: Rgb::splat(l),
            samples: 64,
        },
        Vec3::ZERO,
    );
    assert!((got.r - e).abs() < 0.01 * e, "{got:?} vs {e}");
    // The other side of the rectangle emits nothing.
    let back = floor_radiance(
        Light::Rect {
            corner: Vec3::new(-a, h, -a),
            edge_u: Vec3::new(0.0, 0.0, 2.0 * a),
            edge_v: Vec3::new(2.0 * a, 0.0, 0.0),
            radiance: Rgb::splat(l),
            samples: 16,
        },
        Vec3::ZERO,
    );
    assert_eq!(back, Rgb::BLACK);
}

#[test]
fn mitsuba_spot_and_projector_light_the_whitted_floor_like_the_path_tracer() {
    // Mitsuba's spot (cutoff 30°, beam 10°): at 20° from the axis half the intensity.
    let theta = 20f32.to_radians();
    let q = Vec3::new(4.0 * theta.tan(), 0.0, 0.0);
    let got = floor_radiance(
        Light::Spot {
            position: Vec3::new(0.0, 4.0, 0.0),
            direction: -Vec3::Y,
            intensity: Rgb::splat(16.0),
            cos_inner: 10f32.to_radians().cos(),
            cos_outer: 30f32.to_radians().cos(),
            profile: irradia_scene::SpotProfile::Linear,
            texture: None,
        },
        q,
    );
    let e = 16.0 * theta.cos().powi(3) / 16.0 * 0.5;
    assert!((got.r - e).abs() < 1e-5, "{got:?} vs {e}");
    // A projector 2 above the floor, constant image 3, scale 0.5: E = π · 1.5 / 4.
    let proj = irradia_scene::Projector::new(
        Vec3::new(0.0, 2.0, 0.0),
        Vec3::ZERO,
        Vec3::Z,
        50.0,
        irradia_scene::FovAxis::Horizontal,
        Arc::new(irradia_core::Image::from_pixels(
            1,
            1,
            vec![Rgb::splat(3.0)],
        )),
        0.5,
    );
    let got = floor_radiance(Light::Projector(Arc::new(proj)), Vec3::new(0.3, 0.0, -0.2));
    let e = PI * 1.5 / 4.0;
    assert!((got.r - e).abs() < 1e-4 * e, "{got:?} vs {e}");
}

#[test]
fn whitted_rays_that_leave_the_scene_see_constant_and_envmap_lights() {
    let map = irradia_scene::EnvMap {
        image: Arc::new(irradia_core::Image::from_pixels(
            4,
            2,
            (0..8).map(|i| Rgb::splat(i as f32)).collect(),
        )),
        scale: 2.0,
        to_world: glam::Mat3::IDENTITY,
        path: "m".into(),
    };
    let mut s = settings(8, 8);
    s.background = Rgb::splat(0.25);
    let scene = Scene::new(
        camera(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 40.0),
        s,
        vec![diffuse("white", Rgb::WHITE, 1.0)],
        vec![
            Light::Constant {
                radiance: Rgb::splat(0.5),
            },
            Light::Envmap(Arc::new(map.clone())),
        ],
        Vec::new(),
        Vec::new(),
    );
    let w = Whitted::new(&scene);
    // The map's own lookup (Mitsuba's bilinear vertex grid, checked against Mitsuba in
    // emitters.rs) at two directions, added to the background and the constant light.
    for d in [Vec3::new(1.0, 0.3, 0.2), Vec3::new(0.0, -0.5, -1.0)] {
        let got = w.sample(
            &Ray::new(Vec3::ZERO, d.normalize()),
            &mut Rng::new(0, 0),
            &mut Stats::default(),
            &mut AovSample::default(),
        );
        let env = map.eval(d).g;
        assert!(env > 0.0);
        let want = 0.25 + 0.5 + env;
        assert!((got.g - want).abs() < 1e-5 * want, "{d}: {got:?} vs {want}");
    }
}
