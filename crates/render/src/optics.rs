//! Geometric optics of a smooth interface: mirror reflection, refraction by Snell's law,
//! total internal reflection and the Fresnel equations for dielectrics (lecture:
//! "Reflection and Transmission").
//!
//! Conventions: `d` is the incoming direction (travelling towards the surface), `n` the
//! unit normal on the side the ray comes from (`d · n < 0`), `eta = n1 / n2` the ratio of
//! the index of the medium the ray is in to that of the medium it enters.

use glam::Vec3;

/// Mirror reflection of direction `d` about the unit normal `n`: `d - 2 (d·n) n`.
#[inline]
pub fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - 2.0 * d.dot(n) * n
}

/// Refraction of the unit direction `d` through a surface with unit normal `n` facing
/// the incoming ray (`d·n <= 0`), with `eta = n1 / n2`. Snell's law
/// `n1 sin θ1 = n2 sin θ2`; returns `None` on total internal reflection
/// (`eta sin θ1 > 1`). The result is a unit vector.
#[inline]
pub fn refract(d: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = -d.dot(n);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t > 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((eta * d + (eta * cos_i - cos_t) * n).normalize())
}

/// The critical angle (radians) beyond which light going from index `n1` into a less
/// dense medium `n2 < n1` is totally reflected: `asin(n2 / n1)`. `None` when `n2 >= n1`.
pub fn critical_angle(n1: f32, n2: f32) -> Option<f32> {
    (n2 < n1).then(|| (n2 / n1).asin())
}

/// Unpolarised Fresnel reflectance of a dielectric interface for incidence cosine
/// `cos_i` (>= 0) and `eta = n1 / n2`: the mean of the s and p reflectances. 1 under
/// total internal reflection.
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    // r_s = (n1 cos_i - n2 cos_t)/(n1 cos_i + n2 cos_t), divided through by n2.
    let rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (rs * rs + rp * rp)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir_at(theta: f32) -> Vec3 {
        // Coming down onto the plane z = 0 (normal +z) at angle theta from the normal.
        Vec3::new(theta.sin(), 0.0, -theta.cos())
    }

    #[test]
    fn snell_law_holds_for_every_angle_below_critical() {
        for &(n1, n2) in &[(1.0f32, 1.5f32), (1.5, 1.0), (1.33, 2.4), (1.0, 1.0)] {
            let eta = n1 / n2;
            for k in 0..90 {
                let theta = (k as f32).to_radians();
                let d = dir_at(theta);
                match refract(d, Vec3::Z, eta) {
                    Some(t) => {
                        assert!((t.length() - 1.0).abs() < 1e-5);
                        assert!(t.z < 0.0, "transmitted ray continues through");
                        let sin_t = (t.x * t.x + t.y * t.y).sqrt();
                        assert!(
                            (n1 * theta.sin() - n2 * sin_t).abs() < 1e-5,
                            "n1 sin θ1 = n2 sin θ2 at {k} deg, {n1}->{n2}"
                        );
                        assert!(
                            t.x * d.x >= 0.0,
                            "stays in the plane of incidence, same side"
                        );
                        assert!(t.y.abs() < 1e-6);
                    }
                    None => {
                        let crit =
                            critical_angle(n1, n2).expect("TIR only into a less dense medium");
                        assert!(theta > crit - 1e-4, "TIR at {k} deg below critical {crit}");
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
        let below = refract(dir_at(crit - 1e-3), Vec3::Z, n1 / n2);
        let above = refract(dir_at(crit + 1e-3), Vec3::Z, n1 / n2);
        assert!(
            below.is_some(),
            "just below the critical angle light leaves"
        );
        let grazing = below.unwrap();
        assert!(
            grazing.z.abs() < 0.1,
            "and leaves almost parallel to the surface"
        );
        assert!(above.is_none(), "just above it is totally reflected");
        assert_eq!(fresnel_dielectric((crit + 1e-3).cos(), n1 / n2), 1.0);
        assert!(critical_angle(1.0, 1.5).is_none());
    }

    #[test]
    fn fresnel_matches_closed_forms() {
        // Normal incidence: ((n1 - n2) / (n1 + n2))^2 = 0.04 for glass.
        assert!((fresnel_dielectric(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
        // Brewster's angle: p-polarised reflectance vanishes, so R = r_s^2 / 2.
        let brewster = 1.5f32.atan();
        let r = fresnel_dielectric(brewster.cos(), 1.0 / 1.5);
        let theta_t = (brewster.sin() / 1.5).asin();
        let rs = (brewster - theta_t).sin() / (brewster + theta_t).sin();
        assert!((r - 0.5 * rs * rs).abs() < 1e-5);
        // Grazing incidence reflects everything.
        assert!(fresnel_dielectric(0.0, 1.0 / 1.5) > 0.999);
        // Reciprocity of the refracted pair (Stokes): R(θi, n1→n2) = R(θt, n2→n1).
        let ti = 0.7f32;
        let tt = (ti.sin() / 1.5).asin();
        assert!(
            (fresnel_dielectric(ti.cos(), 1.0 / 1.5) - fresnel_dielectric(tt.cos(), 1.5)).abs()
                < 1e-5
        );
    }

    #[test]
    fn reflection_keeps_the_angle() {
        let d = dir_at(0.4);
        let r = reflect(d, Vec3::Z);
        assert!((r.z - 0.4f32.cos()).abs() < 1e-6 && (r.x - d.x).abs() < 1e-6);
    }
}
