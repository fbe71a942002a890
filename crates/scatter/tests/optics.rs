//! The optics module against closed forms: Snell's law, total internal reflection at
//! the critical angle, Fresnel at normal incidence, Brewster's angle and grazing
//! incidence, Stokes reciprocity, and the conductor Fresnel against a direct evaluation
//! of the complex s and p amplitudes (Born and Wolf §14.2). The first tests are those of
//! the former world-space `irradia_render::optics`, in the local frame.

use glam::Vec3;
use irradia_scatter::optics::*;

/// A direction away from the surface on the outside at angle `theta` from +z.
fn out_at(theta: f32) -> Vec3 {
    Vec3::new(theta.sin(), 0.0, theta.cos())
}

#[test]
fn snell_law_holds_for_every_angle_below_critical() {
    // (exterior, interior) indices; light arrives from outside (wo.z > 0) or inside.
    for &(n_ext, n_int) in &[(1.0f32, 1.5f32), (1.5, 1.0), (1.33, 2.4), (1.0, 1.0)] {
        let eta = n_int / n_ext;
        for side in [1.0f32, -1.0] {
            let (n1, n2) = if side > 0.0 {
                (n_ext, n_int)
            } else {
                (n_int, n_ext)
            };
            for k in 0..90 {
                let theta = (k as f32).to_radians();
                let w = out_at(theta) * Vec3::new(1.0, 1.0, side);
                let f = fresnel_dielectric(w.z, eta);
                assert!(
                    (f.eta_it - n2 / n1).abs() < 1e-6 && (f.eta_ti * f.eta_it - 1.0).abs() < 1e-6
                );
                if f.reflectance < 1.0 {
                    let t = refract(w, f.cos_theta_t, f.eta_ti);
                    assert!((t.length() - 1.0).abs() < 1e-5);
                    assert!(t.z * w.z < 0.0, "goes through");
                    let sin_t = (t.x * t.x + t.y * t.y).sqrt();
                    assert!(
                        (n1 * theta.sin() - n2 * sin_t).abs() < 1e-5,
                        "n1 sin θ1 = n2 sin θ2 at {k} deg, {n1}->{n2}"
                    );
                    assert_eq!(
                        snell_sin_t(theta.sin(), n1, n2).map(|s| (s - sin_t).abs() < 1e-5),
                        Some(true)
                    );
                    assert!(
                        t.x * w.x <= 0.0,
                        "continues on the other side of the normal"
                    );
                    assert!(t.y.abs() < 1e-6);
                } else {
                    let crit = critical_angle(n1, n2).expect("TIR only into a less dense medium");
                    assert!(theta > crit - 1e-4, "TIR at {k} deg below critical {crit}");
                    assert!(snell_sin_t(theta.sin(), n1, n2).is_none() || theta - crit < 1e-3);
                }
            }
        }
    }
}

#[test]
fn total_internal_reflection_starts_at_the_critical_angle() {
    let (n1, n2) = (1.5f32, 1.0f32);
    let crit = critical_angle(n1, n2).unwrap();
    assert!((crit - (1.0f32 / 1.5).asin()).abs() < 1e-7);
    assert!((crit.to_degrees() - 41.8103).abs() < 1e-3);
    // Inside glass (eta = 1.5 interior/exterior), going out: w.z < 0.
    let inside = |theta: f32| out_at(theta) * Vec3::new(1.0, 1.0, -1.0);
    let below = fresnel_dielectric(inside(crit - 1e-3).z, 1.5);
    let above = fresnel_dielectric(inside(crit + 1e-3).z, 1.5);
    assert!(
        below.reflectance < 1.0,
        "just below the critical angle light leaves"
    );
    let grazing = refract(inside(crit - 1e-3), below.cos_theta_t, below.eta_ti);
    assert!(
        grazing.z > 0.0 && grazing.z < 0.1,
        "and leaves almost parallel to the surface"
    );
    assert_eq!(above.reflectance, 1.0, "just above it is totally reflected");
    assert!(critical_angle(1.0, 1.5).is_none());
}

#[test]
fn fresnel_matches_closed_forms() {
    // Normal incidence: ((n1 - n2) / (n1 + n2))^2 = 0.04 for glass, from either side.
    assert!((fresnel_dielectric(1.0, 1.5).reflectance - 0.04).abs() < 1e-6);
    assert!((fresnel_dielectric(-1.0, 1.5).reflectance - 0.04).abs() < 1e-6);
    // Brewster's angle: p-polarised reflectance vanishes, so R = r_s^2 / 2.
    let brewster = 1.5f32.atan();
    let r = fresnel_dielectric(brewster.cos(), 1.5).reflectance;
    let theta_t = (brewster.sin() / 1.5).asin();
    let rs = (brewster - theta_t).sin() / (brewster + theta_t).sin();
    assert!((r - 0.5 * rs * rs).abs() < 1e-5);
    // Grazing incidence reflects everything.
    assert!(fresnel_dielectric(1e-4, 1.5).reflectance > 0.999);
    assert_eq!(fresnel_dielectric(0.0, 1.5).reflectance, 1.0);
    // Index-matched media do not reflect.
    assert_eq!(fresnel_dielectric(0.3, 1.0).reflectance, 0.0);
    // Stokes reciprocity of the refracted pair: R(θi, n1→n2) = R(θt, n2→n1).
    let ti = 0.7f32;
    let f = fresnel_dielectric(ti.cos(), 1.5);
    let back = fresnel_dielectric(f.cos_theta_t, 1.5);
    assert!((f.reflectance - back.reflectance).abs() < 1e-5);
    assert!((back.cos_theta_t - ti.cos()).abs() < 1e-5);
}

#[test]
fn reflection_keeps_the_angle() {
    let w = out_at(0.4);
    let r = reflect(w);
    assert!((r.z - 0.4f32.cos()).abs() < 1e-6 && (r.x + w.x).abs() < 1e-6);
    let m = Vec3::new(0.3, -0.2, 0.9).normalize();
    let rm = reflect_about(w, m);
    assert!((rm.dot(m) - w.dot(m)).abs() < 1e-6 && ((rm + w).normalize() - m).length() < 1e-5);
}

#[test]
fn microfacet_refraction_obeys_snell_about_m() {
    let m = Vec3::new(0.3, -0.2, 0.9).normalize();
    let w = Vec3::new(-0.5, 0.4, 0.6).normalize();
    let f = fresnel_dielectric(w.dot(m), 1.5);
    let t = refract_about(w, m, f.cos_theta_t, f.eta_ti);
    assert!((t.length() - 1.0).abs() < 1e-5);
    let sin_i = w.cross(m).length();
    let sin_t = t.cross(m).length();
    assert!((sin_i - 1.5 * sin_t).abs() < 1e-5 && t.dot(m) < 0.0);
    // The generalised half vector of the pair is m (Walter et al. 2007, eq. 16).
    let h = -(w + 1.5 * t).normalize();
    assert!((h - m).length() < 1e-4 || (h + m).length() < 1e-4);
}

/// |r|² for the s and p amplitudes of a complex index, computed directly with complex
/// arithmetic: r_s = (cos i - n̂ cos t)/(cos i + n̂ cos t), r_p = (n̂ cos i - cos t)/(n̂ cos i + cos t),
/// n̂ cos t = sqrt(n̂² - sin² i).
fn conductor_reference(cos_i: f64, eta: f64, k: f64) -> f64 {
    type C = (f64, f64);
    let mul = |a: C, b: C| (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
    let div = |a: C, b: C| {
        let d = b.0 * b.0 + b.1 * b.1;
        ((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
    };
    let sqrt = |a: C| {
        let r = (a.0 * a.0 + a.1 * a.1).sqrt();
        let re = ((r + a.0) / 2.0).sqrt();
        let im = ((r - a.0) / 2.0).sqrt().copysign(a.1);
        (re, im)
    };
    let n = (eta, k);
    let sin2 = 1.0 - cos_i * cos_i;
    let n2 = mul(n, n);
    let n_cos_t = sqrt((n2.0 - sin2, n2.1));
    let rs = div(
        (cos_i - n_cos_t.0, -n_cos_t.1),
        (cos_i + n_cos_t.0, n_cos_t.1),
    );
    // n̂ cos t = sqrt(n̂² - sin²), so cos t = n_cos_t / n̂; r_p = (n̂² cos i - n̂ cos t)/(n̂² cos i + n̂ cos t).
    let a = (n2.0 * cos_i, n2.1 * cos_i);
    let rp = div(
        (a.0 - n_cos_t.0, a.1 - n_cos_t.1),
        (a.0 + n_cos_t.0, a.1 + n_cos_t.1),
    );
    0.5 * (rs.0 * rs.0 + rs.1 * rs.1 + rp.0 * rp.0 + rp.1 * rp.1)
}

#[test]
fn conductor_fresnel_is_the_exact_complex_fresnel() {
    for &(eta, k) in &[
        (0.143f32, 3.983f32),
        (1.1, 2.6),
        (0.2, 0.0),
        (2.5, 0.3),
        (1.5, 0.0),
    ] {
        for i in 0..=50 {
            let cos_i = i as f64 / 50.0;
            let got = fresnel_conductor(cos_i as f32, eta, k) as f64;
            let want = conductor_reference(cos_i.max(1e-12), eta as f64, k as f64);
            assert!(
                (got - want).abs() < 1e-5,
                "eta {eta} k {k} cos {cos_i}: {got} vs {want}"
            );
        }
    }
    // k = 0 is a dielectric (outside, below the critical angle).
    let d = fresnel_dielectric(0.6, 1.5).reflectance;
    assert!((fresnel_conductor(0.6, 1.5, 0.0) - d).abs() < 1e-6);
    // Mitsuba's "none": eta 0, k 1 is a perfect mirror.
    for c in [0.0f32, 0.3, 1.0] {
        assert!((fresnel_conductor(c, 0.0, 1.0) - 1.0).abs() < 1e-6);
    }
}

/// The world-space refraction the Whitted tracer and the two-pass display use: a ray
/// `d` arriving against the normal `n` of its side, `eta = n1 / n2`, refracts to
/// `eta d + (eta cos θi - cos θt) n` (the former `irradia_render::optics::refract`,
/// written out here), also for a shading normal slightly behind the ray.
#[test]
fn refract_through_is_the_world_space_snell_refraction() {
    let mut rng = irradia_core::Rng::new(9, 2);
    for _ in 0..2000 {
        let n = rng.next_centered_vec3().normalize();
        let d = rng.next_centered_vec3().normalize();
        let d = if d.dot(n) > 0.05 { -d } else { d };
        let eta = [1.0 / 1.5, 1.5, 1.33, 1.0][rng.below(4) as usize];
        let cos_i = -d.dot(n);
        let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
        let expect = (sin2_t <= 1.0)
            .then(|| (eta * d + (eta * cos_i - (1.0 - sin2_t).sqrt()) * n).normalize());
        let got = refract_through(-d, n, 1.0 / eta);
        match (got, expect) {
            (Some(g), Some(e)) => assert!((g - e).length() < 1e-5, "{g:?} vs {e:?}"),
            (None, None) => {}
            (g, e) => assert!((sin2_t - 1.0).abs() < 1e-5, "TIR disagrees: {g:?} vs {e:?}"),
        }
    }
}
