//! Parametric surfaces: a parametric sphere (periodic seam and poles) is watertight and
//! matches the analytic sphere within the measured tessellation deviation, with exact
//! shading normals; a flat parametric patch hits where its plane does; spawned rays do
//! not re-hit; bad input is reported.

use irradia_core::{offset_ray_origin, Ray, Rng, Vec3};
use irradia_geometry::shapes::{ParametricError, ParametricSurface};
use irradia_geometry::Shape;
use std::f64::consts::PI;

fn sphere(res: (u32, u32)) -> ParametricSurface {
    ParametricSurface::parse(
        ["cos(u) * sin(v)", "cos(v)", "sin(u) * sin(v)"],
        (0.0, 2.0 * PI),
        (0.0, PI),
        res,
    )
    .unwrap()
}

fn random_dir(rng: &mut Rng) -> Vec3 {
    loop {
        let v = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - Vec3::ONE;
        if v.length_squared() > 0.01 && v.length_squared() <= 1.0 {
            return v.normalize();
        }
    }
}

#[test]
fn parametric_sphere_matches_the_unit_sphere_with_exact_normals() {
    let s = sphere((48, 24));
    let dev = s.max_deviation();
    assert!(dev > 0.0 && dev < 5e-3, "{dev}");
    let mut rng = Rng::new(2, 0);
    for _ in 0..500 {
        let o = random_dir(&mut rng) * 3.0;
        let target = random_dir(&mut rng) * 0.7;
        let ray = Ray::new(o, target - o);
        let h = s
            .intersect(&ray, f32::INFINITY)
            .expect("a chord through the middle hits");
        // On the tessellation: inside the sphere by at most the deviation.
        let r = h.point.length();
        assert!(r <= 1.0 + 1e-5 && r >= 1.0 - 2.0 * dev, "{r}");
        // The shading normal is the exact sphere normal at the refined parameters.
        assert!((h.shading_normal - h.point.normalize()).length() < 4.0 * dev);
        assert!(h.shading_normal.dot(h.normal) > 0.0 && h.normal.dot(h.point) > 0.0);
        let (u, v) = (h.uv.x as f64 * 2.0 * PI, h.uv.y as f64 * PI);
        let exact = s.point(u, v).as_vec3();
        assert!((exact - h.point).length() < 2.0 * dev);
    }
}

#[test]
fn seam_and_poles_are_watertight() {
    let s = sphere((12, 6));
    // Rays at the seam u = 0 = 2π (the xy half-plane x >= 0, z = 0) and at the poles.
    let mut cast = 0;
    // Points on the tessellated seam: between consecutive seam vertices (v = kπ/6).
    for k in 0..=60 {
        let (seg, frac) = (
            (k / 10).min(5),
            (k % 10) as f32 / 10.0 + if k == 60 { 1.0 } else { 0.0 },
        );
        let a = s.point(0.0, PI * seg as f64 / 6.0).as_vec3();
        let b = s.point(0.0, PI * (seg + 1) as f64 / 6.0).as_vec3();
        let q = a + (b - a) * frac;
        for tilt in [-0.3f32, 0.0, 0.3] {
            for dir in [q + Vec3::Z * tilt, -(q + Vec3::Z * tilt)] {
                let o = q - dir.normalize() * 3.0;
                let ray = Ray::new(o, q - o);
                cast += 1;
                let h = s
                    .intersect(&ray, f32::INFINITY)
                    .unwrap_or_else(|| panic!("ray through the seam at {q:?} missed"));
                assert!(h.t <= 1.0 + 1e-3);
            }
        }
    }
    assert!(cast > 300);
}

#[test]
fn a_flat_parametric_patch_hits_where_its_plane_does() {
    // z = 0.5 x + 0.25 y + 1 over u, v in [-1, 1], parametrised non-uniformly.
    let s = ParametricSurface::parse(
        ["u + 0.3 * u^3", "v", "0.5 * (u + 0.3 * u^3) + 0.25 * v + 1"],
        (-1.0, 1.0),
        (-1.0, 1.0),
        (7, 5),
    )
    .unwrap();
    let n = Vec3::new(-0.5, -0.25, 1.0).normalize();
    let d = 1.0 / Vec3::new(-0.5, -0.25, 1.0).length();
    let mut rng = Rng::new(8, 0);
    for _ in 0..300 {
        let o = Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, 6.0);
        let target = Vec3::new(rng.next_f32() * 2.2 - 1.1, rng.next_f32() * 1.6 - 0.8, 0.0);
        let ray = Ray::new(o, target - o);
        let t_plane = (d - n.dot(o)) / n.dot(ray.dir);
        let p = ray.at(t_plane);
        if p.x.abs() < 1.29 && p.y.abs() < 0.99 {
            let h = s
                .intersect(&ray, f32::INFINITY)
                .expect("hit inside the patch");
            assert!((h.t - t_plane).abs() < 1e-5 * t_plane);
            assert!((h.shading_normal - n).length() < 1e-5 && (h.normal - n).length() < 1e-5);
            // Exact parameters despite the cubic parametrisation: y = v, x = u + 0.3u³.
            let (u, v) = (h.uv.x * 2.0 - 1.0, h.uv.y * 2.0 - 1.0);
            assert!((v - p.y).abs() < 1e-4 && (u + 0.3 * u * u * u - p.x).abs() < 1e-4);
        } else if p.x.abs() > 1.31 || p.y.abs() > 1.01 {
            assert!(s.intersect(&ray, f32::INFINITY).is_none());
        }
    }
}

#[test]
fn spawned_rays_never_rehit_at_their_origin() {
    // A torus, parametrically.
    let s = ParametricSurface::parse(
        [
            "(1 + 0.3 * cos(v)) * cos(u)",
            "0.3 * sin(v)",
            "(1 + 0.3 * cos(v)) * sin(u)",
        ],
        (0.0, 2.0 * PI),
        (0.0, 2.0 * PI),
        (64, 24),
    )
    .unwrap();
    let mut rng = Rng::new(12, 0);
    let mut hits = 0;
    for _ in 0..600 {
        let o = random_dir(&mut rng) * 3.0;
        let ray = Ray::new(o, random_dir(&mut rng) * 1.1 - o);
        let Some(h) = s.intersect(&ray, f32::INFINITY) else {
            continue;
        };
        hits += 1;
        let n = h.normal;
        let refl = ray.dir - 2.0 * ray.dir.dot(n) * n;
        let side = if ray.dir.dot(n) < 0.0 { n } else { -n };
        for (off, dir) in [(side, refl), (-side, ray.dir)] {
            let spawned = Ray::new(offset_ray_origin(h.point, off, h.error), dir);
            if let Some(h2) = s.intersect(&spawned, f32::INFINITY) {
                assert!(h2.t * dir.length() > 1e-4, "re-hit at t = {}", h2.t);
            }
        }
    }
    assert!(hits > 100);
}

#[test]
fn bad_input_is_reported() {
    let e =
        ParametricSurface::parse(["u", "v +", "0"], (0.0, 1.0), (0.0, 1.0), (4, 4)).unwrap_err();
    assert!(e.to_string().starts_with("y(u, v): column 4"), "{e}");
    let e = ParametricSurface::parse(["u", "v", "x"], (0.0, 1.0), (0.0, 1.0), (4, 4)).unwrap_err();
    assert!(
        matches!(
            e,
            ParametricError::Expr {
                coordinate: "z",
                ..
            }
        ),
        "{e}"
    );
    let e = ParametricSurface::parse(["u", "v", "0"], (1.0, 1.0), (0.0, 1.0), (4, 4)).unwrap_err();
    assert!(matches!(e, ParametricError::BadRange { which: "u", .. }));
    let e =
        ParametricSurface::parse(["u", "v", "0"], (0.0, 1.0), (0.0, f64::NAN), (4, 4)).unwrap_err();
    assert!(matches!(e, ParametricError::BadRange { which: "v", .. }));
    let e = ParametricSurface::parse(["u", "v", "0"], (0.0, 1.0), (0.0, 1.0), (0, 4)).unwrap_err();
    assert!(matches!(e, ParametricError::BadResolution(0, 4)));
    let e =
        ParametricSurface::parse(["log(u)", "v", "0"], (0.0, 1.0), (0.0, 1.0), (4, 4)).unwrap_err();
    assert!(matches!(e, ParametricError::NotFinite { .. }), "{e}");
}
