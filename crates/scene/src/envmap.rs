//! The environment map of Mitsuba 3's `envmap` emitter: radiance at infinity stored in a
//! latitude-longitude image (width = 2 × height), scaled by `scale` and turned by
//! `to_world`.
//!
//! Mapping (Mitsuba's): a local direction `d` has `u = atan2(d.x, -d.z) / 2π` (wrapped
//! into [0, 1)) and `v = acos(d.y) / π`, so the image's top row is straight up (+y), its
//! left edge looks down -z and its centre column along +z.
//!
//! Lookup (Mitsuba's `envmap`, exactly): the pixels are the vertices of a grid, bilinearly
//! interpolated. Horizontally pixel `x` sits at `u = (x + ½) / W` and the grid is periodic
//! (column `W` repeats column 0); vertically pixel row `y` sits at `v = y / (H - 1)`, so
//! the top row is the north pole itself and the bottom row the south pole. The grid
//! coordinates of `(u, v)` are `(s, t) = ((u - ½/W) mod 1, v)`: cell `(i, j)` covers
//! `s ∈ [i, i+1) / W`, `t ∈ [j, j+1) / (H - 1)`.

use glam::{Mat3, Vec2, Vec3};
use irradia_core::atan2;
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
        self.uv_sin_theta(dir).0
    }

    /// [`EnvMap::uv`] of `dir` and the `sin θ` of `dir` (`sin(π v)`, read off the
    /// direction rather than recomputed from `v`).
    #[inline]
    pub fn uv_sin_theta(&self, dir: Vec3) -> (Vec2, f32) {
        let d = (self.to_world.transpose() * dir).normalize();
        // The polynomial arctangent of [`irradia_core::atan`] (no call into the C library);
        // θ = acos d.y as atan2(√(x² + z²), y), exact to the same 4·10⁻⁷ at the poles.
        let u = atan2(d.x, -d.z) * (0.5 / PI);
        let u = if u < 0.0 { u + 1.0 } else { u };
        let sin_theta = (d.x * d.x + d.z * d.z).sqrt();
        let theta = atan2(sin_theta, d.y);
        (
            Vec2::new(u.min(1.0 - f32::EPSILON), (theta / PI).clamp(0.0, 1.0)),
            sin_theta,
        )
    }

    /// The unit world direction at `(u, v)`; `sin θ` of it is `sin(π v)`.
    #[inline]
    pub fn direction(&self, uv: Vec2) -> Vec3 {
        self.direction_sin_theta(uv).0
    }

    /// [`EnvMap::direction`] and its `sin θ = sin(π v)`, found together.
    #[inline]
    pub fn direction_sin_theta(&self, uv: Vec2) -> (Vec3, f32) {
        let (phi, theta) = (2.0 * PI * uv.x, PI * uv.y);
        // The polynomial sine and cosine, as the wide kernel's lanes compute them.
        let (sp, cp) = irradia_core::sin_cos(phi);
        let (st, ct) = irradia_core::sin_cos(theta);
        (
            (self.to_world * Vec3::new(sp * st, ct, -cp * st)).normalize(),
            st,
        )
    }

    /// The grid coordinates `(s, t)` of map coordinates `(u, v)`, each in [0, 1].
    #[inline]
    pub fn grid(&self, uv: Vec2) -> Vec2 {
        let w = self.image.width() as f32;
        Vec2::new((uv.x - 0.5 / w).rem_euclid(1.0), uv.y.clamp(0.0, 1.0))
    }

    /// The map coordinates `(u, v)` of grid coordinates `(s, t)`.
    #[inline]
    pub fn uv_of_grid(&self, st: Vec2) -> Vec2 {
        let w = self.image.width() as f32;
        Vec2::new((st.x + 0.5 / w).rem_euclid(1.0), st.y)
    }

    /// The grid cell `(i, j)` that grid coordinates `(s, t)` fall in: `W x (H - 1)` cells.
    #[inline]
    pub fn cell(&self, st: Vec2) -> (u32, u32) {
        let (w, h) = (self.image.width(), self.image.height());
        (
            ((st.x * w as f32) as u32).min(w - 1),
            ((st.y * (h - 1) as f32) as u32).min(h - 2),
        )
    }

    /// The pixel at grid vertex `(x, y)`, `x` in `0..=W` (column `W` is column 0).
    #[inline]
    pub fn vertex(&self, x: u32, y: u32) -> Rgb {
        let w = self.image.width();
        self.image.get(if x >= w { x - w } else { x }, y)
    }

    /// Radiance at map coordinates `uv`: the bilinear interpolation of the four pixels
    /// around it, times `scale`.
    #[inline]
    pub fn eval_uv(&self, uv: Vec2) -> Rgb {
        let (w, h) = (self.image.width(), self.image.height());
        let st = self.grid(uv);
        let (i, j) = self.cell(st);
        let fx = (st.x * w as f32 - i as f32).clamp(0.0, 1.0);
        let fy = (st.y * (h - 1) as f32 - j as f32).clamp(0.0, 1.0);
        let top = self.vertex(i, j) * (1.0 - fx) + self.vertex(i + 1, j) * fx;
        let bottom = self.vertex(i, j + 1) * (1.0 - fx) + self.vertex(i + 1, j + 1) * fx;
        (top * (1.0 - fy) + bottom * fy) * self.scale
    }

    /// Radiance arriving from world direction `-dir`, i.e. seen by a ray travelling
    /// along `dir` that leaves the scene.
    #[inline]
    pub fn eval(&self, dir: Vec3) -> Rgb {
        self.eval_uv(self.uv(dir))
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

    /// Mitsuba's lookup by hand on a 4 x 3 map: pixel `(x, y)` sits at
    /// `u = (x + ½)/4`, `v = y/2`; in between the value is bilinear, and the grid wraps
    /// from the last column to the first.
    #[test]
    fn lookup_is_mitsubas_bilinear_vertex_grid() {
        let px: Vec<Rgb> = (0..12).map(|k| Rgb::splat(k as f32)).collect();
        let map = EnvMap {
            image: Arc::new(Image::from_pixels(4, 3, px)),
            scale: 2.0,
            to_world: Mat3::IDENTITY,
            path: PathBuf::new(),
        };
        let at = |u: f32, v: f32| map.eval_uv(Vec2::new(u, v)).r / 2.0;
        // On the pixels themselves.
        for (x, y) in [(0u32, 0u32), (1, 0), (3, 1), (2, 2)] {
            let want = (y * 4 + x) as f32;
            let got = at((x as f32 + 0.5) / 4.0, y as f32 / 2.0);
            assert!((got - want).abs() < 1e-5, "pixel ({x}, {y}): {got}");
        }
        // Half-way between pixels (1, 1) = 5 and (2, 1) = 6, and a quarter of the way
        // down from row 0 to row 1 at column 1: 1 + 0.5 * 4 = 3.
        assert!((at(0.5, 0.5) - 5.5).abs() < 1e-5);
        assert!((at(0.375, 0.25) - 3.0).abs() < 1e-5);
        // Across the seam: half-way between column 3 (7) and column 0 (4) of row 1, at
        // u = 0 (= 1).
        assert!((at(0.0, 0.5) - 5.5).abs() < 1e-5);
        assert!((at(0.999_999, 0.5) - 5.5).abs() < 1e-3);
        // The poles are the first and last rows.
        assert!((at(0.125, 0.0) - 0.0).abs() < 1e-5);
        assert!((at(0.625, 1.0) - 10.0).abs() < 1e-5);
    }
}
