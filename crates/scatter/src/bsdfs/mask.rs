//! Mitsuba 3's `mask`: a nested BSDF made partly transparent. With probability
//! `opacity` light scatters by the nested BSDF (whose value and density are scaled by
//! `opacity`); otherwise it passes straight through, `wi = -wo`, by the null lobe
//! (flag [`LobeFlags::NULL`], weight 1, probability `1 - opacity`).

use crate::bsdf::{Bsdf, BsdfSample, LobeFlags, Scatter};
use glam::{Vec2, Vec3};
use irradia_core::Rgb;

#[derive(Clone, Debug)]
pub struct Mask {
    /// Mitsuba's `opacity`, in [0, 1] (clamped where used, as Mitsuba does; default 0.5).
    pub opacity: f32,
    /// Mitsuba's nested BSDF.
    pub nested_bsdf: Box<Bsdf>,
}

impl Mask {
    fn alpha(&self) -> f32 {
        self.opacity.clamp(0.0, 1.0)
    }

    /// The fraction of light that passes straight through the surface (Mitsuba's
    /// `eval_null_transmission` for a nested BSDF without a null lobe of its own).
    pub fn null_transmission(&self) -> f32 {
        1.0 - self.alpha()
    }
}

impl Scatter for Mask {
    fn flags(&self) -> LobeFlags {
        self.nested_bsdf.flags() | LobeFlags::NULL | LobeFlags::FRONT_SIDE | LobeFlags::BACK_SIDE
    }

    fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        self.nested_bsdf.eval(wo, wi) * self.alpha()
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.nested_bsdf.pdf(wo, wi) * self.alpha()
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        let alpha = self.alpha();
        if u_lobe < alpha {
            // The nested BSDF's value and density both carry `opacity`: its weight stays.
            let s = self.nested_bsdf.sample(wo, u_lobe / alpha, u)?;
            return Some(BsdfSample {
                pdf: s.pdf * alpha,
                ..s
            });
        }
        Some(BsdfSample {
            wi: -wo,
            weight: Rgb::WHITE,
            pdf: 1.0 - alpha,
            lobe: LobeFlags::NULL,
            eta: 1.0,
        })
    }
}
