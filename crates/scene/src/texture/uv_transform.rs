//! Mitsuba's `to_uv`: a 2D affine map applied to a surface's (u, v) before a texture is
//! looked up (Mitsuba 3 `bitmap` and `checkerboard` plugins, parameter `to_uv`).

use glam::{Affine2, Vec2};

/// The map from surface (u, v) to texture coordinates; the identity by default.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform(pub Affine2);

impl Default for UvTransform {
    fn default() -> Self {
        UvTransform(Affine2::IDENTITY)
    }
}

impl UvTransform {
    /// The texture coordinates of surface coordinates `uv`.
    pub fn apply(&self, uv: Vec2) -> Vec2 {
        self.0.transform_point2(uv)
    }

    /// The per-axis repeat factors when the map is a pure axis-aligned scale (no
    /// rotation, shear or translation); `None` otherwise.
    pub fn as_scale(&self) -> Option<Vec2> {
        let m = self.0.matrix2;
        let pure = m.x_axis.y == 0.0 && m.y_axis.x == 0.0 && self.0.translation == Vec2::ZERO;
        pure.then_some(Vec2::new(m.x_axis.x, m.y_axis.y))
    }
}
