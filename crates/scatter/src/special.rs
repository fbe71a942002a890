//! The special functions microfacet sampling needs: the error function (from `libm`,
//! the Rust port of musl's, exact to an ulp) and its inverse.

/// The error function erf(x), in double precision.
#[inline]
pub fn erf(x: f64) -> f64 {
    libm::erf(x)
}

/// The complementary error function erfc(x) = 1 - erf(x), without cancellation for
/// large x.
#[inline]
pub fn erfc(x: f64) -> f64 {
    libm::erfc(x)
}

/// The inverse error function on (-1, 1): Giles' single-precision rational
/// approximation (M. Giles, "Approximating the erfinv function", *GPU Computing Gems*,
/// 2011), refined by two Newton steps on [`erf`] to double precision. ±∞ at ±1.
pub fn erfinv(y: f64) -> f64 {
    if y <= -1.0 {
        return f64::NEG_INFINITY;
    }
    if y >= 1.0 {
        return f64::INFINITY;
    }
    let w = -((1.0 - y) * (1.0 + y)).ln();
    let p = if w < 5.0 {
        let w = w - 2.5;
        [
            3.43273939e-07,
            -3.5233877e-06,
            -4.39150654e-06,
            0.00021858087,
            -0.00125372503,
            -0.00417768164,
            0.246640727,
            1.50140941,
        ]
        .iter()
        .fold(2.81022636e-08, |p, c| c + p * w)
    } else {
        let w = w.sqrt() - 3.0;
        [
            0.000100950558,
            0.00134934322,
            -0.00367342844,
            0.00573950773,
            -0.0076224613,
            0.00943887047,
            1.00167406,
            2.83297682,
        ]
        .iter()
        .fold(-0.000200214257, |p, c| c + p * w)
    };
    let mut x = p * y;
    // Newton on erf(x) = y: erf'(x) = 2/√π e^{-x²}.
    for _ in 0..2 {
        let d = 2.0 / std::f64::consts::PI.sqrt() * (-x * x).exp();
        if d > 0.0 {
            x -= (erf(x) - y) / d;
        }
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn erfinv_inverts_erf() {
        for i in -399..400 {
            let x = i as f64 / 100.0;
            let y = erf(x);
            if y.abs() < 1.0 - 1e-15 {
                let back = erfinv(y);
                assert!((back - x).abs() < 1e-9 * x.abs().max(1.0), "{x}: {back}");
            }
        }
        assert_eq!(erfinv(0.0), 0.0);
        assert!(erfinv(1.0).is_infinite());
    }
}
