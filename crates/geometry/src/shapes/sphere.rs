//! The sphere `(p - c)·(p - c) - r² = 0` (lecture: "Ray Casting a Sphere"), solved as
//! a quadratic in `t` in f64 with the numerically stable form of the roots.
//!
//! Texture coordinates are Mitsuba 3's: with `(x, y, z) = (p - c) / r` in the sphere's
//! own frame, `u = phi / 2π` with `phi = atan2(y, x)` in `[0, 2π)` and `v = theta / π`
//! with `theta = acos(z)`: the poles are on the z axis, `v = 0` at `+z`. Mitsuba's
//! `flip_normals` turns the normals inward; such a sphere is an open surface (not a
//! solid, so not usable in CSG and no medium inside).

use crate::shape::{Boundary, Facets, Hit, Shape, Span};
use crate::shapes::shape_error::{finite, positive, ShapeError};
use glam::{Vec2, Vec3};
use irradia_core::{Aabb, Ray};
use std::f64::consts::PI;

#[derive(Clone, Debug)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
    flipped: bool,
}

impl Sphere {
    /// A sphere; `radius` must be positive and finite (the scene loader checks).
    pub fn new(center: Vec3, radius: f32) -> Self {
        assert!(
            radius > 0.0 && radius.is_finite(),
            "sphere radius must be positive"
        );
        Self {
            center,
            radius,
            flipped: false,
        }
    }

    /// The same sphere with its normals pointing inward (Mitsuba's `flip_normals`): an
    /// open surface, no longer a solid.
    pub fn with_flipped_normals(mut self, flip: bool) -> Self {
        self.flipped = flip;
        self
    }

    /// Whether the normals point inward.
    pub fn flipped(&self) -> bool {
        self.flipped
    }

    /// A sphere, or an error for a non-positive or non-finite radius or centre.
    pub fn try_new(center: Vec3, radius: f32) -> Result<Self, ShapeError> {
        finite("sphere center", &center.as_dvec3().to_array())?;
        positive("sphere radius", radius as f64)?;
        Ok(Self::new(center, radius))
    }

    /// Both roots `t0 <= t1` of the ray-sphere quadratic, or `None` on a miss.
    fn roots(&self, ray: &Ray) -> Option<(f64, f64)> {
        let (a, c, q) = self.quadratic(ray)?;
        let (t0, t1) = if q == 0.0 { (0.0, 0.0) } else { (q / a, c / q) };
        Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
    }

    /// The nearest root in `(0, t_max)` (f64), or `None`.
    #[inline]
    fn root_t(&self, ray: &Ray, t_max: f32) -> Option<f64> {
        let (t0, t1) = self.roots(ray)?;
        let t = if t0 > 0.0 { t0 } else { t1 };
        (t > 0.0 && t < t_max as f64).then_some(t)
    }

    /// The hit at root `t` ([`Self::root_t`]): [`Self::surface`] and the error bound.
    #[inline]
    fn hit_at(&self, ray: &Ray, t: f64, uv: bool) -> Hit {
        let (p, n, uv) = self.surface(ray, t, uv);
        let mut h = Hit::new(t as f32, p, n, uv);
        h.error = (self.center.abs().max_element() + self.radius) * 4.0 * f32::EPSILON;
        h
    }

    /// The quadratic `a t² + 2 b t + c = 0` of the ray as `(a, c, q)` with
    /// `q = -b - sign(b) √disc`,
    /// whose roots are `q / a` and `c / q` (the numerically stable pair; Press et al.,
    /// Numerical Recipes §5.6), or `None` on a miss. The discriminant is Haines et al.'s,
    /// "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing Gems, ch. 7):
    /// `b² - a(|o|² - r²)` rewritten so the cancellation happens on a small vector
    /// instead of on large numbers.
    #[inline]
    fn quadratic(&self, ray: &Ray) -> Option<(f64, f64, f64)> {
        let o = ray.origin.as_dvec3() - self.center.as_dvec3();
        let d = ray.dir.as_dvec3();
        let r = self.radius as f64;
        let a = d.dot(d);
        let b = o.dot(d);
        let l = o - d * (b / a);
        let disc = a * (r * r - l.dot(l));
        if disc < 0.0 {
            return None;
        }
        let q = -b - b.signum() * disc.sqrt();
        Some((a, o.dot(o) - r * r, q))
    }

    /// Point, outward (or flipped) unit normal and uv at parameter `t`. The offset from
    /// the centre is taken in f64 (where `o + t d` cancels) and rounded once; the
    /// normal is normalised and the point projected back onto the sphere in f32, which
    /// stays within the hit's error bound `4 ε (max |c_i| + r)` (the normal's relative
    /// error is a few ε; `c + r n` adds half an ulp) at a fraction of the f64 cost.
    fn surface(&self, ray: &Ray, t: f64, uv: bool) -> (Vec3, Vec3, Vec2) {
        let p = ray.origin.as_dvec3() + ray.dir.as_dvec3() * t;
        let n = (p - self.center.as_dvec3()).as_vec3().normalize();
        // Texture coordinates in f32: plenty for textures, and f32 atan2/acos cost a
        // fraction of the f64 ones (this runs for both ends of every CSG span).
        let uv = if uv { mitsuba_sphere_uv(n) } else { Vec2::ZERO };
        // Project the point onto the sphere to remove the error of t.
        let p = self.center + n * self.radius;
        let n = if self.flipped { -n } else { n };
        (p, n, uv)
    }
}

/// Mitsuba's sphere uv of the unit direction `n` from the centre:
/// `(atan2(y, x) / 2π` in `[0, 1)`, `acos(z) / π)`.
#[inline]
pub fn mitsuba_sphere_uv(n: Vec3) -> Vec2 {
    let mut phi = irradia_core::atan2(n.y, n.x) / std::f32::consts::TAU;
    if phi < 0.0 {
        phi = (phi + 1.0).min(1.0 - f32::EPSILON / 2.0);
    }
    let theta = irradia_core::atan2((n.x * n.x + n.y * n.y).sqrt(), n.z);
    Vec2::new(phi, theta / std::f32::consts::PI)
}

impl Shape for Sphere {
    fn kind(&self) -> &'static str {
        "sphere"
    }

    fn bounds(&self) -> Aabb {
        Aabb::new(
            self.center - Vec3::splat(self.radius),
            self.center + Vec3::splat(self.radius),
        )
    }

    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        self.root_t(ray, t_max).map(|t| self.hit_at(ray, t, true))
    }

    fn splits_surface(&self) -> bool {
        true
    }

    #[inline]
    fn nearest_t(&self, ray: &Ray, t_max: f32) -> Option<f64> {
        self.root_t(ray, t_max)
    }

    fn surface_at(&self, ray: &Ray, t: f64, uv: bool) -> Hit {
        self.hit_at(ray, t, uv)
    }

    /// `(dp/du, dp/dv)` at the point with unit direction `n` from the centre, for
    /// Mitsuba's uv (`p = c + r (sin θ cos φ, sin θ sin φ, cos θ)`, `φ = 2π u`,
    /// `θ = π v`): `2π r (−n_y, n_x, 0)` and `π r (n_z cos φ, n_z sin φ, −sin θ)`, with
    /// `sin θ cos φ = n_x` (no trigonometry); at the poles `dp/du` is zero and `dp/dv`
    /// Mitsuba's `π r (1, 0, 0)`.
    fn uv_derivatives(&self, p: Vec3, _uv: Vec2, _prim: u32) -> (Vec3, Vec3) {
        let n = (p - self.center).normalize_or_zero();
        use std::f32::consts::{PI, TAU};
        let r = self.radius;
        let rho = (n.x * n.x + n.y * n.y).sqrt();
        let dpdv = if rho > 0.0 {
            Vec3::new(n.z * n.x / rho, n.z * n.y / rho, -rho)
        } else {
            Vec3::X
        };
        (Vec3::new(-n.y, n.x, 0.0) * (TAU * r), dpdv * (PI * r))
    }

    /// Whether a root `q / a` or `c / q` lies in `(0, t_max)`, decided without
    /// dividing (`a > 0`): `0 < q < t_max a`, or `c` and `q` of one sign with
    /// `|c| < t_max |q|`. A shadow ray asks this of every sphere it passes.
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        let Some((a, c, q)) = self.quadratic(ray) else {
            return false;
        };
        let tm = t_max as f64;
        (q > 0.0 && q < tm * a) || (c * q > 0.0 && c.abs() < tm * q.abs())
    }

    fn is_solid(&self) -> bool {
        !self.flipped
    }

    fn as_sphere(&self) -> Option<&Sphere> {
        Some(self)
    }

    fn facets(&self, detail: u32) -> Option<Facets> {
        let mut f = uv_sphere(detail);
        for v in &mut f.vertices {
            *v = self.center + *v * self.radius;
        }
        if self.flipped {
            for face in &mut f.faces {
                face.reverse();
            }
            for n in &mut f.normals {
                *n = -*n;
            }
        }
        Some(f)
    }

    fn area(&self) -> Option<f32> {
        Some(4.0 * std::f32::consts::PI * self.radius * self.radius)
    }

    fn sample_surface(&self, u: Vec2) -> Option<(Vec3, Vec3)> {
        let n = irradia_core::sampling::uniform_sphere(u);
        let out = if self.flipped { -n } else { n };
        Some((self.center + n * self.radius, out))
    }

    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        if self.flipped {
            return;
        }
        if let Some((t0, t1)) = self.roots(ray) {
            let (_, n0, uv0) = self.surface(ray, t0, true);
            let (_, n1, uv1) = self.surface(ray, t1, true);
            out.push(Span {
                enter: Boundary::new(t0 as f32, n0, uv0),
                exit: Boundary::new(t1 as f32, n1, uv1),
            });
        }
    }

    /// One boundary of [`Self::spans`]: the same root and the same surface there,
    /// without the other end's (two `atan2`s and a normal).
    fn span_boundary(&self, ray: &Ray, index: u32, _: &mut Vec<Span>) -> Option<Boundary> {
        if self.flipped || index > 1 {
            return None;
        }
        let (t0, t1) = self.roots(ray)?;
        let t = if index == 0 { t0 } else { t1 };
        let (_, n, uv) = self.surface(ray, t, true);
        Some(Boundary::new(t as f32, n, uv))
    }

    /// [`Self::spans`]' roots without the surfaces (normal, uv) at them.
    fn spans_t(&self, ray: &Ray, out: &mut Vec<Span>) {
        if self.flipped {
            return;
        }
        if let Some((t0, t1)) = self.roots(ray) {
            out.push(Span {
                enter: Boundary::new(t0 as f32, Vec3::ZERO, Vec2::ZERO),
                exit: Boundary::new(t1 as f32, Vec3::ZERO, Vec2::ZERO),
            });
        }
    }
}

/// The unit sphere as a UV sphere: `detail` segments around (at least 3) and half as
/// many rings (at least 2), quads counter-clockwise seen from outside, triangles at the
/// poles, per-vertex normals equal to the positions.
pub(crate) fn uv_sphere(detail: u32) -> Facets {
    let seg = detail.max(3) as usize;
    let rings = (detail as usize / 2).max(2);
    let mut f = Facets::default();
    f.vertices.push(Vec3::Y);
    for i in 1..rings {
        let theta = PI * i as f64 / rings as f64;
        for j in 0..seg {
            let phi = 2.0 * PI * j as f64 / seg as f64;
            f.vertices.push(Vec3::new(
                (theta.sin() * phi.cos()) as f32,
                theta.cos() as f32,
                (theta.sin() * phi.sin()) as f32,
            ));
        }
    }
    f.vertices.push(-Vec3::Y);
    let south = (f.vertices.len() - 1) as u32;
    let at = |i: usize, j: usize| (1 + (i - 1) * seg + j % seg) as u32;
    for j in 0..seg {
        f.faces.push(vec![0, at(1, j + 1), at(1, j)]);
        for i in 1..rings - 1 {
            f.faces
                .push(vec![at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)]);
        }
        f.faces
            .push(vec![at(rings - 1, j), at(rings - 1, j + 1), south]);
    }
    f.normals = f.vertices.clone();
    f
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_from_outside_and_inside() {
        let s = Sphere::new(Vec3::new(0.0, 0.0, 5.0), 1.0);
        let h = s
            .intersect(&Ray::new(Vec3::ZERO, Vec3::Z), f32::INFINITY)
            .unwrap();
        assert!((h.t - 4.0).abs() < 1e-6);
        assert!((h.normal - -Vec3::Z).length() < 1e-6);
        let h = s
            .intersect(&Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::Z), f32::INFINITY)
            .unwrap();
        assert!((h.t - 1.0).abs() < 1e-6);
        assert!(s
            .intersect(&Ray::new(Vec3::ZERO, -Vec3::Z), f32::INFINITY)
            .is_none());
    }
}
