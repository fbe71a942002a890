//! Watertight ray-triangle intersection: Woop, Benthin and Wald, "Watertight
//! Ray/Triangle Intersection", JCGT 2(1), 2013, with the conservative bounds of
//! pbrt-v4 (Pharr, Jakob, Humphreys, section 6.5.3 and 6.8.4) for the `t > 0` test and
//! the error of the hit point.
//!
//! The ray is turned into a shear transform that maps it to the +z axis from the
//! origin; the triangle's vertices are carried by the same transform, one vertex at a
//! time, so an edge shared by two triangles gets bit-identical edge functions with
//! opposite signs. A ray through an edge or a vertex therefore hits at least one of
//! the triangles around it: there are no cracks. Edge functions that come out exactly
//! zero are recomputed in double precision, as the paper prescribes.

use crate::bvh::node::gamma;
use glam::Vec3;
use irradia_core::Ray;

/// A ray prepared for triangle tests: its origin, the permutation that makes the
/// largest direction component `z`, and the shear.
#[derive(Clone, Copy, Debug)]
pub struct TriangleRay {
    origin: Vec3,
    kx: usize,
    ky: usize,
    kz: usize,
    sx: f32,
    sy: f32,
    sz: f32,
}

/// Where a ray meets a triangle: the parameter and barycentric coordinates
/// (`point = b0 p0 + b1 p1 + b2 p2`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    pub t: f32,
    pub b0: f32,
    pub b1: f32,
    pub b2: f32,
}

impl TriangleHit {
    /// The hit point from the barycentrics, and an absolute bound on its error
    /// (pbrt-v4 eq. 6.31: γ(7) Σ |b_i p_i|, the largest component).
    pub fn point_and_error(&self, p0: Vec3, p1: Vec3, p2: Vec3) -> (Vec3, f32) {
        let p = self.b0 * p0 + self.b1 * p1 + self.b2 * p2;
        let abs_sum = (self.b0 * p0).abs() + (self.b1 * p1).abs() + (self.b2 * p2).abs();
        (p, gamma(7) * abs_sum.max_element())
    }
}

impl TriangleRay {
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        let d = ray.dir;
        let a = d.abs();
        let kz = if a.x > a.y && a.x > a.z {
            0
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let kx = if kz == 2 { 0 } else { kz + 1 };
        let ky = if kx == 2 { 0 } else { kx + 1 };
        let dz = d[kz];
        Self {
            origin: ray.origin,
            kx,
            ky,
            kz,
            sx: -d[kx] / dz,
            sy: -d[ky] / dz,
            sz: 1.0 / dz,
        }
    }

    /// The permutation (x, y, z axes of the sheared frame).
    #[inline(always)]
    pub fn axes(&self) -> (usize, usize, usize) {
        (self.kx, self.ky, self.kz)
    }
    #[inline(always)]
    pub fn origin(&self) -> Vec3 {
        self.origin
    }
    #[inline(always)]
    pub fn shear_xy(&self) -> (f32, f32) {
        (self.sx, self.sy)
    }
    #[inline(always)]
    pub fn shear_z(&self) -> f32 {
        self.sz
    }

    /// The triangle `(p0, p1, p2)` hit with `0 < t < t_max`, from either side.
    /// Degenerate triangles (zero area) are never hit.
    #[inline]
    pub fn intersect(&self, p0: Vec3, p1: Vec3, p2: Vec3, t_max: f32) -> Option<TriangleHit> {
        let (kx, ky, kz) = (self.kx, self.ky, self.kz);
        let a = (p0 - self.origin).to_array();
        let b = (p1 - self.origin).to_array();
        let c = (p2 - self.origin).to_array();
        // Shear so the ray runs along +z (z is scaled later, only if the edges pass).
        let (az, bz, cz) = (a[kz], b[kz], c[kz]);
        let ax = a[kx] + self.sx * az;
        let ay = a[ky] + self.sy * az;
        let bx = b[kx] + self.sx * bz;
        let by = b[ky] + self.sy * bz;
        let cx = c[kx] + self.sx * cz;
        let cy = c[ky] + self.sy * cz;
        // Edge functions (scaled barycentrics).
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        if u == 0.0 || v == 0.0 || w == 0.0 {
            u = (cx as f64 * by as f64 - cy as f64 * bx as f64) as f32;
            v = (ax as f64 * cy as f64 - ay as f64 * cx as f64) as f32;
            w = (bx as f64 * ay as f64 - by as f64 * ax as f64) as f32;
        }
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        let (az, bz, cz) = (az * self.sz, bz * self.sz, cz * self.sz);
        let t_scaled = u * az + v * bz + w * cz;
        if det < 0.0 && (t_scaled >= 0.0 || t_scaled <= t_max * det) {
            return None;
        }
        if det > 0.0 && (t_scaled <= 0.0 || t_scaled >= t_max * det) {
            return None;
        }
        let inv_det = 1.0 / det;
        let t = t_scaled * inv_det;
        if !(t < t_max) {
            return None;
        }
        // Make sure t > 0 beyond doubt (pbrt-v4, section 6.8.4).
        let max_zt = az.abs().max(bz.abs()).max(cz.abs());
        let delta_z = gamma(3) * max_zt;
        let max_xt = ax.abs().max(bx.abs()).max(cx.abs());
        let max_yt = ay.abs().max(by.abs()).max(cy.abs());
        let delta_x = gamma(5) * (max_xt + max_zt);
        let delta_y = gamma(5) * (max_yt + max_zt);
        let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
        let max_e = u.abs().max(v.abs()).max(w.abs());
        let delta_t =
            3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv_det.abs();
        if t <= delta_t {
            return None;
        }
        Some(TriangleHit {
            t,
            b0: u * inv_det,
            b1: v * inv_det,
            b2: w * inv_det,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_inside_misses_outside() {
        let (p0, p1, p2) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        let r = TriangleRay::new(&Ray::new(Vec3::new(0.25, 0.25, 1.0), -Vec3::Z));
        let h = r.intersect(p0, p1, p2, f32::INFINITY).unwrap();
        assert!((h.t - 1.0).abs() < 1e-6);
        assert!((h.b0 - 0.5).abs() < 1e-6 && (h.b1 - 0.25).abs() < 1e-6);
        assert!(r.intersect(p0, p1, p2, 0.5).is_none());
        let r = TriangleRay::new(&Ray::new(Vec3::new(0.75, 0.75, 1.0), -Vec3::Z));
        assert!(r.intersect(p0, p1, p2, f32::INFINITY).is_none());
        // Behind the origin.
        let r = TriangleRay::new(&Ray::new(Vec3::new(0.25, 0.25, 1.0), Vec3::Z));
        assert!(r.intersect(p0, p1, p2, f32::INFINITY).is_none());
    }

    #[test]
    fn degenerate_triangle_is_never_hit() {
        let r = TriangleRay::new(&Ray::new(Vec3::new(0.5, 0.0, 1.0), -Vec3::Z));
        assert!(r
            .intersect(Vec3::ZERO, Vec3::X, Vec3::X * 2.0, f32::INFINITY)
            .is_none());
    }
}
