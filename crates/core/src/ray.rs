//! Rays `p(t) = origin + t * dir` (lecture: "Ray is parametric") and robust spawning
//! of secondary rays from a surface point.

use glam::Vec3;

/// A ray. `dir` need not be unit length: shapes and transforms keep `t` in units of
/// `dir`, so a ray carried into object space by an affine map keeps its parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
}

impl Ray {
    #[inline]
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Self { origin, dir }
    }

    /// The point at parameter `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }
}

/// Moves a surface point off its surface along the geometric normal `n` so that a ray
/// spawned from it does not hit the same surface again at `t ~ 0`.
///
/// The offset is a number of units in the last place of each coordinate (so it scales
/// with the magnitude of the point), plus a fixed tiny offset near the origin where ULPs
/// vanish. This is the method of Wächter and Binder, "A Fast and Robust Method for
/// Avoiding Self-Intersection", Ray Tracing Gems (2019), ch. 6. `n` must point to the
/// side the new ray leaves on (flip it for transmitted rays). `extra_error` is an
/// absolute error bound on `p` that the shape reports (e.g. from iterative root
/// finding); the point is also pushed out by that much.
#[inline]
pub fn offset_ray_origin(p: Vec3, n: Vec3, extra_error: f32) -> Vec3 {
    const ORIGIN: f32 = 1.0 / 32.0;
    const FLOAT_SCALE: f32 = 1.0 / 65536.0;
    const INT_SCALE: f32 = 256.0;
    let p = p + n * extra_error;
    let of_i = [
        (INT_SCALE * n.x) as i32,
        (INT_SCALE * n.y) as i32,
        (INT_SCALE * n.z) as i32,
    ];
    let step = |pc: f32, oi: i32| -> f32 {
        let bits = pc.to_bits() as i32;
        let moved = if pc < 0.0 { bits - oi } else { bits + oi };
        f32::from_bits(moved as u32)
    };
    let p_i = Vec3::new(step(p.x, of_i[0]), step(p.y, of_i[1]), step(p.z, of_i[2]));
    Vec3::new(
        if p.x.abs() < ORIGIN {
            p.x + FLOAT_SCALE * n.x
        } else {
            p_i.x
        },
        if p.y.abs() < ORIGIN {
            p.y + FLOAT_SCALE * n.y
        } else {
            p_i.y
        },
        if p.z.abs() < ORIGIN {
            p.z + FLOAT_SCALE * n.z
        } else {
            p_i.z
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offset_moves_to_the_normal_side_at_every_scale() {
        for &s in &[1e-4f32, 1e-2, 1.0, 1e3, 1e6] {
            let p = Vec3::new(s, -s, 0.5 * s);
            for n in [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Z, Vec3::ONE.normalize()] {
                let q = offset_ray_origin(p, n, 0.0);
                assert!((q - p).dot(n) > 0.0, "scale {s} normal {n}");
                assert!((q - p).length() < 1e-3 * s.max(0.05));
            }
        }
    }
}
