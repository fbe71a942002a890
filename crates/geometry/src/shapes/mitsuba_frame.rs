//! The orthonormal frame Mitsuba 3 builds around a unit vector (its `Frame3f(n)`, the
//! branchless construction of Duff et al., "Building an Orthonormal Basis, Revisited",
//! JCGT 2017). Mitsuba's disk and cylinder measure their azimuth `phi` from the first
//! tangent towards the second, so shapes that take Mitsuba's parameterisation build
//! the same frame to report the same texture coordinates.

use glam::DVec3;

/// The tangents `(s, t)` of Mitsuba's frame around the unit vector `n`: `(s, t, n)` is
/// right-handed and orthonormal, and for `n = +z` it is `(+x, +y)`.
pub fn mitsuba_frame(n: DVec3) -> (DVec3, DVec3) {
    let sign = 1f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        DVec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

/// The azimuth of `(x, y)` as a fraction of a turn in `[0, 1)`, as Mitsuba reports it
/// (`atan2(y, x) / 2π`, plus one turn when negative).
pub fn turn_fraction(y: f64, x: f64) -> f64 {
    let f = y.atan2(x) / std::f64::consts::TAU;
    if f < 0.0 {
        // A tiny negative angle would round to exactly 1: keep the range half-open.
        (f + 1.0).min(1.0 - f64::EPSILON / 2.0)
    } else {
        f
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_is_orthonormal_right_handed_and_mitsubas_for_z() {
        let (s, t) = mitsuba_frame(DVec3::Z);
        assert_eq!((s, t), (DVec3::X, DVec3::Y));
        for n in [
            DVec3::new(0.3, -0.5, 0.8),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(0.1, 0.2, -0.97),
            -DVec3::Z,
        ] {
            let n = n.normalize();
            let (s, t) = mitsuba_frame(n);
            assert!((s.length() - 1.0).abs() < 1e-12 && (t.length() - 1.0).abs() < 1e-12);
            assert!(s.dot(t).abs() < 1e-12 && s.dot(n).abs() < 1e-12 && t.dot(n).abs() < 1e-12);
            assert!((s.cross(t) - n).length() < 1e-12);
        }
    }

    #[test]
    fn turn_fraction_is_half_open() {
        assert_eq!(turn_fraction(0.0, 1.0), 0.0);
        assert!((turn_fraction(1.0, 0.0) - 0.25).abs() < 1e-15);
        assert!((turn_fraction(-1.0, 0.0) - 0.75).abs() < 1e-15);
        assert!(turn_fraction(-1e-300, 1.0) < 1.0);
    }
}
