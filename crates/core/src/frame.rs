//! Orthonormal frames around a normal, for sampling directions in local coordinates.

use glam::Vec3;

/// An orthonormal basis `(s, t, n)`; local z is the normal.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    pub s: Vec3,
    pub t: Vec3,
    pub n: Vec3,
}

impl Frame {
    /// Builds a frame around unit `n` without branches on a chosen axis: Duff et al.,
    /// "Building an Orthonormal Basis, Revisited", JCGT 6(1), 2017.
    pub fn from_normal(n: Vec3) -> Self {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let s = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let t = Vec3::new(b, sign + n.y * n.y * a, -n.y);
        Self { s, t, n }
    }

    /// The frame around unit `n` whose `s` axis is `tangent` made orthogonal to `n`
    /// (Gram-Schmidt; Mitsuba's shading frame from `dp_du`), or [`Frame::from_normal`]
    /// when `tangent` is (nearly) zero or parallel to `n`.
    pub fn from_normal_tangent(n: Vec3, tangent: Vec3) -> Self {
        let s = tangent - n * n.dot(tangent);
        let len2 = s.length_squared();
        let usable = len2 > 1e-12 * tangent.length_squared() && len2.is_finite();
        if !usable {
            return Self::from_normal(n);
        }
        let s = s / len2.sqrt();
        Self {
            s,
            t: n.cross(s),
            n,
        }
    }

    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }

    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_orthonormal() {
        for n in [
            Vec3::Z,
            -Vec3::Z,
            Vec3::X,
            Vec3::new(0.3, -0.4, 0.866).normalize(),
            Vec3::new(0.0, 0.0, -0.99999).normalize(),
        ] {
            let f = Frame::from_normal(n);
            assert!((f.s.length() - 1.0).abs() < 1e-5);
            assert!((f.t.length() - 1.0).abs() < 1e-5);
            assert!(
                f.s.dot(f.t).abs() < 1e-5 && f.s.dot(n).abs() < 1e-5 && f.t.dot(n).abs() < 1e-5
            );
            let v = Vec3::new(0.2, -0.5, 0.7);
            assert!((f.to_local(f.to_world(v)) - v).length() < 1e-5);
        }
    }
}
