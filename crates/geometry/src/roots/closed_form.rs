//! Closed-form cubic (Cardano / Viète) and quartic (Ferrari) solutions, each root
//! polished with Newton steps on the original polynomial. Cancellation in these
//! formulas can lose roots that are close together; ray casting uses
//! [`super::real_roots_in`], and this module serves as an independent cross-check.

use super::polynomial::{solve_quadratic, Polynomial};
use std::f64::consts::PI;

/// Real roots of `x³ + a x² + b x + c`, ascending (1 to 3 of them).
pub fn solve_cubic(a: f64, b: f64, c: f64) -> Vec<f64> {
    // Depress: x = y - a/3 gives y³ + p y + q.
    let p = b - a * a / 3.0;
    let q = 2.0 * a * a * a / 27.0 - a * b / 3.0 + c;
    let shift = -a / 3.0;
    let disc = q * q / 4.0 + p * p * p / 27.0;
    let mut roots = if disc > 0.0 {
        // One real root (Cardano).
        let s = disc.sqrt();
        vec![(-q / 2.0 + s).cbrt() + (-q / 2.0 - s).cbrt() + shift]
    } else if p == 0.0 {
        vec![shift]
    } else {
        // Three real roots (Viète's trigonometric form).
        let m = 2.0 * (-p / 3.0).sqrt();
        let arg = (3.0 * q / (p * m)).clamp(-1.0, 1.0);
        let theta = arg.acos() / 3.0;
        (0..3)
            .map(|k| m * (theta - 2.0 * PI * k as f64 / 3.0).cos() + shift)
            .collect()
    };
    let poly = Polynomial::new(&[c, b, a, 1.0]);
    for r in roots.iter_mut() {
        *r = newton_polish(&poly, *r);
    }
    roots.sort_by(f64::total_cmp);
    roots
}

/// Real roots of `x⁴ + a x³ + b x² + c x + d`, ascending (Ferrari's method: the
/// depressed quartic factored into two quadratics through a root of the resolvent
/// cubic), each polished by Newton on the original quartic.
pub fn solve_quartic(a: f64, b: f64, c: f64, d: f64) -> Vec<f64> {
    // Depress: x = y - a/4 gives y⁴ + p y² + q y + r.
    let shift = -a / 4.0;
    let a2 = a * a;
    let p = b - 3.0 * a2 / 8.0;
    let q = c - a * b / 2.0 + a2 * a / 8.0;
    let r = d - a * c / 4.0 + a2 * b / 16.0 - 3.0 * a2 * a2 / 256.0;
    let mut ys = Vec::with_capacity(4);
    let scale = p.abs().max(r.abs().sqrt()).max(1e-300);
    if q.abs() <= 1e-14 * scale * scale.sqrt() {
        // Biquadratic: z² + p z + r with z = y².
        let (zs, n) = solve_quadratic(1.0, p, r);
        for &z in &zs[..n] {
            if z >= 0.0 {
                ys.push(z.sqrt());
                ys.push(-z.sqrt());
            }
        }
    } else {
        // (y² + s y + t)(y² - s y + v) with z = s² a root of the resolvent
        // z³ + 2p z² + (p² - 4r) z - q² = 0 (it always has a positive root).
        let z = solve_cubic(2.0 * p, p * p - 4.0 * r, -q * q)
            .into_iter()
            .fold(f64::NEG_INFINITY, f64::max);
        if z > 0.0 {
            let s = z.sqrt();
            let t = 0.5 * (p + z - q / s);
            let v = 0.5 * (p + z + q / s);
            for (bq, cq) in [(s, t), (-s, v)] {
                let (rs, n) = solve_quadratic(1.0, bq, cq);
                ys.extend_from_slice(&rs[..n]);
            }
        }
    }
    let poly = Polynomial::new(&[d, c, b, a, 1.0]);
    let mut xs: Vec<f64> = ys
        .into_iter()
        .map(|y| newton_polish(&poly, y + shift))
        .collect();
    xs.sort_by(f64::total_cmp);
    xs
}

/// A few Newton steps, kept only while they reduce |p|.
fn newton_polish(p: &Polynomial, mut x: f64) -> f64 {
    let mut fx = p.eval(x).abs();
    for _ in 0..4 {
        let (v, d) = p.eval_with_derivative(x);
        if d == 0.0 || v == 0.0 {
            break;
        }
        let nx = x - v / d;
        let nf = p.eval(nx).abs();
        if nf >= fx {
            break;
        }
        x = nx;
        fx = nf;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quartic_with_four_known_roots() {
        // (x+2)(x-0.5)(x-3)(x-7) = x⁴ - 8.5x³ + 5x² + 41.5x - 21
        let r = solve_quartic(-8.5, 5.0, 41.5, -21.0);
        let want = [-2.0, 0.5, 3.0, 7.0];
        assert_eq!(r.len(), 4, "{r:?}");
        for (x, w) in r.iter().zip(want) {
            assert!((x - w).abs() < 1e-12, "{r:?}");
        }
    }

    #[test]
    fn cubic_three_roots() {
        // (x-1)(x-2)(x+3) = x³ - 7x + 6
        let r = solve_cubic(0.0, -7.0, 6.0);
        assert_eq!(r.len(), 3);
        for (x, w) in r.iter().zip([-3.0, 1.0, 2.0]) {
            assert!((x - w).abs() < 1e-13);
        }
    }
}
