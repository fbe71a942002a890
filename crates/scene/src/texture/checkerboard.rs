//! Mitsuba 3's `checkerboard` texture: two values alternating on the unit squares of
//! (transformed) uv space, two cells per unit along each axis.

use super::uv_transform::UvTransform;
use glam::Vec2;
use irradia_core::Rgb;

/// `color0` where exactly one of the fractional parts of u and v is above 1/2, `color1`
/// elsewhere (so `color1` at uv (0.25, 0.25)), as Mitsuba's `checkerboard.cpp` does;
/// defaults 0.4 and 0.2.
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
    /// The value at surface coordinates `uv`.
    pub fn eval(&self, uv: Vec2) -> Rgb {
        let st = self.to_uv.apply(uv);
        let upper_u = st.x - st.x.floor() > 0.5;
        let upper_v = st.y - st.y.floor() > 0.5;
        if upper_u != upper_v {
            self.color0
        } else {
            self.color1
        }
    }
}
