//! Geometric optics of a smooth interface in the local shading frame (normal +z): mirror
//! reflection, refraction by Snell's law, total internal reflection and the exact
//! Fresnel equations of dielectrics and conductors (lecture "Reflection and
//! Transmission"; Born and Wolf, *Principles of Optics*, §1.5 and §14.2; Mitsuba 3's
//! `fresnel.h`; *PBRT* 4th ed., §9.3 and §9.4).
//!
//! Conventions as the rest of the crate: directions point away from the surface, and
//! `eta = η_interior / η_exterior` (the interior is the side -z). A direction with
//! `w.z > 0` is outside, `w.z < 0` inside.

use glam::Vec3;
use irradia_core::Rgb;

/// Mirror reflection of `w` about the normal +z: `(-x, -y, z)`.
#[inline]
pub fn reflect(w: Vec3) -> Vec3 {
    Vec3::new(-w.x, -w.y, w.z)
}

/// Mirror reflection of `w` about the unit (micro)normal `m`: `2 (w·m) m - w`.
#[inline]
pub fn reflect_about(w: Vec3, m: Vec3) -> Vec3 {
    2.0 * w.dot(m) * m - w
}

/// The exact unpolarised Fresnel reflectance of a dielectric interface and what a
/// sampler needs to refract (the four values of Mitsuba 3's `fresnel()`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DielectricFresnel {
    /// The reflectance F, the mean of the s and p reflectances; 1 under total internal
    /// reflection, 0 for index-matched media.
    pub reflectance: f32,
    /// The cosine of the refracted direction, with the sign of the side it goes to (the
    /// opposite of `cos θi`'s sign); 0 under total internal reflection.
    pub cos_theta_t: f32,
    /// The relative index `η_t / η_i` for light crossing from the side of `cos θi`.
    pub eta_it: f32,
    /// Its reciprocal `η_i / η_t`.
    pub eta_ti: f32,
}

impl DielectricFresnel {
    /// The transmittance `1 - F`.
    #[inline]
    pub fn transmittance(&self) -> f32 {
        1.0 - self.reflectance
    }
}

/// The exact unpolarised Fresnel equations of a dielectric interface (Born and Wolf,
/// §1.5.2) for a direction with cosine `cos_theta_i` to the normal +z (either side) and
/// `eta = η_interior / η_exterior`, as Mitsuba 3's `fresnel(cos_theta_i, eta)`.
pub fn fresnel_dielectric(cos_theta_i: f32, eta: f32) -> DielectricFresnel {
    let outside = cos_theta_i >= 0.0;
    let (eta_it, eta_ti) = if outside {
        (eta, 1.0 / eta)
    } else {
        (1.0 / eta, eta)
    };
    // Snell's law: sin²θt = (η_i/η_t)² sin²θi.
    let cos2_t = 1.0 - (1.0 - cos_theta_i * cos_theta_i) * eta_ti * eta_ti;
    let cos_i = cos_theta_i.abs();
    let cos_t = cos2_t.max(0.0).sqrt();
    let reflectance = if eta == 1.0 {
        0.0
    } else if cos_i == 0.0 || cos2_t <= 0.0 {
        1.0
    } else {
        // Amplitude coefficients divided through by η_i.
        let r_s = (cos_i - eta_it * cos_t) / (cos_i + eta_it * cos_t);
        let r_p = (eta_it * cos_i - cos_t) / (eta_it * cos_i + cos_t);
        0.5 * (r_s * r_s + r_p * r_p)
    };
    DielectricFresnel {
        reflectance,
        cos_theta_t: if outside { -cos_t } else { cos_t },
        eta_it,
        eta_ti,
    }
}

/// Refraction of `w` through the interface with normal +z, given the signed
/// `cos_theta_t` and `eta_ti` of [`fresnel_dielectric`] for `w.z`: the refracted
/// direction, pointing away on the other side. Meaningless under total internal
/// reflection (`cos_theta_t = 0`).
#[inline]
pub fn refract(w: Vec3, cos_theta_t: f32, eta_ti: f32) -> Vec3 {
    Vec3::new(-eta_ti * w.x, -eta_ti * w.y, cos_theta_t)
}

/// Refraction of `w` through a microfacet with unit normal `m`, given `cos_theta_t` and
/// `eta_ti` of [`fresnel_dielectric`] for `w·m` (Walter et al. 2007, eq. 40).
#[inline]
pub fn refract_about(w: Vec3, m: Vec3, cos_theta_t: f32, eta_ti: f32) -> Vec3 {
    (w.dot(m) * eta_ti + cos_theta_t) * m - w * eta_ti
}

/// Refraction of the unit `w` through a surface with unit normal `m` facing `w`'s side
/// (the exterior), `eta = η_beyond / η_w's side`: the unit refracted direction, or
/// `None` under total internal reflection. Frame-free, for world-space callers; the
/// cosine is taken as `|w·m|` so that a shading normal slightly off `w`'s side still
/// refracts (as a geometric tracer wants).
#[inline]
pub fn refract_through(w: Vec3, m: Vec3, eta: f32) -> Option<Vec3> {
    let f = fresnel_dielectric(w.dot(m).abs(), eta);
    (f.cos_theta_t != 0.0).then(|| refract_about(w, m, f.cos_theta_t, f.eta_ti).normalize())
}

/// Snell's law: the sine of the refraction angle, `sin θt = (η_i / η_t) sin θi`, for
/// light going from index `eta_i` into `eta_t`; `None` under total internal reflection.
pub fn snell_sin_t(sin_theta_i: f32, eta_i: f32, eta_t: f32) -> Option<f32> {
    let sin_t = eta_i / eta_t * sin_theta_i;
    (sin_t <= 1.0).then_some(sin_t)
}

/// The critical angle (radians) beyond which light going from index `eta_i` into a less
/// dense medium `eta_t < eta_i` is totally reflected: `asin(eta_t / eta_i)`. `None`
/// when `eta_t >= eta_i`.
pub fn critical_angle(eta_i: f32, eta_t: f32) -> Option<f32> {
    (eta_t < eta_i).then(|| (eta_t / eta_i).asin())
}

/// The exact unpolarised Fresnel reflectance of a conductor with complex index
/// `eta + i k` (relative to the exterior) for incidence cosine `cos_theta_i` in [0, 1]
/// (Born and Wolf, §14.2; the closed form of Lazányi and Szirmay-Kalos 2005 and
/// *PBRT* 3rd ed. §8.2.1, as Mitsuba 3's `fresnel_conductor`). `eta = 0, k = 1` gives
/// a perfect mirror (F = 1 at every angle).
pub fn fresnel_conductor(cos_theta_i: f32, eta: f32, k: f32) -> f32 {
    let cos_i = cos_theta_i.clamp(0.0, 1.0) as f64;
    let (eta, k) = (eta as f64, k as f64);
    let cos2_i = cos_i * cos_i;
    let sin2_i = 1.0 - cos2_i;
    let sin4_i = sin2_i * sin2_i;
    let temp = eta * eta - k * k - sin2_i;
    // a² + b² = |η̂² - sin²θi|, a = Re sqrt(η̂² - sin²θi).
    let a2_plus_b2 = (temp * temp + 4.0 * k * k * eta * eta).max(0.0).sqrt();
    let a = (0.5 * (a2_plus_b2 + temp)).max(0.0).sqrt();
    let term_1 = a2_plus_b2 + cos2_i;
    let term_2 = 2.0 * cos_i * a;
    let term_3 = a2_plus_b2 * cos2_i + sin4_i;
    let term_4 = term_2 * sin2_i;
    // R = (R_s + R_p) / 2 with R_s = (t1 - t2) / (t1 + t2) and R_p = R_s (t3 - t4) /
    // (t3 + t4), which is R_s t3 / (t3 + t4): one division.
    ((term_1 - term_2) * term_3 / ((term_1 + term_2) * (term_3 + term_4))) as f32
}

/// [`fresnel_conductor`] per RGB channel.
pub fn fresnel_conductor_rgb(cos_theta_i: f32, eta: Rgb, k: Rgb) -> Rgb {
    Rgb::new(
        fresnel_conductor(cos_theta_i, eta.r, k.r),
        fresnel_conductor(cos_theta_i, eta.g, k.g),
        fresnel_conductor(cos_theta_i, eta.b, k.b),
    )
}
