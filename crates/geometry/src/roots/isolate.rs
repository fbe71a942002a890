//! Every real root of a polynomial inside a finite interval, by derivative isolation
//! with safeguarded Newton refinement (see the module summary in `roots/mod.rs`).

// `!(a < b)` comparisons are deliberate: they are also true when a value is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::polynomial::Polynomial;

/// Most roots a polynomial of degree 8 can have.
const MAX_ROOTS: usize = 8;

/// Appends to `out`, in increasing order, the roots of `p` in `[lo, hi]`: every point
/// where `p` changes sign, and points where `p` is exactly zero at the end of a monotone
/// piece. A root of even multiplicity at which `p` does not change sign (a ray grazing a
/// surface) is reported only if `p` evaluates to exactly zero there.
///
/// `lo` and `hi` must be finite with `lo <= hi`.
pub fn real_roots_in(p: &Polynomial, lo: f64, hi: f64, out: &mut Vec<f64>) {
    let (roots, n) = roots_rec(p, lo, hi);
    out.extend_from_slice(&roots[..n]);
}

fn roots_rec(p: &Polynomial, lo: f64, hi: f64) -> ([f64; MAX_ROOTS], usize) {
    let mut roots = [0.0; MAX_ROOTS];
    let mut n = 0;
    if p.is_zero() || p.degree() == 0 || !(lo <= hi) {
        return (roots, 0);
    }
    if p.degree() == 1 {
        let c = p.coeffs();
        let x = -c[0] / c[1];
        if x >= lo && x <= hi {
            roots[0] = x;
            n = 1;
        }
        return (roots, n);
    }
    // Critical points split [lo, hi] into pieces where p is monotone.
    let (crit, nc) = roots_rec(&p.derivative(), lo, hi);
    let mut breaks = [0.0; MAX_ROOTS + 2];
    breaks[0] = lo;
    let mut nb = 1;
    for &c in &crit[..nc] {
        if c > breaks[nb - 1] && c < hi {
            breaks[nb] = c;
            nb += 1;
        }
    }
    breaks[nb] = hi;
    nb += 1;

    let push = |x: f64, roots: &mut [f64; MAX_ROOTS], n: &mut usize| {
        if *n < MAX_ROOTS && (*n == 0 || roots[*n - 1] != x) {
            roots[*n] = x;
            *n += 1;
        }
    };
    let mut fa = p.eval(breaks[0]);
    for k in 0..nb - 1 {
        let (a, b) = (breaks[k], breaks[k + 1]);
        let fb = p.eval(b);
        if fa == 0.0 {
            push(a, &mut roots, &mut n);
        } else if fb != 0.0 && (fa < 0.0) != (fb < 0.0) {
            let x = refine_bracketed(|x| p.eval_with_derivative(x), a, b);
            push(x, &mut roots, &mut n);
        }
        fa = fb;
    }
    if fa == 0.0 {
        push(breaks[nb - 1], &mut roots, &mut n);
    }
    (roots, n)
}

/// The root of `f` in `[a, b]`, where `f(a)` and `f(b)` have opposite signs, to full
/// f64 precision. `f` returns the value and the derivative. Newton steps are taken while
/// they stay inside the bracket, which shrinks with every evaluation; bisection
/// otherwise (Numerical Recipes, 3rd ed., §9.4, "rtsafe"). Always converges.
pub fn refine_bracketed(mut f: impl FnMut(f64) -> (f64, f64), a: f64, b: f64) -> f64 {
    let (mut a, mut b) = if a <= b { (a, b) } else { (b, a) };
    let fa_neg = f(a).0 < 0.0;
    let mut x = 0.5 * (a + b);
    for _ in 0..200 {
        let (fx, dfx) = f(x);
        if fx == 0.0 || fx.is_nan() {
            return x;
        }
        if (fx < 0.0) == fa_neg {
            a = x;
        } else {
            b = x;
        }
        let newton = x - fx / dfx;
        let next = if newton > a && newton < b {
            newton
        } else {
            0.5 * (a + b)
        };
        let tol = f64::EPSILON * next.abs();
        if (next - x).abs() <= tol || b - a <= 2.0 * tol || next == a || next == b {
            return next;
        }
        x = next;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_all_roots_of_a_product() {
        // (x-1)(x-2)(x-3)(x-4) = x⁴ - 10x³ + 35x² - 50x + 24
        let p = Polynomial::new(&[24.0, -50.0, 35.0, -10.0, 1.0]);
        let mut r = Vec::new();
        real_roots_in(&p, -10.0, 10.0, &mut r);
        assert_eq!(r.len(), 4);
        for (i, x) in r.iter().enumerate() {
            assert!((x - (i + 1) as f64).abs() < 1e-13, "{r:?}");
        }
        r.clear();
        real_roots_in(&p, 1.5, 3.5, &mut r);
        assert_eq!(r.len(), 2);
    }

    #[test]
    fn close_roots_are_separated() {
        // (x - 1)(x - (1 + 1e-7)): the derivative's root isolates them.
        let e = 1e-7;
        let p = Polynomial::new(&[1.0 + e, -(2.0 + e), 1.0]);
        let mut r = Vec::new();
        real_roots_in(&p, 0.0, 2.0, &mut r);
        assert_eq!(r.len(), 2);
        assert!(r[0] < 1.0 + 0.5 * e && r[1] > 1.0 + 0.5 * e);
        assert!((r[0] - 1.0).abs() < 1e-8 && (r[1] - 1.0 - e).abs() < 1e-8);
    }
}
