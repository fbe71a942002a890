//! Mitsuba 3's `checkerboard` texture: two values alternating on the unit squares of
//! (transformed) uv space, two cells per unit along each axis.

use super::uv_transform::UvTransform;
use glam::Vec2;
use irradia_core::Rgb;

/// Two colours on alternating cells, as Mitsuba 3's `checkerboard.cpp` does, with its
/// two conventions (checked against Mitsuba 3.9.1): as a colour (`eval`), `color0`
/// where the fractional parts of u and v are both above 1/2 or both below (so `color0`
/// at uv (0.25, 0.25) and at (0, 0)); as a number (`eval_1`, e.g. a roughness), the
/// other way round. Defaults 0.4 and 0.2.
#[derive(Clone, Debug, PartialEq)]
pub struct Checkerboard {
    pub color0: Rgb,
    pub color1: Rgb,
    pub to_uv: UvTransform,
}

impl Default for Checkerboard {
    fn default() -> Self {
        Checkerboard {
            color0: Rgb::splat(0.4),
            color1: Rgb::splat(0.2),
            to_uv: UvTransform::default(),
        }
    }
}

impl Checkerboard {
    /// The colour at surface coordinates `uv` (Mitsuba's `eval`).
    pub fn eval(&self, uv: Vec2) -> Rgb {
        if self.same_halves(uv) {
            self.color0
        } else {
            self.color1
        }
    }

    /// The colour whose luminance is the number at `uv` (Mitsuba's `eval_1`, which
    /// picks the cells the other way round).
    pub fn eval_1_color(&self, uv: Vec2) -> Rgb {
        if self.same_halves(uv) {
            self.color1
        } else {
            self.color0
        }
    }

    /// Whether u and v of the transformed `uv` lie in the same half of their cells.
    fn same_halves(&self, uv: Vec2) -> bool {
        let st = self.to_uv.apply(uv);
        let upper_u = st.x - st.x.floor() > 0.5;
        let upper_v = st.y - st.y.floor() > 0.5;
        upper_u == upper_v
    }
}
