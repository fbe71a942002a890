//! One bicubic Bézier patch `P(u, v) = Σ B_i(u) B_j(v) P_ij` (Bernstein basis; Farin,
//! *Curves and Surfaces for CAGD*, ch. 14): evaluation, first and mixed derivatives, and
//! normals that stay exact where a derivative vanishes (collapsed edges such as the
//! teapot's lid top and bottom, where one whole patch edge is a single point).

#![allow(clippy::needless_range_loop)]

use glam::{DVec3, Vec3};

/// A bicubic Bézier patch. `points[4 * i + j]` is `P_ij`: `i` runs along `u`, `j`
/// along `v`. The patch's own orientation is `∂P/∂u × ∂P/∂v`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BezierPatch {
    pub points: [Vec3; 16],
}

/// Cubic Bernstein polynomials at `t`.
#[inline]
fn bernstein(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t]
}

/// Derivatives of the cubic Bernstein polynomials at `t`.
#[inline]
fn bernstein_derivative(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [
        -3.0 * s * s,
        3.0 * s * s - 6.0 * s * t,
        6.0 * s * t - 3.0 * t * t,
        3.0 * t * t,
    ]
}

/// The cubic Bézier curve with control points `c` at `t`, in f64.
#[inline]
pub fn cubic_point(c: &[Vec3; 4], t: f64) -> DVec3 {
    let b = bernstein(t);
    c[0].as_dvec3() * b[0]
        + c[1].as_dvec3() * b[1]
        + c[2].as_dvec3() * b[2]
        + c[3].as_dvec3() * b[3]
}

/// Position and derivatives at a parameter point.
#[derive(Clone, Copy, Debug)]
pub struct PatchDerivatives {
    pub p: DVec3,
    pub du: DVec3,
    pub dv: DVec3,
    pub duv: DVec3,
}

impl BezierPatch {
    pub fn new(points: [Vec3; 16]) -> Self {
        Self { points }
    }

    #[inline]
    fn cp(&self, i: usize, j: usize) -> DVec3 {
        self.points[4 * i + j].as_dvec3()
    }

    /// The point at `(u, v)`, in f64.
    pub fn eval(&self, u: f64, v: f64) -> DVec3 {
        let (bu, bv) = (bernstein(u), bernstein(v));
        let mut p = DVec3::ZERO;
        for i in 0..4 {
            for j in 0..4 {
                p += self.cp(i, j) * (bu[i] * bv[j]);
            }
        }
        p
    }

    pub fn derivatives(&self, u: f64, v: f64) -> PatchDerivatives {
        let (bu, bv) = (bernstein(u), bernstein(v));
        let (du, dv) = (bernstein_derivative(u), bernstein_derivative(v));
        let mut r = PatchDerivatives {
            p: DVec3::ZERO,
            du: DVec3::ZERO,
            dv: DVec3::ZERO,
            duv: DVec3::ZERO,
        };
        for i in 0..4 {
            for j in 0..4 {
                let c = self.cp(i, j);
                r.p += c * (bu[i] * bv[j]);
                r.du += c * (du[i] * bv[j]);
                r.dv += c * (bu[i] * dv[j]);
                r.duv += c * (du[i] * dv[j]);
            }
        }
        r
    }

    /// Edge `k` as a cubic curve: 0 is `u = 0` (along v), 1 is `u = 1`, 2 is `v = 0`
    /// (along u), 3 is `v = 1`.
    pub fn edge(&self, k: usize) -> [Vec3; 4] {
        let p = &self.points;
        match k {
            0 => [p[0], p[1], p[2], p[3]],
            1 => [p[12], p[13], p[14], p[15]],
            2 => [p[0], p[4], p[8], p[12]],
            _ => [p[3], p[7], p[11], p[15]],
        }
    }

    /// A size for relative tolerances: the largest control-point spread.
    fn scale(&self) -> f64 {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for p in &self.points {
            lo = lo.min(p.as_dvec3());
            hi = hi.max(p.as_dvec3());
        }
        (hi - lo).max_element().max(f64::MIN_POSITIVE)
    }

    /// The unit normal `∂P/∂u × ∂P/∂v` at `(u, v)`, exact also where one derivative
    /// vanishes: on an edge collapsed to a point, `∂P/∂v = 0` along `u = const` (or
    /// `∂P/∂u = 0`), and the limit of the normal is `∂P/∂u × ∂²P/∂u∂v` (resp.
    /// `∂²P/∂u∂v × ∂P/∂v`), the first-order Taylor term of the vanishing derivative.
    /// Falls back to a nearby interior point, then to `+y`, only for patches degenerate
    /// beyond that (e.g. all control points equal).
    pub fn normal(&self, u: f64, v: f64) -> Vec3 {
        self.normal_f64(u, v).as_vec3()
    }

    pub fn normal_f64(&self, u: f64, v: f64) -> DVec3 {
        let s = self.scale();
        let tiny = 1e-9 * s;
        let d = self.derivatives(u, v);
        let n = d.du.cross(d.dv);
        if n.length() > tiny * s {
            return n.normalize();
        }
        // Which derivative vanished? Replace it by its Taylor term towards the interior.
        let candidates = [
            if d.dv.length() <= tiny {
                // ∂P/∂v(u, v) ≈ (u - u_edge) ∂²P/∂u∂v, with the interior at larger u when
                // u_edge = 0 and at smaller u when u_edge = 1.
                let sign = if u < 0.5 { 1.0 } else { -1.0 };
                d.du.cross(d.duv * sign)
            } else {
                DVec3::ZERO
            },
            if d.du.length() <= tiny {
                let sign = if v < 0.5 { 1.0 } else { -1.0 };
                (d.duv * sign).cross(d.dv)
            } else {
                DVec3::ZERO
            },
        ];
        for c in candidates {
            if c.length() > tiny * s {
                return c.normalize();
            }
        }
        // Step a little towards the centre of the parameter square.
        for step in [1e-6, 1e-4, 1e-2] {
            let (uu, vv) = (u + (0.5 - u) * step, v + (0.5 - v) * step);
            let d = self.derivatives(uu, vv);
            let n = d.du.cross(d.dv);
            if n.length() > tiny * s {
                return n.normalize();
            }
        }
        DVec3::Y
    }
}
