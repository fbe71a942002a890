//! The torus: major radius `R` (centre of the tube to the axis), minor radius `r`
//! (the tube), axis `y`, centred at the origin (place it with an `Instance`).
//!
//! Summary / public API:
//! - `Torus::new(major, minor)` (panics unless `0 < minor < major`, finite) and
//!   `Torus::try_new(major, minor) -> Result<Torus, String>` for loaders.
//! - A closed solid: `spans` gives up to two entry/exit spans per ray for CSG.
//! - Exact normals (the direction from the nearest point of the tube's centre circle),
//!   `uv` = (angle around the axis, angle around the tube) / 2π, `facets(detail)`,
//!   `area` = 4π²Rr.
//!
//! Intersection (lecture: "Computing Intersections"; the implicit form is in Hanrahan,
//! "Ray-surface intersection", in Glassner's *An Introduction to Ray Tracing*, 1989):
//! substituting the ray into `(|p|² + R² - r²)² - 4R²(x² + z²) = 0` gives a quartic in the
//! ray parameter. It is solved in f64 with the ray origin first moved to where the ray
//! enters the bounding box and the direction normalised (so the coefficients stay well
//! scaled at any size), by derivative isolation with safeguarded Newton
//! (`crate::roots::real_roots_in`), and each root is then polished by Newton on the
//! torus's signed distance, whose gradient has unit length, so the final root does not
//! suffer from the cancellation of the quartic's constant term.

// `!(a < b)` comparisons are deliberate: they are also true when a value is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::roots::{real_roots_in, Polynomial};
use crate::shape::{Boundary, Facets, Hit, Shape, Span};
use glam::{DVec3, Vec2, Vec3};
use irradia_core::{Aabb, Ray};
use std::f64::consts::PI;

#[derive(Clone, Debug)]
pub struct Torus {
    /// Distance from the axis to the centre of the tube.
    pub major: f32,
    /// Radius of the tube.
    pub minor: f32,
}

impl Torus {
    /// A ring torus. Panics unless `0 < minor < major` and both are finite
    /// (use [`Torus::try_new`] for input from files).
    pub fn new(major: f32, minor: f32) -> Self {
        Self::try_new(major, minor).unwrap_or_else(|e| panic!("{e}"))
    }

    /// A ring torus, or a message saying why the radii are invalid.
    pub fn try_new(major: f32, minor: f32) -> Result<Self, String> {
        if !(major.is_finite() && minor.is_finite()) {
            return Err(format!(
                "torus radii must be finite (major {major}, minor {minor})"
            ));
        }
        if !(minor > 0.0) {
            return Err(format!("torus minor radius must be positive, got {minor}"));
        }
        if !(major > minor) {
            return Err(format!(
                "torus major radius ({major}) must exceed the minor radius ({minor})"
            ));
        }
        Ok(Self { major, minor })
    }

    /// Signed distance to the surface (negative inside) and its gradient (unit length).
    fn distance(&self, p: DVec3) -> (f64, DVec3) {
        let rho = (p.x * p.x + p.z * p.z).sqrt();
        let big_r = self.major as f64;
        let q = DVec3::new(rho - big_r, p.y, 0.0);
        let len = q.truncate().length();
        let d = len - self.minor as f64;
        if len == 0.0 || rho == 0.0 {
            return (d, DVec3::Y);
        }
        let radial = DVec3::new(p.x / rho, 0.0, p.z / rho);
        let grad = radial * (q.x / len) + DVec3::Y * (q.y / len);
        (d, grad)
    }

    /// The sorted roots of the ray-torus quartic along the whole line clipped to the
    /// bounding box, in the ray's own parameter `t`, restricted to `[t_lo, t_hi]`.
    fn roots(&self, ray: &Ray, t_lo: f64, t_hi: f64) -> ([f64; 4], usize) {
        let mut out = [0.0; 4];
        let o = ray.origin.as_dvec3();
        let d = ray.dir.as_dvec3();
        let len = d.length();
        if !(len > 0.0) || !len.is_finite() {
            return (out, 0);
        }
        let dn = d / len;
        let Some((b0, b1)) = self.box_interval(o, d) else {
            return (out, 0);
        };
        let (t0, t1) = (b0.max(t_lo), b1.min(t_hi));
        if !(t0 <= t1) {
            return (out, 0);
        }
        // Work in arc length s from the point where the clipped ray starts.
        let start = o + d * t0;
        let s_max = (t1 - t0) * len;
        let big_r = self.major as f64;
        let r = self.minor as f64;
        let b = 2.0 * start.dot(dn);
        let c = start.dot(start) + big_r * big_r - r * r;
        let e = dn.x * dn.x + dn.z * dn.z;
        let f = 2.0 * (start.x * dn.x + start.z * dn.z);
        let g = start.x * start.x + start.z * start.z;
        let k = 4.0 * big_r * big_r;
        // (s² + b s + c)² - k (e s² + f s + g)
        let poly = Polynomial::new(&[
            c * c - k * g,
            2.0 * b * c - k * f,
            b * b + 2.0 * c - k * e,
            2.0 * b,
            1.0,
        ]);
        let mut ss = Vec::with_capacity(4);
        // Widen the search slightly so roots on the box faces are not lost to rounding.
        let pad = 1e-9 * (s_max + big_r + r);
        real_roots_in(&poly, -pad, s_max + pad, &mut ss);
        let mut n = 0;
        for s in ss {
            let s = self.polish(start, dn, s);
            let t = t0 + s / len;
            if t >= t_lo && t <= t_hi && n < 4 {
                out[n] = t;
                n += 1;
            }
        }
        out[..n].sort_by(f64::total_cmp);
        (out, n)
    }

    /// Newton on the signed distance along the ray (gradient of unit length), kept only
    /// while it shrinks |distance|.
    fn polish(&self, start: DVec3, dn: DVec3, mut s: f64) -> f64 {
        let (mut dist, mut grad) = self.distance(start + dn * s);
        for _ in 0..3 {
            let slope = grad.dot(dn);
            if dist == 0.0 || slope.abs() < 1e-3 {
                break;
            }
            let ns = s - dist / slope;
            let (nd, ng) = self.distance(start + dn * ns);
            if !(nd.abs() < dist.abs()) {
                break;
            }
            s = ns;
            dist = nd;
            grad = ng;
        }
        s
    }

    /// Parameter interval of the ray inside the bounding box (whole line), in f64.
    fn box_interval(&self, o: DVec3, d: DVec3) -> Option<(f64, f64)> {
        let outer = self.major as f64 + self.minor as f64;
        let ext = DVec3::new(outer, self.minor as f64, outer) * (1.0 + 1e-9);
        let mut t0 = f64::NEG_INFINITY;
        let mut t1 = f64::INFINITY;
        for a in 0..3 {
            if d[a] == 0.0 {
                if o[a].abs() > ext[a] {
                    return None;
                }
                continue;
            }
            let inv = 1.0 / d[a];
            let (ta, tb) = ((-ext[a] - o[a]) * inv, (ext[a] - o[a]) * inv);
            t0 = t0.max(ta.min(tb));
            t1 = t1.min(ta.max(tb));
        }
        (t0 <= t1).then_some((t0, t1))
    }

    /// Point projected onto the surface, outward normal and uv at ray parameter `t`.
    fn surface(&self, ray: &Ray, t: f64) -> (Vec3, Vec3, Vec2) {
        let p = ray.origin.as_dvec3() + ray.dir.as_dvec3() * t;
        let (_, n) = self.distance(p);
        let rho = (p.x * p.x + p.z * p.z).sqrt();
        let big_r = self.major as f64;
        let (cx, cz) = if rho > 0.0 {
            (p.x / rho * big_r, p.z / rho * big_r)
        } else {
            (big_r, 0.0)
        };
        let on_surface = DVec3::new(cx, 0.0, cz) + n * self.minor as f64;
        let u = 0.5 + p.z.atan2(p.x) / (2.0 * PI);
        let v = 0.5 + p.y.atan2(rho - big_r) / (2.0 * PI);
        (
            on_surface.as_vec3(),
            n.as_vec3(),
            Vec2::new(u as f32, v as f32),
        )
    }

    /// Bound on the error of reported points: they are projected onto the surface in
    /// f64 and rounded to f32, so a few f32 ulps of the largest coordinate.
    fn point_error(&self) -> f32 {
        4.0 * f32::EPSILON * (self.major + self.minor)
    }
}

impl Shape for Torus {
    fn kind(&self) -> &'static str {
        "torus"
    }

    fn bounds(&self) -> Aabb {
        // Rounded up so that the f32 box contains the exact torus.
        let e = (self.major + self.minor) * (1.0 + 2.0 * f32::EPSILON);
        let h = self.minor * (1.0 + 2.0 * f32::EPSILON);
        Aabb::new(Vec3::new(-e, -h, -e), Vec3::new(e, h, e))
    }

    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let (ts, n) = self.roots(ray, 0.0, t_max as f64);
        let t = ts[..n]
            .iter()
            .copied()
            .find(|&t| t > 0.0 && t < t_max as f64)?;
        let (p, normal, uv) = self.surface(ray, t);
        let mut h = Hit::new(t as f32, p, normal, uv);
        h.error = self.point_error();
        Some(h)
    }

    fn is_solid(&self) -> bool {
        true
    }

    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        let (ts, n) = self.roots(ray, f64::NEG_INFINITY, f64::INFINITY);
        if n < 2 {
            return;
        }
        // Inside where the signed distance at the midpoint between two roots is negative;
        // this stays right when a grazing root pair was lost or merged.
        let o = ray.origin.as_dvec3();
        let d = ray.dir.as_dvec3();
        let mut open: Option<Boundary> = None;
        for k in 0..n - 1 {
            let mid = 0.5 * (ts[k] + ts[k + 1]);
            let inside = self.distance(o + d * mid).0 < 0.0;
            if inside && open.is_none() {
                let (_, nrm, uv) = self.surface(ray, ts[k]);
                open = Some(Boundary::new(ts[k] as f32, nrm, uv));
            } else if !inside {
                if let Some(enter) = open.take() {
                    let (_, nrm, uv) = self.surface(ray, ts[k]);
                    out.push(Span {
                        enter,
                        exit: Boundary::new(ts[k] as f32, nrm, uv),
                    });
                }
            }
        }
        if let Some(enter) = open {
            let (_, nrm, uv) = self.surface(ray, ts[n - 1]);
            out.push(Span {
                enter,
                exit: Boundary::new(ts[n - 1] as f32, nrm, uv),
            });
        }
    }

    fn facets(&self, detail: u32) -> Option<Facets> {
        let nu = detail.max(8) as usize;
        let nv = ((detail as f32 * self.minor / self.major).ceil() as usize).max(6);
        let mut f = Facets::default();
        for i in 0..nu {
            let th = 2.0 * std::f32::consts::PI * i as f32 / nu as f32;
            for j in 0..nv {
                let ph = 2.0 * std::f32::consts::PI * j as f32 / nv as f32;
                let n = Vec3::new(ph.cos() * th.cos(), ph.sin(), ph.cos() * th.sin());
                let c = Vec3::new(th.cos(), 0.0, th.sin()) * self.major;
                f.vertices.push(c + n * self.minor);
                f.normals.push(n);
            }
        }
        let idx = |i: usize, j: usize| ((i % nu) * nv + (j % nv)) as u32;
        for i in 0..nu {
            for j in 0..nv {
                // (θ, φ) -> (θ, φ+) -> (θ+, φ+) -> (θ+, φ): counter-clockwise from outside.
                f.faces.push(vec![
                    idx(i, j),
                    idx(i, j + 1),
                    idx(i + 1, j + 1),
                    idx(i + 1, j),
                ]);
            }
        }
        Some(f)
    }

    fn area(&self) -> Option<f32> {
        Some(4.0 * std::f32::consts::PI * std::f32::consts::PI * self.major * self.minor)
    }
}
