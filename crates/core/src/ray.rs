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
    // Branch-free, lane by lane (the signs of a point's coordinates are as good as
    // random, so branches on them mispredict; this runs two or three times per hit):
    // the integer offset is negated for negative coordinates by `(o ^ s) - s` with
    // `s` the sign mask (-0.0 counts as negative here, which only matters where the
    // float offset below is taken instead).
    let step = |pc: f32, nc: f32| -> f32 {
        let oi = (INT_SCALE * nc) as i32;
        let bits = pc.to_bits() as i32;
        let s = bits >> 31;
        let moved = f32::from_bits(bits.wrapping_add((oi ^ s).wrapping_sub(s)) as u32);
        let near = pc + FLOAT_SCALE * nc;
        if pc.abs() < ORIGIN {
            near
        } else {
            moved
        }
    };
    Vec3::new(step(p.x, n.x), step(p.y, n.y), step(p.z, n.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The branchy form the branch-free one replaced (Wächter and Binder's listing).
    fn offset_reference(p: Vec3, n: Vec3, extra_error: f32) -> Vec3 {
        let p = p + n * extra_error;
        let step = |pc: f32, nc: f32| -> f32 {
            let oi = (256.0 * nc) as i32;
            let bits = pc.to_bits() as i32;
            let moved = if pc < 0.0 { bits - oi } else { bits + oi };
            if pc.abs() < 1.0 / 32.0 {
                pc + nc / 65536.0
            } else {
                f32::from_bits(moved as u32)
            }
        };
        Vec3::new(step(p.x, n.x), step(p.y, n.y), step(p.z, n.z))
    }

    #[test]
    fn branch_free_offset_equals_the_reference_bit_for_bit() {
        let mut rng = crate::Rng::new(7, 0);
        for i in 0..200_000 {
            let scale = [1e-3f32, 0.03, 1.0, 1e3, 1e6][i % 5];
            let r = |rng: &mut crate::Rng| 2.0 * rng.next_f32() - 1.0;
            let p = Vec3::new(r(&mut rng), r(&mut rng), r(&mut rng)) * scale;
            let n = Vec3::new(r(&mut rng), r(&mut rng), r(&mut rng)).normalize_or(Vec3::Z);
            let e = if i % 3 == 0 {
                0.0
            } else {
                rng.next_f32() * 1e-4
            };
            let (a, b) = (offset_ray_origin(p, n, e), offset_reference(p, n, e));
            assert_eq!(
                a.to_array().map(f32::to_bits),
                b.to_array().map(f32::to_bits),
                "{p} {n}"
            );
        }
    }

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
