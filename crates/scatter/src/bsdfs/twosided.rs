//! Mitsuba 3's `twosided`: a one-sided BSDF made to scatter on both sides. Light
//! arriving on the front (`wo.z > 0`) sees `front`; light on the back sees `back`
//! (by default the front one again), evaluated with both directions mirrored to +z
//! (`z → -z`) so that a one-sided BSDF sees its own front side.

use crate::bsdf::{Bsdf, BsdfSample, LobeFlags, Scatter};
use glam::{Vec2, Vec3};
use irradia_core::Rgb;

#[derive(Clone, Debug)]
pub struct TwoSided {
    /// The BSDF of the front side (Mitsuba's first nested BSDF, `brdf_0`).
    pub front: Box<Bsdf>,
    /// The BSDF of the back side (Mitsuba's second, `brdf_1`); `None`: the front one.
    pub back: Option<Box<Bsdf>>,
}

/// `w` mirrored through the surface plane.
#[inline]
fn mirror_z(w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, -w.z)
}

impl TwoSided {
    fn back(&self) -> &Bsdf {
        self.back.as_deref().unwrap_or(&self.front)
    }
}

impl Scatter for TwoSided {
    fn flags(&self) -> LobeFlags {
        let side = LobeFlags(LobeFlags::FRONT_SIDE.0 | LobeFlags::BACK_SIDE.0);
        let front = LobeFlags(self.front.flags().0 & !side.0) | LobeFlags::FRONT_SIDE;
        let back = LobeFlags(self.back().flags().0 & !side.0) | LobeFlags::BACK_SIDE;
        front | back
    }

    fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if wo.z > 0.0 {
            self.front.eval(wo, wi)
        } else if wo.z < 0.0 {
            self.back().eval(mirror_z(wo), mirror_z(wi))
        } else {
            Rgb::BLACK
        }
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z > 0.0 {
            self.front.pdf(wo, wi)
        } else if wo.z < 0.0 {
            self.back().pdf(mirror_z(wo), mirror_z(wi))
        } else {
            0.0
        }
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z > 0.0 {
            self.front.sample(wo, u_lobe, u)
        } else if wo.z < 0.0 {
            let s = self.back().sample(mirror_z(wo), u_lobe, u)?;
            Some(BsdfSample {
                wi: mirror_z(s.wi),
                ..s
            })
        } else {
            None
        }
    }
}
