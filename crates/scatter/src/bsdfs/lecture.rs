//! The lecture's mixture BSDF: what a scene's Phong/POV-Ray material becomes in the path
//! tracer (lecture, "The Rendering Equation" and "Path Tracing"). A weighted mixture of up
//! to four lobes: Lambertian, energy-conserving (normalised) Phong gloss, perfect mirror
//! and smooth dielectric with Fresnel.
//!
//! Unlike Mitsuba's one-sided plugins, every lobe here is two-sided: light arriving on
//! the back side (-z) is reflected the same way as on the front, as the lecture's
//! Whitted tracer shades both sides of a surface.

use crate::bsdf::{BsdfSample, LobeFlags, Scatter};
use glam::{Vec2, Vec3};
use irradia_core::sampling::{cosine_hemisphere, cosine_hemisphere_pdf};
use irradia_core::Rgb;
use std::f32::consts::{FRAC_1_PI, PI};

/// One scattering lobe of a [`LectureMix`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LectureLobe {
    /// Ideal diffuse reflection, `f = albedo / π`.
    Lambert { albedo: Rgb },
    /// The modified Phong lobe normalised for energy conservation (Lafortune and
    /// Willems 1994, "Using the modified Phong reflectance model for physically based
    /// rendering"): `f = ks (n + 2) / (2π) cos^n α`, α the angle between `wi` and the
    /// mirror direction of `wo`. Its albedo is at most `ks`.
    Phong { ks: Rgb, exponent: f32 },
    /// Perfect specular reflection with reflectance `r`.
    Mirror { r: Rgb },
    /// A smooth dielectric boundary: Fresnel-weighted reflection and refraction by
    /// Snell's law. `eta` is the index inside over the index outside (the side the
    /// normal points to); transmitted light is tinted by `tint`; both parts are scaled
    /// by `weight` (1 for clear glass) so the lobe can share a mixture.
    Dielectric { eta: f32, tint: Rgb, weight: f32 },
}

/// A weighted mixture of up to four [`LectureLobe`]s; the weights are folded into the
/// lobes' own coefficients, and sampling picks a lobe in proportion to its albedo
/// estimate (one-sample MIS over the smooth lobes).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LectureMix {
    lobes: [Option<LectureLobe>; 4],
    count: usize,
}

impl LectureMix {
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a lobe (ignored when its coefficients are black, or when four are held).
    pub fn with(mut self, lobe: LectureLobe) -> Self {
        if lobe.selection_weight() > 0.0 && self.count < 4 {
            self.lobes[self.count] = Some(lobe);
            self.count += 1;
        }
        self
    }

    pub fn lobes(&self) -> impl Iterator<Item = &LectureLobe> {
        self.lobes[..self.count].iter().flatten()
    }

    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    fn total_weight(&self) -> f32 {
        self.lobes().map(|l| l.selection_weight()).sum()
    }
}

impl Scatter for LectureMix {
    fn flags(&self) -> LobeFlags {
        let lobes = self.lobes().fold(LobeFlags::NONE, |f, l| f | l.flags());
        if lobes == LobeFlags::NONE {
            lobes
        } else {
            lobes | LobeFlags::FRONT_SIDE | LobeFlags::BACK_SIDE
        }
    }

    /// f(wo, wi) summed over the smooth lobes (delta lobes contribute nothing here).
    fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        self.lobes().map(|l| l.eval(wo, wi)).sum()
    }

    /// The density with which `sample` produces `wi` through its smooth lobes.
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let total = self.total_weight();
        if total <= 0.0 {
            return 0.0;
        }
        self.lobes()
            .map(|l| l.selection_weight() / total * l.pdf(wo, wi))
            .sum()
    }

    /// Samples a direction: first a lobe (`u_lobe`), then a direction in it (`u`).
    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if self.count == 1 {
            // One lobe: its own sample is the mixture's (selection probability 1).
            return self.lobes[0]?.sample(wo, u);
        }
        let total = self.total_weight();
        if total <= 0.0 {
            return None;
        }
        let mut pick = u_lobe * total;
        let mut chosen = None;
        for l in self.lobes() {
            let w = l.selection_weight();
            chosen = Some(*l);
            if pick < w {
                break;
            }
            pick -= w;
        }
        let lobe = chosen?;
        let p_lobe = lobe.selection_weight() / total;
        if lobe.is_delta() {
            let mut s = lobe.sample(wo, u)?;
            s.weight = s.weight / p_lobe;
            s.pdf *= p_lobe;
            return Some(s);
        }
        // A smooth lobe: evaluate the whole mixture for the chosen direction (the
        // one-sample MIS of mixture sampling).
        let s = lobe.sample(wo, u)?;
        let pdf = self.pdf(wo, s.wi);
        if pdf <= 0.0 {
            return None;
        }
        let f = self.eval(wo, s.wi);
        Some(BsdfSample {
            weight: f * (s.wi.z.abs() / pdf),
            pdf,
            ..s
        })
    }
}

impl LectureLobe {
    pub fn is_delta(&self) -> bool {
        matches!(
            self,
            LectureLobe::Mirror { .. } | LectureLobe::Dielectric { .. }
        )
    }

    /// The kinds of scattering this lobe does.
    pub fn flags(&self) -> LobeFlags {
        match self {
            LectureLobe::Lambert { .. } => LobeFlags::DIFFUSE_REFLECTION,
            LectureLobe::Phong { .. } => LobeFlags::GLOSSY_REFLECTION,
            LectureLobe::Mirror { .. } => LobeFlags::DELTA_REFLECTION,
            LectureLobe::Dielectric { .. } => {
                LobeFlags::DELTA_REFLECTION | LobeFlags::DELTA_TRANSMISSION
            }
        }
    }

    /// How often sampling picks this lobe, relative to the others.
    fn selection_weight(&self) -> f32 {
        match self {
            LectureLobe::Lambert { albedo } => albedo.mean(),
            LectureLobe::Phong { ks, .. } => ks.mean(),
            LectureLobe::Mirror { r } => r.mean(),
            LectureLobe::Dielectric { tint, weight, .. } => weight * 0.5 * (1.0 + tint.mean()),
        }
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        match *self {
            LectureLobe::Lambert { albedo } => {
                if wo.z * wi.z > 0.0 {
                    albedo * FRAC_1_PI
                } else {
                    Rgb::BLACK
                }
            }
            LectureLobe::Phong { ks, exponent } => {
                if wo.z * wi.z <= 0.0 {
                    return Rgb::BLACK;
                }
                let r = reflect(wo);
                let c = r.dot(wi).max(0.0);
                ks * ((exponent + 2.0) / (2.0 * PI) * c.powf(exponent))
            }
            LectureLobe::Mirror { .. } | LectureLobe::Dielectric { .. } => Rgb::BLACK,
        }
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match *self {
            LectureLobe::Lambert { .. } => {
                if wo.z * wi.z > 0.0 {
                    cosine_hemisphere_pdf(wi.z.abs())
                } else {
                    0.0
                }
            }
            LectureLobe::Phong { exponent, .. } => {
                if wo.z * wi.z <= 0.0 {
                    return 0.0;
                }
                let c = reflect(wo).dot(wi).max(0.0);
                (exponent + 1.0) / (2.0 * PI) * c.powf(exponent)
            }
            LectureLobe::Mirror { .. } | LectureLobe::Dielectric { .. } => 0.0,
        }
    }

    /// Samples a direction of this lobe alone (selection probability 1).
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        match *self {
            LectureLobe::Lambert { albedo } => {
                if wo.z == 0.0 {
                    return None;
                }
                let mut wi = cosine_hemisphere(u);
                if wo.z < 0.0 {
                    wi.z = -wi.z;
                }
                let pdf = cosine_hemisphere_pdf(wi.z.abs());
                (pdf > 0.0).then_some(BsdfSample {
                    wi,
                    weight: albedo,
                    pdf,
                    lobe: LobeFlags::DIFFUSE_REFLECTION,
                    eta: 1.0,
                })
            }
            LectureLobe::Phong { exponent, .. } => {
                // Sample cos^n around the mirror direction.
                let r = reflect(wo);
                let cos_a = u.x.powf(1.0 / (exponent + 1.0));
                let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
                let phi = 2.0 * PI * u.y;
                let frame = irradia_core::Frame::from_normal(r);
                let wi = frame.to_world(Vec3::new(sin_a * phi.cos(), sin_a * phi.sin(), cos_a));
                if wi.z * wo.z <= 0.0 {
                    return None;
                }
                let pdf = self.pdf(wo, wi);
                if pdf <= 0.0 {
                    return None;
                }
                let f = self.eval(wo, wi);
                Some(BsdfSample {
                    wi,
                    weight: f * (wi.z.abs() / pdf),
                    pdf,
                    lobe: LobeFlags::GLOSSY_REFLECTION,
                    eta: 1.0,
                })
            }
            LectureLobe::Mirror { r } => Some(BsdfSample {
                wi: reflect(wo),
                weight: r,
                pdf: 1.0,
                lobe: LobeFlags::DELTA_REFLECTION,
                eta: 1.0,
            }),
            LectureLobe::Dielectric { eta, tint, weight } => {
                let f = fresnel_dielectric(wo.z, eta);
                if u.x < f {
                    Some(BsdfSample {
                        wi: reflect(wo),
                        weight: Rgb::splat(weight),
                        pdf: f,
                        lobe: LobeFlags::DELTA_REFLECTION,
                        eta: 1.0,
                    })
                } else {
                    let (wi, eta_rel) = refract(wo, eta)?;
                    // Radiance is compressed into the denser medium: divide by the
                    // squared relative index (PBRT 4th ed., 9.5.2).
                    Some(BsdfSample {
                        wi,
                        weight: tint * (weight / (eta_rel * eta_rel)),
                        pdf: 1.0 - f,
                        lobe: LobeFlags::DELTA_TRANSMISSION,
                        eta: eta_rel,
                    })
                }
            }
        }
    }

    /// Directional albedo estimate for energy tests: ∫ f |cos θi| dωi, by the lobe's
    /// own sampling with `n` stratified samples. (For a dielectric this includes the
    /// 1/η² radiance scaling of refraction.)
    pub fn albedo(&self, wo: Vec3, n: u32) -> Rgb {
        let m = (n as f32).sqrt().ceil() as u32;
        let mut sum = Rgb::BLACK;
        for i in 0..m {
            for j in 0..m {
                let u = Vec2::new((i as f32 + 0.5) / m as f32, (j as f32 + 0.5) / m as f32);
                if let Some(s) = self.sample(wo, u) {
                    sum += s.weight;
                }
            }
        }
        sum / (m * m) as f32
    }
}

/// Mirror direction of `w` about the +z normal.
#[inline]
pub fn reflect(w: Vec3) -> Vec3 {
    Vec3::new(-w.x, -w.y, w.z)
}

/// Refracts `wo` through a boundary with relative index `eta` (inside / outside, the
/// normal +z pointing outside). Returns the refracted direction and the relative index
/// `eta_t / eta_i` along the path, or `None` on total internal reflection.
pub fn refract(wo: Vec3, eta: f32) -> Option<(Vec3, f32)> {
    let (cos_i, eta_rel, sign) = if wo.z > 0.0 {
        (wo.z, eta, 1.0)
    } else {
        (-wo.z, 1.0 / eta, -1.0)
    };
    let sin2_i = (1.0 - cos_i * cos_i).max(0.0);
    let sin2_t = sin2_i / (eta_rel * eta_rel);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let wi = Vec3::new(-wo.x / eta_rel, -wo.y / eta_rel, -sign * cos_t);
    Some((wi.normalize(), eta_rel))
}

/// Unpolarised Fresnel reflectance of a dielectric boundary for light arriving at
/// cosine `cos_i` (positive: from outside) with relative index `eta` (inside/outside).
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let (cos_i, eta) = if cos_i < 0.0 {
        (-cos_i, 1.0 / eta)
    } else {
        (cos_i, eta)
    };
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (r_parl * r_parl + r_perp * r_perp)
}
