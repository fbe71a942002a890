//! Implicit surfaces: the implicit sphere against the analytic one (both root finders),
//! thin features that must not be skipped, the too-small Lipschitz warning, and spawned
//! rays that never re-hit at their origin.

use irradia_core::{offset_ray_origin, Aabb, Ray, Rng, Vec3};
use irradia_geometry::shapes::{ImplicitError, ImplicitSurface, Sphere};
use irradia_geometry::{Shape, Span};

fn cube(h: f32) -> Aabb {
    Aabb::new(Vec3::splat(-h), Vec3::splat(h))
}

fn random_dir(rng: &mut Rng) -> Vec3 {
    loop {
        let v = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - Vec3::ONE;
        if v.length_squared() > 0.01 && v.length_squared() <= 1.0 {
            return v.normalize();
        }
    }
}

/// A ray from outside the box towards a random point near the centre.
fn random_ray(rng: &mut Rng, reach: f32) -> Ray {
    let o = random_dir(rng) * 4.0;
    let target = (Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5) * 2.0 * reach;
    Ray::new(o, (target - o) * 0.5)
}

fn check_against_sphere(surface: &ImplicitSurface) {
    let sphere = Sphere::new(Vec3::ZERO, 1.0);
    let mut rng = Rng::new(5, 0);
    let mut hits = 0;
    for _ in 0..400 {
        let ray = random_ray(&mut rng, 1.2);
        // Skip near-tangent rays, where a miss and a grazing hit are both right.
        let dn = ray.dir.normalize();
        let closest = (ray.origin - dn * ray.origin.dot(dn)).length();
        if (closest - 1.0).abs() < 1e-3 {
            continue;
        }
        let a = sphere.intersect(&ray, f32::INFINITY);
        let b = surface.intersect(&ray, f32::INFINITY);
        match (a, b) {
            (None, None) => {}
            (Some(a), Some(b)) => {
                hits += 1;
                assert!((a.t - b.t).abs() < 1e-5 * a.t, "t {} vs {}", a.t, b.t);
                assert!((a.point - b.point).length() < 1e-5);
                assert!((a.normal - b.normal).length() < 1e-5);
                assert!(b.error > 0.0 && b.error < 1e-5, "error {}", b.error);
            }
            (a, b) => panic!("analytic {a:?} vs implicit {b:?} for {ray:?}"),
        }
        let (mut sa, mut sb): (Vec<Span>, Vec<Span>) = (Vec::new(), Vec::new());
        sphere.spans(&ray, &mut sa);
        surface.spans(&ray, &mut sb);
        assert_eq!(sa.len(), sb.len());
        for (x, y) in sa.iter().zip(&sb) {
            assert!((x.enter.t - y.enter.t).abs() < 1e-5 && (x.exit.t - y.exit.t).abs() < 1e-5);
            assert!((x.exit.normal - y.exit.normal).length() < 1e-5);
        }
    }
    assert!(hits > 100, "only {hits} hits");
}

#[test]
fn implicit_sphere_matches_the_analytic_sphere_with_intervals() {
    let s = ImplicitSurface::parse("x^2 + y^2 + z^2 - 1", cube(1.5)).unwrap();
    check_against_sphere(&s);
}

#[test]
fn implicit_sphere_matches_the_analytic_sphere_with_sphere_tracing() {
    // |grad f| = 2|p| <= 2 * 1.5 * sqrt(3) < 5.2 in the box.
    let s = ImplicitSurface::parse("x^2 + y^2 + z^2 - 1", cube(1.5))
        .unwrap()
        .with_lipschitz(5.2)
        .unwrap();
    check_against_sphere(&s);
    assert_eq!(s.lipschitz_violation(), None);
    assert_eq!(s.take_lipschitz_warning(), None);
}

#[test]
fn a_thin_slab_is_never_skipped() {
    // |x| - 0.001: a slab 0.002 thick, 1/1000 of the box.
    let interval = ImplicitSurface::parse("abs(x) - 0.001", cube(1.0)).unwrap();
    let traced = ImplicitSurface::parse("abs(x) - 0.001", cube(1.0))
        .unwrap()
        .with_lipschitz(1.0)
        .unwrap();
    let mut rng = Rng::new(9, 0);
    for _ in 0..300 {
        // From the x < 0 side to the x > 0 side, crossing the slab inside the box.
        let o = Vec3::new(-0.9, rng.next_f32() * 1.6 - 0.8, rng.next_f32() * 1.6 - 0.8);
        let e = Vec3::new(0.9, rng.next_f32() * 1.6 - 0.8, rng.next_f32() * 1.6 - 0.8);
        let ray = Ray::new(o, e - o);
        let want_t = (-0.001 - o.x) / (e.x - o.x);
        for s in [&interval, &traced] {
            let h = s.intersect(&ray, f32::INFINITY).expect("thin slab skipped");
            assert!((h.t - want_t).abs() < 1e-5, "{} vs {want_t}", h.t);
            assert!((h.normal - -Vec3::X).length() < 1e-5);
            let mut spans = Vec::new();
            s.spans(&ray, &mut spans);
            assert_eq!(spans.len(), 1);
            assert!((spans[0].exit.t - spans[0].enter.t - 0.002 / (e.x - o.x)).abs() < 1e-5);
        }
    }
}

#[test]
fn a_thin_shell_is_never_skipped() {
    // A spherical shell of radius 0.5 and thickness 0.001.
    let s = ImplicitSurface::parse("abs(x^2 + y^2 + z^2 - 0.25) - 0.0005", cube(1.0)).unwrap();
    let mut rng = Rng::new(13, 0);
    let mut hits = 0;
    for _ in 0..300 {
        let ray = random_ray(&mut rng, 0.4);
        let dn = ray.dir.normalize();
        let closest = (ray.origin - dn * ray.origin.dot(dn)).length();
        if closest > 0.49 {
            continue;
        }
        hits += 1;
        let h = s
            .intersect(&ray, f32::INFINITY)
            .expect("thin shell skipped");
        assert!(
            (h.point.length() - 0.5).abs() < 0.0011,
            "{}",
            h.point.length()
        );
        let mut spans = Vec::new();
        s.spans(&ray, &mut spans);
        assert_eq!(spans.len(), 2, "a chord through a shell crosses it twice");
    }
    assert!(hits > 100);
}

#[test]
fn a_too_small_lipschitz_bound_is_reported_once() {
    let s = ImplicitSurface::parse("x^2 + y^2 + z^2 - 1", cube(1.5))
        .unwrap()
        .with_lipschitz(0.5)
        .unwrap();
    assert_eq!(s.lipschitz_violation(), None);
    let mut rng = Rng::new(1, 0);
    for _ in 0..50 {
        s.intersect(&random_ray(&mut rng, 1.0), f32::INFINITY);
    }
    let ratio = s.lipschitz_violation().expect("violation recorded");
    assert!(ratio > 0.5 && ratio <= 5.2, "{ratio}");
    let msg = s.take_lipschitz_warning().expect("first warning");
    assert!(msg.contains("Lipschitz bound 0.5 is too small"), "{msg}");
    assert_eq!(s.take_lipschitz_warning(), None, "warned only once");
}

#[test]
fn spawned_rays_never_rehit_at_their_origin() {
    // A torus (R = 0.6, r = 0.25) written implicitly: a curved, non-convex surface.
    // |grad f| <= 4 (|p|² + R² - r²) |p| + 8 R² |p| < 30 in the box.
    let src = "(x^2 + y^2 + z^2 + 0.6^2 - 0.25^2)^2 - 4 * 0.6^2 * (x^2 + z^2)";
    let interval = ImplicitSurface::parse(src, cube(1.0)).unwrap();
    let traced = ImplicitSurface::parse(src, cube(1.0))
        .unwrap()
        .with_lipschitz(30.0)
        .unwrap();
    let mut rng = Rng::new(21, 0);
    for s in [&interval, &traced] {
        let mut hits = 0;
        for _ in 0..300 {
            let ray = random_ray(&mut rng, 0.8);
            let Some(h) = s.intersect(&ray, f32::INFINITY) else {
                continue;
            };
            hits += 1;
            let n = h.normal;
            let refl = ray.dir - 2.0 * ray.dir.dot(n) * n;
            for (side, dir) in [(n, refl), (-n, ray.dir)] {
                let spawned = Ray::new(offset_ray_origin(h.point, side, h.error), dir);
                if let Some(h2) = s.intersect(&spawned, f32::INFINITY) {
                    assert!(h2.t * dir.length() > 1e-4, "re-hit at t = {}", h2.t);
                }
            }
        }
        assert!(hits > 50);
        assert_eq!(s.lipschitz_violation(), None);
    }
}

#[test]
fn bad_input_is_reported() {
    let e = ImplicitSurface::parse("x^2 + ", cube(1.0)).unwrap_err();
    assert!(
        matches!(&e, ImplicitError::Expr(err) if err.column == 7),
        "{e}"
    );
    assert!(e.to_string().contains("column 7"));
    let e = ImplicitSurface::parse("x + w", cube(1.0)).unwrap_err();
    assert!(e.to_string().contains("unknown name 'w'"));
    let flat = Aabb::new(Vec3::ZERO, Vec3::new(1.0, 0.0, 1.0));
    assert!(matches!(
        ImplicitSurface::parse("x", flat),
        Err(ImplicitError::BadBounds { .. })
    ));
    assert!(matches!(
        ImplicitSurface::parse("x", Aabb::INFINITE),
        Err(ImplicitError::BadBounds { .. })
    ));
    let s = ImplicitSurface::parse("x", cube(1.0)).unwrap();
    assert!(matches!(
        s.with_lipschitz(-1.0),
        Err(ImplicitError::BadLipschitz(_))
    ));
}
