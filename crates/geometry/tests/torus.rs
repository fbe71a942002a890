//! Torus: roots against closed forms at many scales, spans, the quartic solvers against
//! each other, and spawned rays that never re-hit at their origin.

use irradia_core::{offset_ray_origin, Ray, Rng, Vec3};
use irradia_geometry::roots::{real_roots_in, solve_quartic, Polynomial};
use irradia_geometry::shapes::Torus;
use irradia_geometry::{Shape, Span};

const SCALES: [f32; 6] = [1e-3, 1e-1, 1.0, 10.0, 1e3, 1e5];

fn rel_close(a: f32, b: f32, tol: f32) -> bool {
    (a - b).abs() <= tol * a.abs().max(b.abs()).max(1e-30)
}

#[test]
fn equatorial_ray_hits_the_four_known_roots_at_every_scale() {
    for &s in &SCALES {
        let (big_r, r) = (2.0 * s, 0.5 * s);
        let torus = Torus::new(big_r, r);
        // From x = -5s along +x through the centre: walls at x = ±(R+r), ±(R-r).
        let ray = Ray::new(Vec3::new(-5.0 * s, 0.0, 0.0), Vec3::X);
        let want = [5.0 * s - (big_r + r), 5.0 * s - (big_r - r)];
        let h = torus.intersect(&ray, f32::INFINITY).expect("hit");
        assert!(
            rel_close(h.t, want[0], 1e-6),
            "scale {s}: t {} want {}",
            h.t,
            want[0]
        );
        assert!((h.normal - -Vec3::X).length() < 1e-5);
        let mut spans = Vec::new();
        torus.spans(&ray, &mut spans);
        assert_eq!(spans.len(), 2, "scale {s}");
        let wants = [
            (5.0 * s - (big_r + r), 5.0 * s - (big_r - r)),
            (5.0 * s + (big_r - r), 5.0 * s + (big_r + r)),
        ];
        for (sp, w) in spans.iter().zip(wants) {
            assert!(rel_close(sp.enter.t, w.0, 1e-6) && rel_close(sp.exit.t, w.1, 1e-6));
            assert!(sp.enter.normal.dot(ray.dir) < 0.0 && sp.exit.normal.dot(ray.dir) > 0.0);
        }
        // From inside the hole the first hit is the inner wall at x = R - r.
        let ray = Ray::new(Vec3::ZERO, Vec3::X);
        let h = torus.intersect(&ray, f32::INFINITY).unwrap();
        assert!(rel_close(h.t, big_r - r, 1e-6));
        assert!((h.normal - -Vec3::X).length() < 1e-5);
    }
}

#[test]
fn rays_along_the_axis_direction() {
    for &s in &SCALES {
        let (big_r, r) = (3.0 * s, 1.0 * s);
        let torus = Torus::new(big_r, r);
        // The axis itself goes through the hole.
        let ray = Ray::new(Vec3::new(0.0, 10.0 * s, 0.0), -Vec3::Y);
        assert!(torus.intersect(&ray, f32::INFINITY).is_none());
        let mut spans = Vec::new();
        torus.spans(&ray, &mut spans);
        assert!(spans.is_empty());
        // Parallel to the axis at distance R + r/2 from it: the tube's circle gives
        // y = ±sqrt(r² - (r/2)²).
        let x = big_r + 0.5 * r;
        let y = (r * r - 0.25 * r * r).sqrt();
        let ray = Ray::new(Vec3::new(x, 10.0 * s, 0.0), -Vec3::Y);
        let h = torus.intersect(&ray, f32::INFINITY).unwrap();
        assert!(rel_close(h.t, 10.0 * s - y, 1e-6), "scale {s}");
        let n_want = Vec3::new(0.5, y / r, 0.0).normalize();
        assert!((h.normal - n_want).length() < 1e-5);
        // Through the middle of the tube: tangent to nothing, one span of length 2r.
        let ray = Ray::new(Vec3::new(0.0, 10.0 * s, -big_r), -Vec3::Y * 2.0);
        let mut spans = Vec::new();
        torus.spans(&ray, &mut spans);
        assert_eq!(spans.len(), 1);
        assert!(rel_close(spans[0].exit.t - spans[0].enter.t, r, 1e-5));
    }
}

#[test]
fn isolating_and_closed_form_quartic_solvers_agree() {
    let mut rng = Rng::new(7, 0);
    for _ in 0..2000 {
        let roots: Vec<f64> = (0..4)
            .map(|_| (rng.next_f32() as f64 - 0.5) * 20.0)
            .collect();
        // Expand (x - r0)(x - r1)(x - r2)(x - r3), ascending coefficients.
        let mut c = vec![1.0];
        for &r in &roots {
            let mut n = vec![0.0; c.len() + 1];
            for (i, &ci) in c.iter().enumerate() {
                n[i + 1] += ci;
                n[i] -= r * ci;
            }
            c = n;
        }
        let mut iso = Vec::new();
        real_roots_in(&Polynomial::new(&c), -20.0, 20.0, &mut iso);
        let ferrari = solve_quartic(c[3], c[2], c[1], c[0]);
        let mut sorted = roots.clone();
        sorted.sort_by(f64::total_cmp);
        // Roots closer than 1e-4 are ill-conditioned for the closed form; skip those.
        if sorted.windows(2).any(|w| w[1] - w[0] < 1e-3) {
            continue;
        }
        assert_eq!(iso.len(), 4, "{sorted:?} -> {iso:?}");
        assert_eq!(ferrari.len(), 4, "{sorted:?} -> {ferrari:?}");
        for k in 0..4 {
            assert!((iso[k] - sorted[k]).abs() < 1e-9, "{sorted:?} {iso:?}");
            assert!(
                (ferrari[k] - sorted[k]).abs() < 1e-7,
                "{sorted:?} {ferrari:?}"
            );
        }
    }
}

fn random_dir(rng: &mut Rng) -> Vec3 {
    loop {
        let v = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - Vec3::ONE;
        if v.length_squared() > 0.01 && v.length_squared() <= 1.0 {
            return v.normalize();
        }
    }
}

/// Distance from `p` to the torus surface.
fn torus_distance(p: Vec3, big_r: f32, r: f32) -> f32 {
    let q = glam::Vec2::new(glam::Vec2::new(p.x, p.z).length() - big_r, p.y);
    q.length() - r
}

#[test]
fn random_hits_lie_on_the_surface_and_spans_alternate() {
    let mut rng = Rng::new(11, 0);
    for &s in &SCALES {
        let torus = Torus::new(1.0 * s, 0.3 * s);
        let mut hits = 0;
        for _ in 0..500 {
            let o = random_dir(&mut rng) * 3.0 * s;
            let target = (Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5)
                * Vec3::new(2.6, 0.6, 2.6)
                * s;
            let ray = Ray::new(o, (target - o) * 0.37);
            if let Some(h) = torus.intersect(&ray, f32::INFINITY) {
                hits += 1;
                assert!(torus_distance(h.point, s, 0.3 * s).abs() < 1e-5 * s);
                assert!((ray.at(h.t) - h.point).length() < 1e-5 * s);
            }
            let mut spans: Vec<Span> = Vec::new();
            torus.spans(&ray, &mut spans);
            for w in spans.windows(2) {
                assert!(w[0].exit.t <= w[1].enter.t);
            }
            for sp in &spans {
                assert!(sp.enter.t <= sp.exit.t);
                let mid = ray.at(0.5 * (sp.enter.t + sp.exit.t));
                assert!(torus_distance(mid, s, 0.3 * s) < 1e-5 * s);
            }
        }
        assert!(hits > 100, "scale {s}: only {hits} hits");
    }
}

#[test]
fn spawned_rays_never_rehit_at_their_origin() {
    let mut rng = Rng::new(3, 0);
    for &s in &SCALES {
        let torus = Torus::new(1.0 * s, 0.25 * s);
        for _ in 0..400 {
            let o = random_dir(&mut rng) * 3.0 * s;
            let ray = Ray::new(o, (random_dir(&mut rng) * 0.8 * s - o).normalize());
            let Some(h) = torus.intersect(&ray, f32::INFINITY) else {
                continue;
            };
            let n = h.normal;
            // Reflected (leaves outward) and transmitted (leaves inward) rays.
            let refl = ray.dir - 2.0 * ray.dir.dot(n) * n;
            for (side, dir) in [(n, refl), (-n, ray.dir)] {
                let origin = offset_ray_origin(h.point, side, h.error);
                let spawned = Ray::new(origin, dir);
                if let Some(h2) = torus.intersect(&spawned, f32::INFINITY) {
                    assert!(
                        h2.t > 1e-3 * s,
                        "scale {s}: re-hit at t = {} (from {:?})",
                        h2.t,
                        h.point
                    );
                }
            }
        }
    }
}
