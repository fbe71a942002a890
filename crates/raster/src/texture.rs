//! Image textures looked up per fragment.
//!
//! The pipeline holds a table of textures (`Pipeline::textures`), shared by index like
//! the material table: a material with `texture: Some(i)` multiplies the fragment's base
//! colour by texture `i` at the fragment's perspective-correct texture coordinate
//! (Heckbert and Moreton 1991, see [`crate::interpolate`]). The lookup is the ray
//! tracer's, the same function (`irradia_scene::image_texel`): the coordinate times
//! `scale`, repeated (wrapped to [0, 1)), nearest texel, `v` running up the image, so
//! that a rasterized and a ray-traced surface sample the same texel at the same point.

use glam::{Vec2, Vec3};
use irradia_core::Image;
use std::sync::Arc;

/// An image repeated over the surface's (u, v), `scale` repeats per unit uv.
#[derive(Clone, Debug)]
pub struct Texture {
    /// Linear RGB texels, row 0 at the top (v = 1).
    pub image: Arc<Image>,
    pub scale: Vec2,
}

impl PartialEq for Texture {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.image, &other.image) && self.scale == other.scale
    }
}

impl Texture {
    pub fn new(image: Arc<Image>, scale: Vec2) -> Self {
        Self { image, scale }
    }

    /// The texel at `uv`: nearest, repeated ([`irradia_scene::image_texel`], the ray
    /// tracer's own lookup).
    #[inline]
    pub fn sample(&self, uv: Vec2) -> Vec3 {
        let c = irradia_scene::image_texel(&self.image, uv * self.scale);
        Vec3::new(c.r, c.g, c.b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use irradia_core::Rgb;

    #[test]
    fn nearest_repeated_v_up() {
        // 2x2: top row red, green; bottom row blue, white.
        let img = Image::from_pixels(
            2,
            2,
            vec![
                Rgb::new(1.0, 0.0, 0.0),
                Rgb::new(0.0, 1.0, 0.0),
                Rgb::new(0.0, 0.0, 1.0),
                Rgb::WHITE,
            ],
        );
        let t = Texture::new(Arc::new(img), Vec2::ONE);
        assert_eq!(t.sample(Vec2::new(0.25, 0.75)), Vec3::X);
        assert_eq!(t.sample(Vec2::new(0.75, 0.75)), Vec3::Y);
        assert_eq!(t.sample(Vec2::new(0.25, 0.25)), Vec3::Z);
        // Repeated: one unit over is the same texel, negative too.
        assert_eq!(t.sample(Vec2::new(1.25, -0.25)), Vec3::X);
        let twice = Texture::new(t.image.clone(), Vec2::splat(2.0));
        assert_eq!(twice.sample(Vec2::new(0.375, 0.375)), Vec3::Y);
    }
}
