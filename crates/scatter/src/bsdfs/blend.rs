//! Mitsuba 3's `blendbsdf`: the linear interpolation `(1 - weight) f₀ + weight f₁` of two
//! nested BSDFs (`weight` 0 shows the first, 1 the second).
//!
//! Sampling picks the nested BSDF with probability `1 - weight` or `weight` and, for a
//! smooth direction, weights it by the blended value over the blended density (the
//! one-sample MIS of a mixture), as Mitsuba's plugin does. A direction from a delta lobe
//! keeps the chosen BSDF's own weight and its selection probability (Mitsuba adds the
//! other BSDF's solid-angle density to that discrete probability; that mixes measures,
//! so it is not done here).

use crate::bsdf::{Bsdf, BsdfSample, LobeFlags, Scatter};
use glam::{Vec2, Vec3};
use irradia_core::Rgb;

#[derive(Clone, Debug)]
pub struct Blend {
    /// Mitsuba's `weight`, in [0, 1] (clamped where used, as Mitsuba does).
    pub weight: f32,
    /// The first nested BSDF (Mitsuba's `bsdf_0`), shown at `weight` 0.
    pub bsdf_0: Box<Bsdf>,
    /// The second nested BSDF (Mitsuba's `bsdf_1`), shown at `weight` 1.
    pub bsdf_1: Box<Bsdf>,
}

impl Blend {
    fn w(&self) -> f32 {
        self.weight.clamp(0.0, 1.0)
    }
}

impl Scatter for Blend {
    fn flags(&self) -> LobeFlags {
        self.bsdf_0.flags() | self.bsdf_1.flags()
    }

    fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let w = self.w();
        self.bsdf_0.eval(wo, wi) * (1.0 - w) + self.bsdf_1.eval(wo, wi) * w
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let w = self.w();
        self.bsdf_0.pdf(wo, wi) * (1.0 - w) + self.bsdf_1.pdf(wo, wi) * w
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        let w = self.w();
        // The chosen BSDF, its selection probability, the other one and its share.
        let (chosen, p, other, q, u_lobe) = if u_lobe < w {
            (&self.bsdf_1, w, &self.bsdf_0, 1.0 - w, u_lobe / w)
        } else {
            (
                &self.bsdf_0,
                1.0 - w,
                &self.bsdf_1,
                w,
                (u_lobe - w) / (1.0 - w),
            )
        };
        let s = chosen.sample(wo, u_lobe.min(1.0 - f32::EPSILON), u)?;
        if s.is_delta() {
            return Some(BsdfSample {
                pdf: s.pdf * p,
                ..s
            });
        }
        let pdf = p * s.pdf + q * other.pdf(wo, s.wi);
        if pdf <= 0.0 {
            return None;
        }
        // f_chosen |cos| = weight × pdf of the chosen BSDF.
        let f_cos = s.weight * (p * s.pdf) + other.eval(wo, s.wi) * (q * s.wi.z.abs());
        Some(BsdfSample {
            weight: f_cos / pdf,
            pdf,
            ..s
        })
    }
}
