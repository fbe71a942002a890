//! Implicit surfaces `f(x, y, z) = 0` given as an expression (see `crate::expr`), inside a
//! required bounding box; the solid is `f < 0` within the box.
//!
//! Summary / public API:
//! - `ImplicitSurface::parse("x^2 + y^2 + z^2 - 1", bounds) -> Result<_, ImplicitError>`
//!   or `ImplicitSurface::new(expr, bounds)` with an `Expr` over `["x", "y", "z"]`: root
//!   isolation by interval arithmetic (the default, needs no constant from the user).
//! - `.with_lipschitz(L)`: sphere tracing with the user's Lipschitz bound `L` on `f`
//!   instead (`|f(a) - f(b)| <= L |a - b|`).
//! - `.with_tolerance(len)`: the finest ray segment (object-space length) examined;
//!   features thinner than this may be missed. Default: 1e-6 of the box diagonal.
//! - `lipschitz_violation() -> Option<f64>`: the largest ratio `|Δf| / |Δp|` observed
//!   above the given `L` (a proof that `L` is too small); `take_lipschitz_warning()`
//!   returns a message the first time only, for the renderer to print once.
//! - `abandoned_rays()`: rays whose search hit the work limit (counted, reported as misses).
//!
//! Root finding along a ray clipped to the box:
//! - Interval method (Mitchell, "Robust ray intersection with interval arithmetic",
//!   Graphics Interface 1990; Knoll et al., "Interactive ray tracing of arbitrary
//!   implicits with SIMD interval arithmetic", 2007): the parameter interval is split
//!   depth first, nearest half first, and a piece is dropped as soon as the interval
//!   enclosure of `f` over the piece's bounding box excludes 0. Since the enclosure is
//!   sound, no piece holding a root is ever dropped, however thin the feature; pieces that
//!   reach the tolerance length and show a sign change are refined by safeguarded Newton.
//!   Subdivision stops early on a piece where the enclosure of the derivative along the
//!   ray, `∇f · d` (interval dual numbers), excludes 0: `f` is monotone there, so it has
//!   a root exactly when its ends differ in sign (Mitchell's monotonicity test).
//! - Lipschitz method (Hart, "Sphere tracing", The Visual Computer 1996): steps of
//!   `|f| / L` (at least the tolerance) cannot jump over a surface when `L` is a true
//!   bound; each step compares `|Δf|` with `L |Δp|` and records a violation.
//!
//! Normals are `∇f / |∇f|` from forward-mode dual numbers (outward, since `f < 0` inside).
//! `Hit::error` bounds the distance from the reported point to the true surface: the
//! residual `|f| / |∇f|` at the root, the final bracket, and f32 rounding of the point.

// `!(a < b)` comparisons are deliberate: they are also true when a value is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::expr::{Expr, ExprError, Interval};
use crate::roots::refine_bracketed;
use crate::shape::{Boundary, Hit, Shape, Span};
use glam::{DVec3, Vec2, Vec3};
use irradia_core::{Aabb, Ray};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// How roots are found along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RootMethod {
    /// Interval-arithmetic root isolation (no constant needed).
    Interval,
    /// Sphere tracing with this Lipschitz bound on `f`.
    Lipschitz(f64),
}

/// Why an implicit surface could not be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ImplicitError {
    #[error("expression: {0}")]
    Expr(#[from] ExprError),
    #[error("the bounding box must be finite and non-empty (min {min:?}, max {max:?})")]
    BadBounds { min: [f32; 3], max: [f32; 3] },
    #[error("the expression must be over the variables x, y, z (got {0:?})")]
    BadVariables(Vec<String>),
    #[error("the Lipschitz bound must be positive and finite, got {0}")]
    BadLipschitz(f64),
    #[error("the tolerance must be positive and finite, got {0}")]
    BadTolerance(f64),
}

/// Interval evaluations allowed per root search before the ray is abandoned.
const MAX_INTERVAL_EVALS: usize = 20_000;
/// Sphere-tracing steps allowed per root search.
const MAX_TRACE_STEPS: usize = 20_000;

#[derive(Debug)]
pub struct ImplicitSurface {
    expr: Expr,
    bounds: Aabb,
    method: RootMethod,
    /// Finest segment length examined (object space).
    tolerance: f64,
    /// f64 bits of the largest `|Δf|/|Δp|` seen above the Lipschitz bound (0: none).
    violation_bits: AtomicU64,
    warned: AtomicBool,
    abandoned: AtomicU64,
}

impl ImplicitSurface {
    /// Parses `source` over `x, y, z`; interval root isolation inside `bounds`.
    pub fn parse(source: &str, bounds: Aabb) -> Result<Self, ImplicitError> {
        Self::new(Expr::parse(source, &["x", "y", "z"])?, bounds)
    }

    /// An expression over exactly the variables `x, y, z` (in that order).
    pub fn new(expr: Expr, bounds: Aabb) -> Result<Self, ImplicitError> {
        if expr.variables() != ["x", "y", "z"] {
            return Err(ImplicitError::BadVariables(expr.variables().to_vec()));
        }
        if !bounds.is_finite() || !(bounds.min.cmplt(bounds.max).all()) {
            return Err(ImplicitError::BadBounds {
                min: bounds.min.to_array(),
                max: bounds.max.to_array(),
            });
        }
        let diag = (bounds.max - bounds.min).as_dvec3().length();
        Ok(Self {
            expr,
            bounds,
            method: RootMethod::Interval,
            tolerance: 1e-6 * diag,
            violation_bits: AtomicU64::new(0),
            warned: AtomicBool::new(false),
            abandoned: AtomicU64::new(0),
        })
    }

    /// Sphere tracing with the Lipschitz bound `l` instead of interval isolation.
    pub fn with_lipschitz(mut self, l: f64) -> Result<Self, ImplicitError> {
        if !(l > 0.0 && l.is_finite()) {
            return Err(ImplicitError::BadLipschitz(l));
        }
        self.method = RootMethod::Lipschitz(l);
        Ok(self)
    }

    /// The finest segment length examined along a ray (object space).
    pub fn with_tolerance(mut self, len: f64) -> Result<Self, ImplicitError> {
        if !(len > 0.0 && len.is_finite()) {
            return Err(ImplicitError::BadTolerance(len));
        }
        self.tolerance = len;
        Ok(self)
    }

    pub fn expr(&self) -> &Expr {
        &self.expr
    }

    pub fn method(&self) -> RootMethod {
        self.method
    }

    /// The largest `|Δf| / |Δp|` observed that exceeds the given Lipschitz bound, if any.
    pub fn lipschitz_violation(&self) -> Option<f64> {
        let bits = self.violation_bits.load(Ordering::Relaxed);
        (bits != 0).then(|| f64::from_bits(bits))
    }

    /// A warning about a too-small Lipschitz bound, returned once (later calls give
    /// `None`), or `None` when no violation has been seen.
    pub fn take_lipschitz_warning(&self) -> Option<String> {
        let ratio = self.lipschitz_violation()?;
        let RootMethod::Lipschitz(l) = self.method else {
            return None;
        };
        if self.warned.swap(true, Ordering::Relaxed) {
            return None;
        }
        Some(format!(
            "implicit surface '{}': the Lipschitz bound {l} is too small: |f(a) - f(b)| / |a - b| \
             reached {ratio:.6} along a ray, so surfaces may have been skipped; use at least \
             {:.3} (or the interval method)",
            self.expr.source(),
            ratio * 1.1
        ))
    }

    /// Rays abandoned at the work limit (reported as misses).
    pub fn abandoned_rays(&self) -> u64 {
        self.abandoned.load(Ordering::Relaxed)
    }

    #[inline]
    fn f(&self, p: DVec3) -> f64 {
        self.expr.eval(&[p.x, p.y, p.z])
    }

    fn record_violation(&self, ratio: f64) {
        self.violation_bits
            .fetch_max(ratio.to_bits(), Ordering::Relaxed);
    }

    /// Parameter interval of the whole line inside the box, in f64.
    fn box_interval(&self, o: DVec3, d: DVec3) -> Option<(f64, f64)> {
        let (lo, hi) = (self.bounds.min.as_dvec3(), self.bounds.max.as_dvec3());
        let mut t0 = f64::NEG_INFINITY;
        let mut t1 = f64::INFINITY;
        for a in 0..3 {
            if d[a] == 0.0 {
                if o[a] < lo[a] || o[a] > hi[a] {
                    return None;
                }
                continue;
            }
            let (ta, tb) = ((lo[a] - o[a]) / d[a], (hi[a] - o[a]) / d[a]);
            t0 = t0.max(ta.min(tb));
            t1 = t1.min(ta.max(tb));
        }
        (t0 <= t1).then_some((t0, t1))
    }

    /// Roots of `f` along `o + t d` for `t` in `[ta, tb]`, in increasing order; stops
    /// after the first when `first_only`.
    fn roots(&self, o: DVec3, d: DVec3, ta: f64, tb: f64, first_only: bool, out: &mut Vec<f64>) {
        match self.method {
            RootMethod::Interval => self.roots_interval(o, d, ta, tb, first_only, out),
            RootMethod::Lipschitz(l) => self.roots_traced(o, d, ta, tb, l, first_only, out),
        }
    }

    /// Refines a sign change of `f` in `[a, b]`.
    fn refine(&self, o: DVec3, d: DVec3, a: f64, b: f64) -> f64 {
        refine_bracketed(
            |t| {
                let p = o + d * t;
                let (v, g) = self.expr.eval_gradient(&[p.x, p.y, p.z]);
                (v, DVec3::from(g).dot(d))
            },
            a,
            b,
        )
    }

    fn roots_interval(
        &self,
        o: DVec3,
        d: DVec3,
        ta: f64,
        tb: f64,
        first_only: bool,
        out: &mut Vec<f64>,
    ) {
        let dlen = d.length();
        let min_dt = self.tolerance / dlen;
        let mut stack: Vec<(f64, f64)> = vec![(ta, tb)];
        let mut evals = 0usize;
        while let Some((a, b)) = stack.pop() {
            evals += 1;
            if evals > MAX_INTERVAL_EVALS {
                self.abandoned.fetch_add(1, Ordering::Relaxed);
                return;
            }
            let (range, slope) = self.enclosure(o, d, a, b);
            if range.is_empty() || !range.contains(0.0) {
                continue;
            }
            // Strictly monotone along the ray on this piece (one root at most), or a
            // piece no longer than the tolerance: a root there exactly when the ends
            // differ in sign.
            if slope.lo > 0.0 || slope.hi < 0.0 || b - a <= min_dt {
                if self.end_root(o, d, a, b, out) && first_only {
                    return;
                }
                continue;
            }
            let mid = 0.5 * (a + b);
            stack.push((mid, b));
            stack.push((a, mid));
        }
    }

    /// The root of a piece `[a, b]` that holds at most one, found from its ends: `a`
    /// itself where `f(a) = 0` (not pushed again when the previous piece ended there),
    /// else a sign change refined. True when the piece has a root.
    fn end_root(&self, o: DVec3, d: DVec3, a: f64, b: f64, out: &mut Vec<f64>) -> bool {
        let (fa, fb) = (self.f(o + d * a), self.f(o + d * b));
        if fa == 0.0 {
            if out.last() != Some(&a) {
                out.push(a);
            }
        } else if fb == 0.0 {
            out.push(b);
        } else if (fa < 0.0) != (fb < 0.0) {
            out.push(self.refine(o, d, a, b));
        } else {
            return false;
        }
        true
    }

    /// Sound enclosures of `f` and of its derivative along the ray, `∇f · d`, over the
    /// points `o + t d`, `t` in `[a, b]`.
    fn enclosure(&self, o: DVec3, d: DVec3, a: f64, b: f64) -> (Interval, Interval) {
        let (pa, pb) = (o + d * a, o + d * b);
        let iv = |x: f64, y: f64| {
            let (lo, hi) = (x.min(y), x.max(y));
            // The points are computed in f64 with rounding: widen a little.
            let slack = 4.0 * f64::EPSILON * (lo.abs().max(hi.abs())) + 1e-300;
            Interval::new(lo - slack, hi + slack)
        };
        self.expr.eval_interval_directional(
            &[iv(pa.x, pb.x), iv(pa.y, pb.y), iv(pa.z, pb.z)],
            &[d.x, d.y, d.z],
        )
    }

    #[allow(clippy::too_many_arguments)]
    fn roots_traced(
        &self,
        o: DVec3,
        d: DVec3,
        ta: f64,
        tb: f64,
        l: f64,
        first_only: bool,
        out: &mut Vec<f64>,
    ) {
        let dlen = d.length();
        let min_dt = self.tolerance / dlen;
        let mut t = ta;
        let mut f = self.f(o + d * t);
        if f == 0.0 {
            out.push(t);
            if first_only {
                return;
            }
        }
        for _ in 0..MAX_TRACE_STEPS {
            if t >= tb {
                return;
            }
            let dt = (f.abs() / l / dlen).max(min_dt);
            let t_new = (t + dt).min(tb);
            let f_new = self.f(o + d * t_new);
            let ratio = (f_new - f).abs() / ((t_new - t) * dlen);
            if ratio > l * (1.0 + 1e-9) && ratio.is_finite() {
                self.record_violation(ratio);
            }
            if f_new == 0.0 || (f != 0.0 && (f < 0.0) != (f_new < 0.0)) {
                let root = if f_new == 0.0 {
                    t_new
                } else {
                    self.refine(o, d, t, t_new)
                };
                out.push(root);
                if first_only {
                    return;
                }
            }
            t = t_new;
            f = f_new;
        }
        self.abandoned.fetch_add(1, Ordering::Relaxed);
    }

    /// Outward unit normal at `p` (from the gradient) and the gradient's length.
    fn normal(&self, p: DVec3, fallback: DVec3) -> (DVec3, f64) {
        let (_, g) = self.expr.eval_gradient(&[p.x, p.y, p.z]);
        let g = DVec3::from(g);
        let len = g.length();
        if len > 0.0 && len.is_finite() {
            (g / len, len)
        } else {
            (fallback.normalize(), 0.0)
        }
    }

    fn uv(&self, p: DVec3) -> Vec2 {
        let c = self.bounds.center().as_dvec3();
        let q = p - c;
        let r = q.length().max(1e-300);
        Vec2::new(
            (0.5 + q.z.atan2(q.x) / std::f64::consts::TAU) as f32,
            ((q.y / r).clamp(-1.0, 1.0).acos() / std::f64::consts::PI) as f32,
        )
    }

    /// Point, normal, uv and error bound at a root `t`.
    fn surface(&self, o: DVec3, d: DVec3, t: f64) -> (Vec3, Vec3, Vec2, f32) {
        let p = o + d * t;
        let (n, glen) = self.normal(p, -d);
        let residual = if glen > 0.0 {
            self.f(p).abs() / glen
        } else {
            self.tolerance
        };
        // The bracket of the refinement is a few f64 ulps of t.
        let bracket = 4.0 * f64::EPSILON * t.abs() * d.length();
        let rounding = 4.0 * f32::EPSILON as f64 * p.abs().max_element();
        let error = 2.0 * (residual + bracket) + rounding;
        (p.as_vec3(), n.as_vec3(), self.uv(p), error as f32)
    }

    /// Outward normal of the box face through which the line leaves or enters at `t`.
    fn box_face_normal(&self, o: DVec3, d: DVec3, t: f64) -> Vec3 {
        let p = o + d * t;
        let (lo, hi) = (self.bounds.min.as_dvec3(), self.bounds.max.as_dvec3());
        let mut best = (f64::INFINITY, Vec3::X);
        for a in 0..3 {
            let mut n = Vec3::ZERO;
            n[a] = -1.0;
            if (p[a] - lo[a]).abs() < best.0 {
                best = ((p[a] - lo[a]).abs(), n);
            }
            n[a] = 1.0;
            if (p[a] - hi[a]).abs() < best.0 {
                best = ((p[a] - hi[a]).abs(), n);
            }
        }
        best.1
    }
}

impl Shape for ImplicitSurface {
    fn take_warnings(&self) -> Vec<String> {
        let mut out: Vec<String> = self.take_lipschitz_warning().into_iter().collect();
        let abandoned = self.abandoned.swap(0, Ordering::Relaxed);
        if abandoned > 0 {
            out.push(format!(
                "implicit surface '{}': {abandoned} rays were given up after the interval \
                 method's evaluation limit; thin features may be missing there",
                self.expr.source()
            ));
        }
        out
    }

    fn kind(&self) -> &'static str {
        "implicit"
    }

    fn bounds(&self) -> Aabb {
        self.bounds
    }

    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        if !(d.length_squared() > 0.0) {
            return None;
        }
        let (b0, b1) = self.box_interval(o, d)?;
        let (ta, tb) = (b0.max(0.0), b1.min(t_max as f64));
        if !(ta <= tb) {
            return None;
        }
        let mut roots = Vec::with_capacity(1);
        self.roots(o, d, ta, tb, true, &mut roots);
        let t = roots.into_iter().find(|&t| t > 0.0 && t < t_max as f64)?;
        let (p, n, uv, error) = self.surface(o, d, t);
        let mut h = Hit::new(t as f32, p, n, uv);
        h.error = error;
        Some(h)
    }

    fn is_solid(&self) -> bool {
        true
    }

    /// Spans of `f < 0` inside the box: between consecutive roots the sign of `f` at the
    /// midpoint decides; a span that is open where the line enters or leaves the box
    /// ends on the box face.
    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        if !(d.length_squared() > 0.0) {
            return;
        }
        let Some((ta, tb)) = self.box_interval(o, d) else {
            return;
        };
        let mut events = vec![ta];
        self.roots(o, d, ta, tb, false, &mut events);
        events.push(tb);
        let last = events.len() - 1;
        let boundary = |k: usize| {
            let t = events[k];
            if k == 0 || k == last {
                let p = o + d * t;
                Boundary::new(t as f32, self.box_face_normal(o, d, t), self.uv(p))
            } else {
                let (_, n, uv, _) = self.surface(o, d, t);
                Boundary::new(t as f32, n, uv)
            }
        };
        let mut open: Option<Boundary> = None;
        for k in 0..last {
            let (a, b) = (events[k], events[k + 1]);
            if !(b > a) {
                continue;
            }
            let inside = self.f(o + d * (0.5 * (a + b))) < 0.0;
            if inside && open.is_none() {
                open = Some(boundary(k));
            } else if !inside {
                if let Some(enter) = open.take() {
                    out.push(Span {
                        enter,
                        exit: boundary(k),
                    });
                }
            }
        }
        if let Some(enter) = open {
            out.push(Span {
                enter,
                exit: boundary(last),
            });
        }
    }
}
