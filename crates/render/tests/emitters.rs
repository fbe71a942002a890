//! The path tracer's emitters as Mitsuba's and pbrt's own tests check them: the
//! environment map's sampling against its density (chi-square), every non-delta
//! emitter's density integrated over the sphere of directions, the irradiance of point,
//! spot, directional and projector lights on a diffuse plane against closed forms, the
//! irradiance of an environment map on a plane against the integral of its interpolant, and a
//! furnace lit by Mitsuba's `constant` emitter.

mod chi_square;
mod path_common;

use glam::{Mat3, Vec2, Vec3};
use irradia_core::{Image, Ray, Rgb, Rng};
use irradia_geometry::shapes::{Plane, Sphere};
use irradia_geometry::Instance;
use irradia_render::path::envmap::EnvmapSampler;
use irradia_render::path::integrator::{radiance, PathCounters};
use irradia_render::path::lights::LightSampler;
use irradia_render::path::PathParams;
use irradia_scene::{EnvMap, FovAxis, Light, Object, Projector, Scene, SpotProfile};
use std::f64::consts::PI;
use std::path::PathBuf;
use std::sync::Arc;

/// A 32 x 16 map with a smooth gradient, a black band and one bright texel, turned by
/// `to_world`.
fn test_map(to_world: Mat3) -> Arc<EnvMap> {
    let (w, h) = (32u32, 16u32);
    let mut px = Vec::new();
    for j in 0..h {
        for i in 0..w {
            let v = if i == 20 && j == 3 {
                Rgb::new(400.0, 300.0, 200.0)
            } else if (8..11).contains(&i) {
                Rgb::BLACK
            } else {
                Rgb::new(0.2 + 0.05 * i as f32, 0.5, 1.0 + 0.1 * j as f32)
            };
            px.push(v);
        }
    }
    Arc::new(EnvMap {
        image: Arc::new(Image::from_pixels(w, h, px)),
        scale: 1.5,
        to_world,
        path: PathBuf::from("test"),
    })
}

fn dir(z: f64, phi: f64) -> Vec3 {
    let s = (1.0 - z * z).max(0.0).sqrt();
    Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, z as f32)
}

const Z_BINS: usize = 12;
const PHI_BINS: usize = 24;

/// ∫ `pdf` dω over each (z, φ) bin by the midpoint rule on a fine grid (z and φ are
/// equal-area coordinates: dω = dz dφ).
fn bin_integrals(pdf: impl Fn(Vec3) -> f64, sub: usize) -> Vec<f64> {
    let (dz, dp) = (2.0 / Z_BINS as f64, 2.0 * PI / PHI_BINS as f64);
    let mut out = vec![0.0; Z_BINS * PHI_BINS];
    for (b, o) in out.iter_mut().enumerate() {
        let (t, p) = (b / PHI_BINS, b % PHI_BINS);
        let mut s = 0.0;
        for i in 0..sub {
            for j in 0..sub {
                let z = -1.0 + dz * (t as f64 + (i as f64 + 0.5) / sub as f64);
                let phi = dp * (p as f64 + (j as f64 + 0.5) / sub as f64);
                s += pdf(dir(z, phi));
            }
        }
        *o = s * dz * dp / (sub * sub) as f64;
    }
    out
}

/// The map's `(u, v)` of a direction in its own frame, derived here from Mitsuba's
/// definition: u = atan2(x, −z) / 2π, v = acos(y) / π.
fn lat_long(d: Vec3) -> (f64, f64) {
    let d = d.as_dvec3().normalize();
    let mut u = d.x.atan2(-d.z) / (2.0 * PI);
    if u < 0.0 {
        u += 1.0;
    }
    (u, d.y.clamp(-1.0, 1.0).acos() / PI)
}

const U_BINS: usize = 20;
const V_BINS: usize = 12;

/// Pearson's test of `n` samples of the map's sampler against its density. Samples are
/// binned by their grid coordinates `(s, t) = ((u − ½/W) mod 1, v)` (Mitsuba's pixel
/// grid, with `(u, v)` derived here from the direction) on bins that do not line up
/// with the map's `W x (H − 1)` cells; the density is constant over each cell in
/// `(s, t)` (dω = 2π² sin θ du dv), so each bin's expected share is exact: Σ over cells
/// of the density at the cell's centre times its overlap with the bin.
fn envmap_p_value(sampler: &EnvmapSampler, n: usize, seed: u64) -> f64 {
    let map = &sampler.map;
    let (w, h) = (map.image.width() as usize, map.image.height() as usize);
    let rows = h - 1;
    let half = 0.5 / w as f64;
    let mut observed = vec![0.0; U_BINS * V_BINS];
    let mut rng = Rng::new(seed, 3);
    for _ in 0..n {
        if let Some(s) = sampler.sample(rng.next_2d()) {
            let (u, v) = lat_long(map.to_world.transpose() * s.wi);
            let su = (u - half).rem_euclid(1.0);
            let bu = ((su * U_BINS as f64) as usize).min(U_BINS - 1);
            let bv = ((v * V_BINS as f64) as usize).min(V_BINS - 1);
            observed[bv * U_BINS + bu] += 1.0;
        }
    }
    let overlap = |a0: f64, a1: f64, b0: f64, b1: f64| (a1.min(b1) - a0.max(b0)).max(0.0);
    let mut expected = vec![0.0; U_BINS * V_BINS];
    for j in 0..rows {
        for i in 0..w {
            let (s_c, t) = ((i as f64 + 0.5) / w as f64, (j as f64 + 0.5) / rows as f64);
            let u = (s_c + half).rem_euclid(1.0);
            let d = map.direction(Vec2::new(u as f32, t as f32));
            let density_uv = sampler.pdf(d) as f64 * 2.0 * PI * PI * (PI * t).sin();
            for bv in 0..V_BINS {
                for bu in 0..U_BINS {
                    let a = overlap(
                        i as f64 / w as f64,
                        (i + 1) as f64 / w as f64,
                        bu as f64 / U_BINS as f64,
                        (bu + 1) as f64 / U_BINS as f64,
                    ) * overlap(
                        j as f64 / rows as f64,
                        (j + 1) as f64 / rows as f64,
                        bv as f64 / V_BINS as f64,
                        (bv + 1) as f64 / V_BINS as f64,
                    );
                    expected[bv * U_BINS + bu] += density_uv * a * n as f64;
                }
            }
        }
    }
    chi_square::pearson(&observed, &expected)
}

#[test]
fn envmap_sampling_matches_its_density_chi_square() {
    for (k, m) in [
        Mat3::IDENTITY,
        Mat3::from_rotation_x(0.7) * Mat3::from_rotation_y(-1.1),
    ]
    .into_iter()
    .enumerate()
    {
        let sampler = EnvmapSampler::new(test_map(m));
        let p = envmap_p_value(&sampler, 200_000, 11 + k as u64);
        assert!(p > 1e-3, "rotation {k}: chi-square p-value {p}");
    }
}

/// The sampled radiance and density agree with the map's own lookup and `pdf`, and the
/// density integrates to one over the sphere.
#[test]
fn envmap_samples_report_the_maps_radiance_and_a_density_that_integrates_to_one() {
    let map = test_map(Mat3::from_rotation_z(0.4));
    let sampler = EnvmapSampler::new(map.clone());
    let total: f64 = bin_integrals(|w| sampler.pdf(w) as f64, 40).iter().sum();
    assert!((total - 1.0).abs() < 2e-3, "∫ pdf dω = {total}");
    let mut rng = Rng::new(5, 1);
    let mut edge_pdfs = 0;
    for _ in 0..2000 {
        let s = sampler.sample(rng.next_2d()).unwrap();
        let (l, pdf) = (map.eval(s.wi), sampler.pdf(s.wi));
        // The radiance is the map's bilinear lookup; the density is the cell's (a
        // direction on a cell edge may round to the neighbour cell).
        assert!(
            (l - s.radiance).max_component().abs() <= 1e-3 * l.max_component().max(1.0),
            "radiance {l:?} vs {:?}",
            s.radiance
        );
        if (pdf - s.pdf).abs() > 1e-3 * s.pdf {
            edge_pdfs += 1;
        }
    }
    assert!(
        edge_pdfs <= 4,
        "{edge_pdfs} of 2000 sampled densities differ from pdf()"
    );
    let black = (0..2000)
        .filter_map(|_| sampler.sample(rng.next_2d()))
        .filter(|s| s.radiance.is_black())
        .count();
    assert_eq!(black, 0, "black texels are never sampled");
}

fn scene_with(lights: Vec<Light>, objects: Vec<(Object, Instance)>, background: Rgb) -> Scene {
    let (objs, insts): (Vec<_>, Vec<_>) = objects.into_iter().unzip();
    let n = objs.len();
    Scene::new(
        path_common::camera(Vec3::new(0.0, 1.0, 5.0), Vec3::ZERO, 40.0),
        path_common::settings(8, 8, 2, background),
        vec![
            path_common::diffuse(1.0, 0.0),
            path_common::diffuse(0.5, 3.0),
        ],
        lights,
        objs,
        insts.into_iter().take(n).collect(),
    )
}

fn object(name: &str, material: u32) -> Object {
    Object {
        name: name.into(),
        material,
        leaf_materials: Vec::new(),
    }
}

/// Every non-delta emitter's density integrated over the sphere of directions from a
/// point: environment directions through `pdf_environment`, directions that reach an
/// emissive sphere through `pdf_object`; each integral is the probability that light
/// sampling picks that emitter, measured from `sample` with stratified choices.
#[test]
fn every_emitters_density_integrates_to_its_choice_probability() {
    let ball = Instance::untransformed(Arc::new(Sphere::new(Vec3::new(2.0, 0.5, -1.0), 0.75)));
    let scene = scene_with(
        vec![
            Light::Envmap(test_map(Mat3::from_rotation_y(0.9))),
            Light::Constant {
                radiance: Rgb::splat(0.3),
            },
            Light::Point {
                position: Vec3::new(0.0, 3.0, 0.0),
                intensity: Rgb::splat(20.0),
            },
        ],
        vec![(object("ball", 1), ball)],
        Rgb::splat(0.1),
    );
    let lights = LightSampler::new(&scene);
    let p = Vec3::new(0.2, 0.1, 0.3);
    // The choice probabilities, from `sample` at stratified `u_pick`.
    let (mut env, mut ball_share, mut delta) = (0usize, 0usize, 0usize);
    let n = 20_000;
    let mut rng = Rng::new(2, 2);
    for k in 0..n {
        let u_pick = (k as f32 + 0.5) / n as f32;
        let Some(s) = lights.sample(&scene, p, u_pick, rng.next_2d()) else {
            continue;
        };
        match (s.delta, s.target) {
            (true, _) => delta += 1,
            (false, None) => env += 1,
            (false, Some(_)) => ball_share += 1,
        }
    }
    let share = |c: usize| c as f64 / n as f64;
    assert!(delta > 0 && env > 0 && ball_share > 0);
    // ∫ pdf over the sphere of directions: the environment's over every direction, the
    // ball's over the directions whose rays from p reach it.
    let (mut env_total, mut int_ball) = (0.0f64, 0.0f64);
    let sub = 400;
    let (dz, dp) = (2.0 / sub as f64, 2.0 * PI / sub as f64);
    for i in 0..sub {
        for j in 0..sub {
            let w = dir(-1.0 + dz * (i as f64 + 0.5), dp * (j as f64 + 0.5));
            env_total += lights.pdf_environment(w) as f64 * dz * dp;
            if let Some(h) = scene.accel.intersect(&Ray::new(p, w), f32::INFINITY) {
                int_ball += lights.pdf_object(&scene, h.instance, p, h.hit.point, h.hit.normal)
                    as f64
                    * dz
                    * dp;
            }
        }
    }
    assert!(
        (env_total - share(env)).abs() < 3e-3,
        "environment: ∫ pdf = {env_total}, chosen {}",
        share(env)
    );
    // Points of the ball facing away from p give no sample, so both sides count only
    // the cap that p sees.
    assert!(
        (int_ball - share(ball_share)).abs() < 3e-3,
        "ball: ∫ pdf = {int_ball}, sampled {}",
        share(ball_share)
    );
}

/// An emissive sphere is sampled by the cone it subtends (Mitsuba 3's `sphere`): seen
/// from outside, every light sample lands on the visible cap (none is lost on the far
/// side), its density is the cone's `1 / (2π (1 - cos θmax))` and equals `pdf_object`
/// at the sampled point; a sphere stretched into an ellipsoid, or seen from inside, is
/// sampled by area, with the density `pdf_object` gives there too.
#[test]
fn spheres_are_sampled_by_their_cones() {
    use glam::{Affine3A, Quat};
    let (centre, r) = (Vec3::new(2.0, 0.5, -1.0), 0.75f32);
    let balls = [
        Instance::untransformed(Arc::new(Sphere::new(centre, r))),
        Instance::new(
            Arc::new(Sphere::new(Vec3::ZERO, 1.0)),
            Affine3A::from_scale_rotation_translation(
                Vec3::new(0.5, 0.9, 0.5),
                Quat::from_rotation_z(0.3),
                centre,
            ),
        ),
    ];
    for (k, ball) in balls.into_iter().enumerate() {
        let cone = k == 0;
        let scene = scene_with(vec![], vec![(object("ball", 1), ball)], Rgb::BLACK);
        let lights = LightSampler::new(&scene);
        let mut rng = Rng::new(4, 9);
        for p in [
            Vec3::new(0.2, 0.1, 0.3),
            centre + Vec3::new(0.1, -0.2, 0.05),
        ] {
            let inside = (p - centre).length() < 0.4;
            let n = 4000;
            let (mut landed, mut misses) = (0, 0);
            for _ in 0..n {
                let Some(s) = lights.sample(&scene, p, 0.5, rng.next_2d()) else {
                    continue;
                };
                landed += 1;
                let q = s.target.unwrap();
                // The sampled point's own surface, as a BSDF ray from p meets it.
                let Some(h) = scene.accel.intersect(&Ray::new(p, s.wi), f32::INFINITY) else {
                    // Only a silhouette's grazing sample may round past the ball.
                    misses += 1;
                    continue;
                };
                assert!(
                    (h.hit.point - q).length() < 1e-3,
                    "{k}: {q} vs {}",
                    h.hit.point
                );
                let pdf = lights.pdf_object(&scene, h.instance, p, h.hit.point, h.hit.normal);
                // (By area the density goes as 1 / cos at the light: the hit's rounding
                // moves it most at grazing angles.)
                if !cone && s.wi.dot(h.hit.normal).abs() < 0.1 {
                    continue;
                }
                assert!(
                    (pdf / s.pdf - 1.0).abs() < 2e-3,
                    "ball {k}, p {p}: sample pdf {} vs pdf_object {pdf}",
                    s.pdf
                );
                if cone && !inside {
                    let sin_max = r as f64 / (centre - p).length() as f64;
                    let omega = 2.0 * PI * (1.0 - (1.0 - sin_max * sin_max).sqrt());
                    assert!((s.pdf as f64 * omega - 1.0).abs() < 1e-4, "{}", s.pdf);
                }
            }
            assert!(
                misses <= n / 500,
                "ball {k}: {misses} rays miss their samples"
            );
            if cone && !inside {
                assert_eq!(landed, n, "every cone sample lands on the visible cap");
            } else if !inside {
                // By area, about half of the points face away from p.
                assert!(landed < n * 7 / 10, "{landed} of {n}");
            }
        }
    }
}

/// Radiance from the white (albedo 1) diffuse floor y = 0 at `p`, lit by `light`
/// alone: E / π, where E is the irradiance there.
fn floor_radiance(light: Light, p: Vec3) -> f64 {
    let floor = Instance::untransformed(Arc::new(Plane::new(Vec3::Y, 0.0).unwrap()));
    let scene = scene_with(vec![light], vec![(object("floor", 0), floor)], Rgb::BLACK);
    let lights = LightSampler::new(&scene);
    let eye = p + Vec3::new(0.3, 0.5, 0.1);
    let ray = Ray::new(eye, (p - eye).normalize());
    let params = PathParams {
        max_depth: 2,
        rr_depth: 5,
    };
    let l = radiance(
        &scene,
        &lights,
        &params,
        ray,
        &mut Rng::new(1, 1),
        &mut PathCounters::default(),
    );
    l.g as f64
}

fn close(got: f64, want: f64, what: &str) {
    assert!(
        (got - want).abs() <= 2e-5 * want.abs().max(1e-3),
        "{what}: {got} vs {want}"
    );
}

#[test]
fn point_directional_and_spot_irradiance_on_a_diffuse_plane() {
    let p = Vec3::new(0.5, 0.0, -0.25);
    let pos = Vec3::new(2.0, 3.0, 1.0);
    let d = (pos - p).as_dvec3();
    let e = 7.0 * (d.normalize().y) / d.length_squared();
    let got = floor_radiance(
        Light::Point {
            position: pos,
            intensity: Rgb::splat(7.0),
        },
        p,
    );
    close(got, e / PI, "point");

    let w = Vec3::new(-1.0, -2.0, 0.5).normalize();
    let got = floor_radiance(
        Light::Directional {
            direction: w,
            irradiance: Rgb::splat(3.0),
        },
        p,
    );
    close(got, 3.0 * -w.y as f64 / PI, "directional");

    // Mitsuba's spot (cutoff 30°, beam 10°) 4 above the floor pointing down: E = I cos θ
    // / r² inside the beam, times (cutoff − θ)/(cutoff − beam) in the transition, 0
    // beyond the cutoff.
    let (cutoff, beam) = (30f64.to_radians(), 10f64.to_radians());
    let spot = Light::Spot {
        position: Vec3::new(0.0, 4.0, 0.0),
        direction: -Vec3::Y,
        intensity: Rgb::splat(16.0),
        cos_inner: (beam as f32).cos(),
        cos_outer: (cutoff as f32).cos(),
        profile: SpotProfile::Linear,
        texture: None,
    };
    for deg in [0.0f64, 5.0, 12.0, 20.0, 27.0, 29.5, 31.0, 50.0] {
        let theta = deg.to_radians();
        let q = Vec3::new((4.0 * theta.tan()) as f32, 0.0, 0.0);
        let r2 = 16.0 / theta.cos().powi(2);
        let falloff = if theta <= beam {
            1.0
        } else if theta < cutoff {
            (cutoff - theta) / (cutoff - beam)
        } else {
            0.0
        };
        let want = 16.0 * theta.cos() / r2 * falloff / PI;
        let got = floor_radiance(spot.clone(), q);
        assert!(
            (got - want).abs() <= 1e-4 * want.max(1e-3),
            "spot at {deg}°: {got} vs {want}"
        );
    }
}

/// Mitsuba's spot `texture`: what the light sends to points around its cone (a
/// checkerboard across the image, the spot looking down with up = +z, so that every
/// quadrant and the transition region are read), against pip Mitsuba 3.9.1's
/// `sample_direction` (scalar_rgb; `intensity * texture * falloff / r²`).
#[test]
fn spot_texture_as_mitsuba() {
    use irradia_scene::texture::{Checkerboard, TextureMap};
    use irradia_scene::SpotTexture;
    let (position, direction, up) = (Vec3::new(1.0, 2.0, 3.0), -Vec3::Y, Vec3::Z);
    let cos_outer = 30f32.to_radians().cos();
    let map = TextureMap::Checkerboard(Checkerboard {
        color0: Rgb::new(0.9, 0.5, 0.1),
        color1: Rgb::new(0.1, 0.3, 0.7),
        ..Checkerboard::default()
    });
    let spot = Light::Spot {
        position,
        direction,
        intensity: Rgb::splat(5.0),
        cos_inner: 15f32.to_radians().cos(),
        cos_outer,
        profile: SpotProfile::Linear,
        texture: Some(Arc::new(SpotTexture::new(map, direction, up, cos_outer))),
    };
    let scene = scene_with(vec![spot], vec![], Rgb::BLACK);
    let lights = LightSampler::new(&scene);
    // (point, Mitsuba's value), measured with pip Mitsuba (see above); its printed digits.
    #[allow(clippy::excessive_precision)]
    let mitsuba = [
        ([1.3, 0.0, 3.6], [0.7724521, 0.42914006, 0.08582801]),
        ([0.5, 0.0, 3.4], [0.0925716, 0.27771479, 0.64800119]),
        ([0.6, 0.0, 2.5], [0.83314443, 0.46285802, 0.0925716]),
        ([1.5, 0.0, 2.8], [0.11600672, 0.34802017, 0.81204706]),
        ([1.1, 0.0, 3.05], [1.12149537, 0.62305295, 0.12461060]),
        ([2.0, 0.0, 3.0], [0.02289976, 0.06869927, 0.16029829]),
    ];
    for (p, want) in mitsuba {
        let s = lights
            .sample(&scene, Vec3::from(p), 0.5, Vec2::splat(0.5))
            .unwrap();
        for k in 0..3 {
            assert!(
                (s.li[k] - want[k]).abs() <= 1e-4 * want[k].max(1e-2),
                "spot texture at {p:?}: {:?} vs Mitsuba {want:?}",
                s.li
            );
        }
    }
}

/// Mitsuba's projector: the image projected onto a plane facing it at distance z gives
/// E = π · scale · E(uv) / z² (a 2 x 2 image, so each quadrant has its own value).
#[test]
fn projector_irradiance_on_a_facing_plane() {
    let image = Arc::new(Image::from_pixels(
        2,
        2,
        vec![
            Rgb::splat(1.0),
            Rgb::splat(2.0),
            Rgb::splat(3.0),
            Rgb::splat(4.0),
        ],
    ));
    let z = 2.5f32;
    let proj = Projector::new(
        Vec3::new(0.0, z, 0.0),
        Vec3::ZERO,
        Vec3::new(0.0, 0.0, -1.0),
        60.0,
        FovAxis::Horizontal,
        image,
        0.8,
    );
    // Looking down -y with up = -z: image right is +x, image top is -z.
    let half = (z * 30f32.to_radians().tan()) as f64;
    for (x, zc, value) in [
        (-0.5, -0.5, 1.0),
        (0.5, -0.5, 2.0),
        (-0.5, 0.5, 3.0),
        (0.5, 0.5, 4.0),
    ] {
        let q = Vec3::new((x * half) as f32, 0.0, (zc * half) as f32);
        let got = floor_radiance(Light::Projector(Arc::new(proj.clone())), q);
        let want = PI * 0.8 * value / (z as f64 * z as f64) / PI;
        close(got, want, &format!("projector at {q}"));
    }
    let outside = floor_radiance(
        Light::Projector(Arc::new(proj)),
        Vec3::new((1.2 * half) as f32, 0.0, 0.0),
    );
    assert_eq!(outside, 0.0);
}

/// Mitsuba's projector reads its image as its `bitmap` texture does: bilinearly, with
/// indices wrapping around at the borders. A 3 x 2 image (raw floats) projected on the
/// floor from 2.5 above (fov 60° across x, up = -z), at points between texel centres
/// and near every edge, against pip Mitsuba 3.9.1's `sample_direction` (scalar_rgb).
#[test]
fn projector_image_is_filtered_as_mitsuba() {
    let px: Vec<Rgb> = (0..6)
        .map(|i| {
            Rgb::new(
                0.3 * i as f32 + 0.1,
                0.3 * i as f32 + 0.2,
                0.3 * i as f32 + 0.3,
            )
        })
        .collect();
    let proj = Projector::new(
        Vec3::new(0.0, 2.5, 0.0),
        Vec3::ZERO,
        Vec3::new(0.0, 0.0, -1.0),
        60.0,
        FovAxis::Horizontal,
        Arc::new(Image::from_pixels(3, 2, px)),
        0.8,
    );
    let scene = scene_with(vec![Light::Projector(Arc::new(proj))], vec![], Rgb::BLACK);
    let lights = LightSampler::new(&scene);
    #[allow(clippy::excessive_precision)] // Mitsuba's printed digits
    let mitsuba = [
        ([0.1, 0.0, 0.2], [0.431279, 0.47165188, 0.51202482]),
        ([-0.9, 0.0, -0.3], [0.12422054, 0.16723089, 0.21024121]),
        ([1.3, 0.0, 0.05], [0.44704193, 0.49237329, 0.53770459]),
        ([0.45, 0.0, -0.8], [0.35920671, 0.40204373, 0.44488078]),
        ([-1.4, 0.0, 0.9], [0.4256829, 0.47399139, 0.52229983]),
    ];
    for (p, want) in mitsuba {
        let s = lights
            .sample(&scene, Vec3::from(p), 0.5, Vec2::splat(0.5))
            .unwrap();
        for k in 0..3 {
            assert!(
                (s.li[k] - want[k]).abs() <= 2e-4 * want[k],
                "projector at {p:?}: {:?} vs Mitsuba {want:?}",
                s.li
            );
        }
    }
}

/// A white diffuse floor under an environment map whose lower half is hidden by the
/// floor: its radiance is E / π with E = ∫ L cos θ dω over the upper hemisphere. With
/// Mitsuba's lookup (pixels at the vertices of a periodic grid, linear in between),
/// the integral over φ of a pixel row's interpolant is 2π times the row's mean, and
/// between rows it is linear in v = θ / π: E = 2π ∫ Ā(θ) cos θ sin θ dθ, integrated
/// here by a fine midpoint rule. Whatever the sampling (here NEE of the envmap and
/// BSDF sampling, combined by MIS).
#[test]
fn envmap_irradiance_on_a_plane_is_the_integral_of_its_interpolant() {
    let map = test_map(Mat3::IDENTITY);
    let (w, h) = (map.image.width(), map.image.height());
    let row_mean: Vec<f64> = (0..h)
        .map(|j| (0..w).map(|i| map.image.get(i, j).g as f64).sum::<f64>() / w as f64)
        .collect();
    let steps = 200_000;
    let mut e = 0.0f64;
    for k in 0..steps {
        let theta = (k as f64 + 0.5) / steps as f64 * PI / 2.0;
        let t = theta / PI * (h - 1) as f64;
        let j = (t as usize).min(h as usize - 2);
        let f = t - j as f64;
        let a = row_mean[j] * (1.0 - f) + row_mean[j + 1] * f;
        e += a * theta.cos() * theta.sin() * (PI / 2.0 / steps as f64);
    }
    e *= 2.0 * PI * map.scale as f64;
    let floor = Instance::untransformed(Arc::new(Plane::new(Vec3::Y, 0.0).unwrap()));
    let scene = scene_with(
        vec![Light::Envmap(map)],
        vec![(object("floor", 0), floor)],
        Rgb::BLACK,
    );
    let lights = LightSampler::new(&scene);
    let params = PathParams {
        max_depth: 2,
        rr_depth: 5,
    };
    let eye = Vec3::new(0.1, 1.0, 0.2);
    let ray = Ray::new(eye, (Vec3::ZERO - eye).normalize());
    let n = 200_000;
    let (mut sum, mut sum2) = (0.0f64, 0.0f64);
    let mut counters = PathCounters::default();
    for s in 0..n {
        let l = radiance(
            &scene,
            &lights,
            &params,
            ray,
            &mut Rng::new(s, 9),
            &mut counters,
        )
        .g as f64;
        sum += l;
        sum2 += l * l;
    }
    let mean = sum / n as f64;
    let sigma = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
    let want = e / PI;
    assert!(
        (mean - want).abs() < 4.0 * sigma + 1e-4 * want,
        "{mean} ± {sigma} vs {want}"
    );
}

/// A white (albedo 1) diffuse sphere lit by Mitsuba's `constant` emitter alone (black
/// background) disappears: every pixel converges to the constant radiance.
#[test]
fn constant_environment_furnace() {
    let ball = Instance::untransformed(Arc::new(Sphere::new(Vec3::ZERO, 1.0)));
    let mut scene = scene_with(
        vec![Light::Constant {
            radiance: Rgb::splat(0.6),
        }],
        vec![(object("ball", 0), ball)],
        Rgb::BLACK,
    );
    scene.camera = path_common::camera(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 35.0);
    let lights = LightSampler::new(&scene);
    let params = PathParams {
        max_depth: 400,
        rr_depth: 5,
    };
    let cam = scene.camera.rays(8, 8);
    let mut counters = PathCounters::default();
    let (mut sum, mut sum2, n) = (0.0f64, 0.0f64, 40_000u32);
    for s in 0..n {
        let px = Vec2::new((s % 8) as f32 + 0.5, ((s / 8) % 8) as f32 + 0.5);
        let l = radiance(
            &scene,
            &lights,
            &params,
            cam.ray(px.x, px.y),
            &mut Rng::new(s as u64, 4),
            &mut counters,
        )
        .g as f64;
        sum += l;
        sum2 += l * l;
    }
    let mean = sum / n as f64;
    let sigma = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
    assert!(
        (mean - 0.6).abs() < 4.0 * sigma + 1e-4,
        "{mean} ± {sigma} vs 0.6"
    );
}

/// The map's radiance against Mitsuba 3's own `envmap` (pip Mitsuba 3.9.1, scalar_rgb):
/// `tests/data/mitsuba_envmap.csv`, written by `mitsuba_envmap.py` beside it, holds
/// Mitsuba's `eval` at 64 world directions for `sky.hdr` with a scale and a rotation.
/// (Mitsuba's sampling density is bilinear inside a grid cell and Irradia's constant,
/// with the same mass per cell, so densities are not compared point by point; the
/// chi-square test above checks Irradia's own.)
#[test]
fn envmap_radiance_is_mitsubas() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let sky = root.join("../scene/tests/data/emitters/sky.hdr");
    let map = EnvMap {
        image: Arc::new(irradia_core::io::load(&sky).unwrap()),
        scale: 1.5,
        to_world: Mat3::from_rotation_y(30f32.to_radians())
            * Mat3::from_rotation_x((-20f32).to_radians()),
        path: sky,
    };
    let csv = std::fs::read_to_string(root.join("tests/data/mitsuba_envmap.csv")).unwrap();
    let mut rows = 0;
    for line in csv
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("dx"))
    {
        let v: Vec<f32> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let d = Vec3::new(v[0], v[1], v[2]);
        let got = map.eval(d);
        for c in 0..3 {
            assert!(
                (got[c] - v[3 + c]).abs() <= 2e-4 * v[3 + c].abs().max(1.0),
                "direction {d}: channel {c} is {} but Mitsuba's is {}",
                got[c],
                v[3 + c]
            );
        }
        rows += 1;
    }
    assert_eq!(rows, 64);
}

/// Mitsuba's textured `area` emitter: an emissive rectangle (Mitsuba's, uv = ((x + 1) / 2,
/// (y + 1) / 2) in its own frame) lying on y = 0, scaled by 2, with a checkerboard for
/// its radiance. Light samples must carry the texture at the sampled point's uv (found
/// here from the point by inverting the transform), and a ray that hits it the texture
/// at the hit's uv; the constant `emission` (the texture's mean) must show nowhere.
#[test]
fn textured_emission_is_read_at_the_points_uv() {
    use glam::{Affine3A, Quat};
    use irradia_geometry::shapes::Rectangle;
    use irradia_scene::texture::{Checkerboard, TextureMap};
    let diff = |a: Rgb, b: Rgb| (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0f32, f32::max);
    let checker = Checkerboard {
        color0: Rgb::new(4.0, 0.5, 0.1),
        color1: Rgb::new(0.2, 1.0, 3.0),
        ..Checkerboard::default()
    };
    let map = TextureMap::Checkerboard(checker.clone());
    let material = irradia_scene::Material {
        emission: map.mean(),
        emission_texture: Some(map),
        ..path_common::diffuse(0.0, 0.0)
    };
    let to_world = Affine3A::from_scale_rotation_translation(
        Vec3::splat(2.0),
        Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2),
        Vec3::ZERO,
    );
    let inst = Instance::new(Arc::new(Rectangle::new()), to_world);
    let scene = Scene::new(
        path_common::camera(Vec3::new(0.0, 3.0, 5.0), Vec3::ZERO, 40.0),
        path_common::settings(8, 8, 1, Rgb::BLACK),
        vec![material],
        vec![],
        vec![object("rect", 0)],
        vec![inst],
    );
    let lights = LightSampler::new(&scene);
    let to_object = to_world.inverse();
    let expected = |q: Vec3| -> Option<Rgb> {
        let l = to_object.transform_point3(q);
        let uv = Vec2::new((l.x + 1.0) / 2.0, (l.y + 1.0) / 2.0);
        // Skip points on the checkerboard's cell borders.
        let near = |t: f32| (t - 0.5).abs() < 1e-3 || !(1e-3..=1.0 - 1e-3).contains(&t);
        (!near(uv.x) && !near(uv.y)).then(|| checker.eval(uv))
    };
    let p = Vec3::new(0.3, 1.5, -0.2);
    let (mut seen0, mut seen1) = (0, 0);
    for i in 0..16 {
        for j in 0..16 {
            let u = Vec2::new((i as f32 + 0.37) / 16.0, (j as f32 + 0.61) / 16.0);
            let s = lights.sample(&scene, p, 0.5, u).unwrap();
            let Some(want) = expected(s.target.unwrap()) else {
                continue;
            };
            assert!(diff(s.li, want) < 1e-5, "{:?} vs {want:?}", s.li);
            if want == checker.color0 {
                seen0 += 1;
            } else {
                seen1 += 1;
            }
        }
    }
    assert!(seen0 > 20 && seen1 > 20, "{seen0} {seen1}");
    // Rays straight down onto the rectangle see the texture at the hit.
    let params = PathParams {
        max_depth: 1,
        rr_depth: 5,
    };
    for (x, z) in [(0.7, 0.9), (-1.3, 0.4), (0.2, -1.6), (-0.5, -0.5)] {
        let q = Vec3::new(x, 0.0, z);
        let ray = Ray::new(q + Vec3::Y * 2.0, -Vec3::Y);
        let got = radiance(
            &scene,
            &lights,
            &params,
            ray,
            &mut Rng::new(1, 1),
            &mut PathCounters::default(),
        );
        let want = expected(q).unwrap();
        assert!(diff(got, want) < 1e-5, "{got:?} vs {want:?} at {q}");
    }
}
