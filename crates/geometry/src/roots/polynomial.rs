//! Polynomials with f64 coefficients (ascending order) and the stable quadratic formula.

/// `c[0] + c[1] x + c[2] x² + ...`. At most degree 8 is expected (fixed-size storage
/// keeps the root finder free of allocation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polynomial {
    coeffs: [f64; 9],
    len: usize,
}

impl Polynomial {
    /// From ascending coefficients; trailing (highest-degree) exact zeros are dropped.
    /// Panics on more than 9 coefficients.
    pub fn new(ascending: &[f64]) -> Self {
        assert!(ascending.len() <= 9, "polynomial degree above 8");
        let mut coeffs = [0.0; 9];
        coeffs[..ascending.len()].copy_from_slice(ascending);
        let mut len = ascending.len();
        while len > 0 && coeffs[len - 1] == 0.0 {
            len -= 1;
        }
        Self { coeffs, len }
    }

    /// The coefficients, ascending, without trailing zeros.
    pub fn coeffs(&self) -> &[f64] {
        &self.coeffs[..self.len]
    }

    /// Degree; the zero polynomial has degree 0 here (check [`Polynomial::is_zero`]).
    pub fn degree(&self) -> usize {
        self.len.saturating_sub(1)
    }

    pub fn is_zero(&self) -> bool {
        self.len == 0
    }

    /// Value at `x` (Horner's rule).
    #[inline]
    pub fn eval(&self, x: f64) -> f64 {
        self.coeffs().iter().rev().fold(0.0, |acc, &c| acc * x + c)
    }

    /// Value and first derivative at `x` (Horner's rule carried for both).
    #[inline]
    pub fn eval_with_derivative(&self, x: f64) -> (f64, f64) {
        let mut p = 0.0;
        let mut dp = 0.0;
        for &c in self.coeffs().iter().rev() {
            dp = dp * x + p;
            p = p * x + c;
        }
        (p, dp)
    }

    pub fn derivative(&self) -> Polynomial {
        let mut out = [0.0; 9];
        for i in 1..self.len {
            out[i - 1] = self.coeffs[i] * i as f64;
        }
        Polynomial::new(&out[..self.len.saturating_sub(1)])
    }
}

/// Real roots of `a x² + b x + c` in increasing order (0, 1 or 2 of them; a double root
/// is reported twice). Uses `q = -(b + sign(b) sqrt(disc)) / 2`, `x = q/a, c/q`, which
/// avoids the cancellation of the textbook formula. Degenerates to the linear case when
/// `a == 0`.
pub fn solve_quadratic(a: f64, b: f64, c: f64) -> ([f64; 2], usize) {
    if a == 0.0 {
        if b == 0.0 {
            return ([0.0; 2], 0);
        }
        return ([-c / b, 0.0], 1);
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return ([0.0; 2], 0);
    }
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    if q == 0.0 {
        // b == 0 and c == 0: the double root 0.
        return ([0.0, 0.0], 2);
    }
    let (x0, x1) = (q / a, c / q);
    if x0 <= x1 {
        ([x0, x1], 2)
    } else {
        ([x1, x0], 2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn horner_and_derivative() {
        let p = Polynomial::new(&[1.0, -3.0, 0.0, 2.0, 0.0]);
        assert_eq!(p.degree(), 3);
        assert_eq!(p.eval(2.0), 1.0 - 6.0 + 16.0);
        let (v, d) = p.eval_with_derivative(2.0);
        assert_eq!(v, 11.0);
        assert_eq!(d, -3.0 + 6.0 * 4.0);
        assert_eq!(p.derivative().coeffs(), &[-3.0, 0.0, 6.0]);
    }

    #[test]
    fn stable_quadratic_keeps_the_small_root() {
        // x² - 1e8 x + 1 = 0: roots 1e-8 and 1e8; the textbook formula loses the small one.
        let (r, n) = solve_quadratic(1.0, -1e8, 1.0);
        assert_eq!(n, 2);
        assert!((r[0] - 1e-8).abs() < 1e-22);
        assert!((r[1] - 1e8).abs() < 1e-6);
    }
}
