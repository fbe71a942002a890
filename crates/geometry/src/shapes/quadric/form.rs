//! The quadratic form `Q(p) = pᵀA p + bᵀp + c` (lecture: "Quadrics") in f64, and the
//! parameter intervals in which a ray lies inside the solid `Q ≤ 0`.
//!
//! Substituting the ray `p(t) = o + t d` gives the quadratic `α t² + β t + γ` with
//! `α = dᵀA d`, `β = 2 oᵀA d + bᵀd`, `γ = Q(o)`. Its roots come from the numerically
//! stable form of the quadratic formula (`q = -(β + sign(β)√Δ)/2`, roots `q/α` and
//! `γ/q`: no subtraction of nearly equal numbers; Press et al., *Numerical Recipes*
//! §5.6), and each root is then polished by Newton's method on `Q` evaluated directly at
//! the point `o + t d`. The direct evaluation matters when the ray starts far from the
//! surface: `γ = Q(o)` is then a large number whose rounding error would otherwise set
//! the root's error, while `Q(p)` near the surface is small.

// `!(x > 0.0)` is deliberate: it is also true for NaN, which must be refused too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use glam::{DAffine3, DMat3, DVec3};

/// `pᵀA p + bᵀp + c` with `A` symmetric. The solid is the set `Q ≤ 0`; the gradient
/// `2 A p + b` points out of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadricForm {
    pub a: DMat3,
    pub b: DVec3,
    pub c: f64,
}

/// Up to two intervals `[t0, t1]` (ends may be infinite) in increasing order.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LineIntervals {
    pub len: usize,
    pub iv: [(f64, f64); 2],
}

impl LineIntervals {
    fn push(&mut self, t0: f64, t1: f64) {
        self.iv[self.len] = (t0, t1);
        self.len += 1;
    }
    pub fn as_slice(&self) -> &[(f64, f64)] {
        &self.iv[..self.len]
    }
}

impl QuadricForm {
    /// From POV-Ray's ten coefficients `[A, B, C, D, E, F, G, H, I, J]` of
    /// `A x² + B y² + C z² + D xy + E xz + F yz + G x + H y + I z + J`.
    pub fn from_coefficients(k: [f64; 10]) -> Self {
        let [a, b, c, d, e, f, g, h, i, j] = k;
        Self {
            a: DMat3::from_cols(
                DVec3::new(a, 0.5 * d, 0.5 * e),
                DVec3::new(0.5 * d, b, 0.5 * f),
                DVec3::new(0.5 * e, 0.5 * f, c),
            ),
            b: DVec3::new(g, h, i),
            c: j,
        }
    }

    /// The ten coefficients in POV-Ray's order (the inverse of `from_coefficients`).
    pub fn coefficients(&self) -> [f64; 10] {
        let a = &self.a;
        [
            a.x_axis.x,
            a.y_axis.y,
            a.z_axis.z,
            2.0 * a.y_axis.x,
            2.0 * a.z_axis.x,
            2.0 * a.z_axis.y,
            self.b.x,
            self.b.y,
            self.b.z,
            self.c,
        ]
    }

    #[inline]
    pub fn value(&self, p: DVec3) -> f64 {
        p.dot(self.a * p) + self.b.dot(p) + self.c
    }

    #[inline]
    pub fn gradient(&self, p: DVec3) -> DVec3 {
        2.0 * (self.a * p) + self.b
    }

    /// A bound on the rounding error of `value(p)`: a few units of f64 rounding of the
    /// sum of the magnitudes of its terms (Higham, *Accuracy and Stability of Numerical
    /// Algorithms*, §3.1, for a sum of products).
    #[inline]
    pub fn value_error(&self, p: DVec3) -> f64 {
        let ap = p.abs();
        let abs_a = DMat3::from_cols(
            self.a.x_axis.abs(),
            self.a.y_axis.abs(),
            self.a.z_axis.abs(),
        );
        let mag = ap.dot(abs_a * ap) + self.b.abs().dot(ap) + self.c.abs();
        mag * 16.0 * f64::EPSILON
    }

    /// The same surface after the affine map `to_world` (object to world): the form
    /// `Q'(p) = Q(M⁻¹(p - t))`, expanded back into `A'`, `b'`, `c'`.
    pub fn transformed(&self, to_world: &DAffine3) -> Self {
        let inv = to_world.inverse();
        let n = inv.matrix3;
        let s = inv.translation;
        let ns = n.transpose();
        let a = ns * self.a * n;
        // Symmetrise to remove rounding asymmetry.
        let a = (a + a.transpose()) * 0.5;
        let b = ns * (2.0 * (self.a * s) + self.b);
        let c = s.dot(self.a * s) + self.b.dot(s) + self.c;
        Self { a, b, c }
    }

    /// Newton's method on `Q(o + t d)` evaluated at the point, at most two steps, each
    /// kept only when it lowers `|Q|` (so a step can never make a root worse).
    #[inline]
    fn polish(&self, o: DVec3, d: DVec3, t: f64) -> f64 {
        let mut t = t;
        let p = o + d * t;
        let mut ap = self.a * p;
        let mut f = p.dot(ap) + self.b.dot(p) + self.c;
        for _ in 0..2 {
            if f == 0.0 {
                break;
            }
            let df = (2.0 * ap + self.b).dot(d);
            let tn = t - f / df;
            if !tn.is_finite() {
                break;
            }
            let pn = o + d * tn;
            let apn = self.a * pn;
            let fnew = pn.dot(apn) + self.b.dot(pn) + self.c;
            if fnew.abs() < f.abs() {
                t = tn;
                ap = apn;
                f = fnew;
            } else {
                break;
            }
        }
        t
    }

    /// The parameter intervals in which `o + t d` lies in the solid `Q ≤ 0`, over the
    /// whole line (ends may be `±∞`). Roots are polished by Newton's method.
    pub fn inside_intervals(&self, o: DVec3, d: DVec3) -> LineIntervals {
        self.intervals(o, d, true)
    }

    /// As `inside_intervals`, for a solid known to lie around `centre`: the ray's origin
    /// is first moved along the ray to the point nearest `centre` (as Haines et al. do
    /// for spheres, "Precision Improvements for Ray/Sphere Intersection", Ray Tracing
    /// Gems ch. 7), so that `γ = Q(o')` is of the size of the solid rather than of the
    /// distance to it; the roots are then accurate without the Newton polish, and the
    /// shift is added back.
    pub fn inside_intervals_near(&self, o: DVec3, d: DVec3, centre: DVec3) -> LineIntervals {
        let shift = (centre - o).dot(d) / d.dot(d);
        if !shift.is_finite() {
            return self.intervals(o, d, true);
        }
        let mut iv = self.intervals(o + d * shift, d, false);
        for (a, b) in iv.iv[..iv.len].iter_mut() {
            *a += shift;
            *b += shift;
        }
        iv
    }

    #[inline]
    fn intervals(&self, o: DVec3, d: DVec3, polish: bool) -> LineIntervals {
        let polish = |t: f64| if polish { self.polish(o, d, t) } else { t };
        let mut out = LineIntervals::default();
        let ad = self.a * d;
        let alpha = d.dot(ad);
        let beta = 2.0 * o.dot(ad) + self.b.dot(d);
        let gamma = self.value(o);
        if alpha == 0.0 {
            // Linear in t (a ray parallel to a cylinder's axis, say).
            if beta > 0.0 {
                out.push(f64::NEG_INFINITY, polish(-gamma / beta));
            } else if beta < 0.0 {
                out.push(polish(-gamma / beta), f64::INFINITY);
            } else if gamma <= 0.0 {
                out.push(f64::NEG_INFINITY, f64::INFINITY);
            }
            return out;
        }
        let disc = beta * beta - 4.0 * alpha * gamma;
        if !(disc >= 0.0) {
            if alpha < 0.0 && !disc.is_nan() {
                out.push(f64::NEG_INFINITY, f64::INFINITY);
            }
            return out;
        }
        let q = -0.5 * (beta + disc.sqrt().copysign(beta));
        let r0 = q / alpha;
        let r1 = if q != 0.0 { gamma / q } else { r0 };
        let (lo, hi) = if r0 <= r1 { (r0, r1) } else { (r1, r0) };
        let (mut t0, mut t1) = (lo, hi);
        if t0.is_finite() {
            t0 = polish(t0);
        }
        if t1.is_finite() {
            t1 = polish(t1);
        }
        if !(t0 <= t1) {
            // Polishing a nearly double root can swap the pair; keep the unpolished ones.
            t0 = lo;
            t1 = hi;
        }
        if alpha > 0.0 {
            out.push(t0, t1);
        } else {
            out.push(f64::NEG_INFINITY, t0);
            out.push(t1, f64::INFINITY);
        }
        out
    }

    /// Whether the quadratic part is positive definite (an ellipsoid or empty set).
    pub fn is_positive_definite(&self) -> bool {
        let a = &self.a;
        let m1 = a.x_axis.x;
        let m2 = a.x_axis.x * a.y_axis.y - a.y_axis.x * a.x_axis.y;
        let m3 = a.determinant();
        m1 > 0.0 && m2 > 0.0 && m3 > 0.0
    }

    /// Bounds of the solid when `A` is positive definite: the ellipsoid has centre
    /// `-A⁻¹b/2` and, with `k = centreᵀA centre - c`, half-extent `√(k (A⁻¹)ᵢᵢ)` on
    /// axis `i` (the support function of an ellipsoid). `None` otherwise or when empty.
    pub fn ellipsoid_bounds(&self) -> Option<(DVec3, DVec3)> {
        if !self.is_positive_definite() {
            return None;
        }
        let inv = self.a.inverse();
        let centre = -0.5 * (inv * self.b);
        let k = centre.dot(self.a * centre) - self.c;
        if !(k > 0.0) {
            return None;
        }
        let half = DVec3::new(
            (k * inv.x_axis.x).sqrt(),
            (k * inv.y_axis.y).sqrt(),
            (k * inv.z_axis.z).sqrt(),
        );
        Some((centre - half, centre + half))
    }
}
