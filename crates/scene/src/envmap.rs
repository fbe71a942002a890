//! The environment map of Mitsuba 3's `envmap` emitter: radiance at infinity stored in a
//! latitude-longitude image (width = 2 × height), scaled by `scale` and turned by
//! `to_world`.
//!
//! Mapping (Mitsuba's): a local direction `d` has `u = atan2(d.x, -d.z) / 2π` (wrapped
//! into [0, 1)) and `v = acos(d.y) / π`, so the image's top row is straight up (+y), its
//! left edge looks down -z and its centre column along +z. Texel `(i, j)` covers `u ∈ [i, i+1) / width`,
//! `v ∈ [j, j+1) / height` and its radiance is constant there (nearest lookup, as
//! pbrt-v4's `ImageInfiniteLight`; Mitsuba interpolates bilinearly, which differs
//! only within a texel), so the importance sampling of the path tracer follows the
//! radiance exactly.

use glam::{Mat3, Vec2, Vec3};
use irradia_core::{Image, Rgb};
use std::f32::consts::PI;
use std::path::PathBuf;
use std::sync::Arc;

#[derive(Clone, Debug, PartialEq)]
pub struct EnvMap {
    /// Linear RGB radiance, `2h x h` texels.
    pub image: Arc<Image>,
    /// Factor on every texel (Mitsuba's `scale`).
    pub scale: f32,
    /// Rotation from the map's frame to the world (Mitsuba's `to_world`).
    pub to_world: Mat3,
    /// The file it came from (for messages).
    pub path: PathBuf,
}

impl EnvMap {
    /// The map's `(u, v)` of world direction `dir` (any length).
    #[inline]
    pub fn uv(&self, dir: Vec3) -> Vec2 {
        let d = (self.to_world.transpose() * dir).normalize();
        let u = d.x.atan2(-d.z) * (0.5 / PI);
        let u = if u < 0.0 { u + 1.0 } else { u };
        Vec2::new(u.min(1.0 - f32::EPSILON), d.y.clamp(-1.0, 1.0).acos() / PI)
    }

    /// The unit world direction at `(u, v)`; `sin θ` of it is `sin(π v)`.
    #[inline]
    pub fn direction(&self, uv: Vec2) -> Vec3 {
        let (phi, theta) = (2.0 * PI * uv.x, PI * uv.y);
        let (sp, cp) = phi.sin_cos();
        let (st, ct) = theta.sin_cos();
        (self.to_world * Vec3::new(sp * st, ct, -cp * st)).normalize()
    }

    /// The texel `(u, v)` falls in.
    #[inline]
    pub fn texel(&self, uv: Vec2) -> (u32, u32) {
        let (w, h) = (self.image.width(), self.image.height());
        (
            ((uv.x * w as f32) as u32).min(w - 1),
            ((uv.y * h as f32) as u32).min(h - 1),
        )
    }

    /// Radiance arriving from world direction `-dir`, i.e. seen by a ray travelling
    /// along `dir` that leaves the scene.
    #[inline]
    pub fn eval(&self, dir: Vec3) -> Rgb {
        let (x, y) = self.texel(self.uv(dir));
        self.image.get(x, y) * self.scale
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uv_and_direction_are_inverse_and_follow_mitsuba() {
        let map = EnvMap {
            image: Arc::new(Image::filled(8, 4, Rgb::WHITE).unwrap()),
            scale: 1.0,
            to_world: Mat3::from_rotation_y(0.3),
            path: PathBuf::new(),
        };
        for uv in [
            Vec2::new(0.1, 0.2),
            Vec2::new(0.7, 0.9),
            Vec2::new(0.5, 0.5),
        ] {
            let back = map.uv(map.direction(uv));
            assert!((back - uv).length() < 1e-5, "{uv} -> {back}");
        }
        let plain = EnvMap {
            to_world: Mat3::IDENTITY,
            ..map
        };
        // Mitsuba's: the top row is +y, u = 0 is -z, u = 1/4 is +x.
        assert!((plain.direction(Vec2::new(0.3, 0.0)) - Vec3::Y).length() < 1e-6);
        assert!((plain.direction(Vec2::new(0.0, 0.5)) - -Vec3::Z).length() < 1e-6);
        assert!((plain.direction(Vec2::new(0.25, 0.5)) - Vec3::X).length() < 1e-6);
    }
}
