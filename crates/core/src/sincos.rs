//! Sine and cosine together by a polynomial, for the angles computed per sample on hot
//! paths (the environment map's direction of a light sample), where the C library's
//! `sincosf` is a call per angle that showed in profiles and that lanes cannot share.
//! The lane version ([`irradia_geometry::packet::lanes`]'s `sin_cos`) evaluates the
//! same operations in the same order, so both give the same bits.
//!
//! The argument is reduced to `r = x - k π/2 ∈ [-π/4, π/4]` with `k` the integer nearest `x / (π/2)` (ties to even)
//! and `π/2` split in three parts whose products with `k` are exact for `|k| < 2¹²`
//! (Cody and Waite, *Software Manual for the Elementary Functions*, 1980, ch. 8);
//! `sin r` and `cos r` are the minimax polynomials of Cephes' `sinf` / `cosf` (Moshier,
//! *Methods and Programs for Mathematical Functions*, 1989), and `k mod 4` picks the
//! quadrant (`sin(r + kπ/2)` is `sin r`, `cos r`, `-sin r`, `-cos r`). Within 3·10⁻⁷ of
//! the exact values for `|x| ≤ 1000` (the test checks it against `f64`); meant for
//! angles of a few turns, not for arguments of any size.

/// `π/2` in three parts, each with trailing zero bits so that `k` times it is exact.
pub const PI_2_PARTS: [f32; 3] = [1.570_312_5, 4.837_513e-4, 7.549_79e-8];

/// Cephes' coefficients of `sin a = a + a z P(z)` and `cos a = 1 - z/2 + z² Q(z)`,
/// `z = a²`, highest power first (public so that lane versions evaluate the same
/// polynomials in the same order).
pub const SIN_COEFFS: [f32; 3] = [-1.951_529_6e-4, 8.332_161e-3, -1.666_665_5e-1];
pub const COS_COEFFS: [f32; 3] = [2.443_315_7e-5, -1.388_731_6e-3, 4.166_664_6e-2];

/// Sine and cosine of `a` for `|a| <= π/4` (Cephes' polynomials).
#[inline(always)]
pub fn sin_cos_quarter_pi(a: f32) -> (f32, f32) {
    let (p, q) = (SIN_COEFFS, COS_COEFFS);
    let z = a * a;
    let s = ((p[0] * z + p[1]) * z + p[2]) * z * a + a;
    let c = ((q[0] * z + q[1]) * z + q[2]) * z * z - 0.5 * z + 1.0;
    (s, c)
}

/// `(sin x, cos x)` (NaN for a NaN or infinite `x`).
#[inline]
pub fn sin_cos(x: f32) -> (f32, f32) {
    let k = (x * std::f32::consts::FRAC_2_PI).round_ties_even();
    let r = ((x - k * PI_2_PARTS[0]) - k * PI_2_PARTS[1]) - k * PI_2_PARTS[2];
    let (s, c) = sin_cos_quarter_pi(r);
    let q = k as i32 & 3;
    let (s, c) = if q & 1 != 0 { (c, -s) } else { (s, c) };
    if q & 2 != 0 {
        (-s, -c)
    } else {
        (s, c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The three parts add up to `π/2` within `f64` rounding, and each has at least 12
    /// trailing zero bits (so `k` times it is exact for `|k| < 2¹²`), but the last.
    #[test]
    fn parts_of_half_pi() {
        let sum: f64 = PI_2_PARTS.iter().map(|&p| p as f64).sum();
        assert!((sum - std::f64::consts::FRAC_PI_2).abs() < 1e-14, "{sum}");
        for p in &PI_2_PARTS[..2] {
            assert!(p.to_bits().trailing_zeros() >= 12, "{p}");
        }
    }

    /// Within 3·10⁻⁷ of `f64`'s sine and cosine over a few turns either way, densely,
    /// and up to 1000; exact at 0; NaN for NaN and infinities.
    #[test]
    fn matches_f64_closely() {
        let mut worst = 0.0f64;
        let mut check = |x: f32| {
            let (s, c) = sin_cos(x);
            let (ws, wc) = (x as f64).sin_cos();
            worst = worst.max((s as f64 - ws).abs()).max((c as f64 - wc).abs());
        };
        for k in 0..400_000 {
            check(-13.0 + 26.0 * k as f32 / 400_000.0);
        }
        for k in 0..100_000 {
            check(1000.0 * k as f32 / 100_000.0);
        }
        for x in [
            0.0,
            1e-30,
            std::f32::consts::PI,
            std::f32::consts::TAU,
            f32::from_bits(std::f32::consts::TAU.to_bits() - 1),
        ] {
            check(x);
            check(-x);
        }
        assert!(worst < 3e-7, "worst error {worst}");
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        for x in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            let (s, c) = sin_cos(x);
            assert!(s.is_nan() && c.is_nan(), "{x}");
        }
    }
}
