//! Spherical lights sampled by the cone of directions they subtend: from a point
//! outside a sphere of radius `R` whose centre is at distance `d`, the sphere fills the
//! cone of half-angle `θmax`, `sin θmax = R / d`; a direction drawn uniformly in that
//! cone (density `1 / (2π (1 - cos θmax))` by solid angle) meets the sphere's near side
//! at one point, so every sample lands on the visible cap (Shirley and Wang,
//! "Distribution Ray Tracing: Theory and Practice", 1992; PBRT 4th ed., §6.2.4; the
//! point found by its angle at the centre as in A. Akalin, "Sampling the visible
//! hemisphere of a sphere", 2021). This is how Mitsuba 3's `sphere` samples
//! directions; sampling the whole sphere by area instead spends half of the samples on
//! the far side, where they give nothing, and weighs the rest unevenly.
//!
//! The angle `α` at the centre between the axis (towards the shading point) and the
//! sampled point, for a direction at angle `θ` from the axis, follows from the
//! triangle centre-point-sample: `cos α = (d / R) sin²θ + cos θ √(1 - (d/R)² sin²θ)`
//! (`α = 0` on the axis, `cos α = R / d` at the silhouette). `1 - cos θmax` is taken as
//! `sin²θmax / (1 + cos θmax)` and `sin²θ` as `e (2 - e)` with `e = 1 - cos θ`, so
//! neither cancels for small, far lights.
//!
//! Inside the sphere (or on it) there is no cone; the caller samples by area there.

use glam::{Vec2, Vec3};
use irradia_core::{sin_cos, Frame};
use irradia_geometry::{Instance, Shape};
use std::f32::consts::{PI, TAU};

/// A light sphere in world space, for cone sampling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct VisibleSphere {
    pub center: Vec3,
    pub radius: f32,
}

/// The cone a sphere subtends from a point outside it.
#[derive(Clone, Copy, Debug)]
struct Cone {
    /// Unit vector from the centre towards the point.
    axis: Vec3,
    /// `sin²θmax = R² / d²`, `d / R`, and `1 - cos θmax`.
    sin2_max: f32,
    d_over_r: f32,
    one_minus_cos_max: f32,
}

impl VisibleSphere {
    /// The world sphere of an unflipped sphere shape under `inst`, when its transform
    /// keeps it a sphere (a rotation, a uniform scale and a translation: columns of
    /// equal length, orthogonal, to 1e-5); `None` for other shapes and placements.
    pub(crate) fn of_instance(inst: &Instance) -> Option<Self> {
        let (center, radius) = outward_sphere(inst.shape.as_ref())?;
        let m = inst.to_world().matrix3;
        let cols = [
            Vec3::from(m.x_axis),
            Vec3::from(m.y_axis),
            Vec3::from(m.z_axis),
        ];
        let len = cols[0].length();
        let similar = cols.iter().all(|c| (c.length() - len).abs() <= 1e-5 * len)
            && [(0, 1), (0, 2), (1, 2)]
                .iter()
                .all(|&(i, j)| cols[i].dot(cols[j]).abs() <= 1e-5 * len * len);
        (similar && len > 0.0).then(|| Self {
            center: inst.to_world().transform_point3(center),
            radius: radius * len,
        })
    }

    /// Whether `p` is outside the sphere (where it is sampled by its cone).
    #[inline]
    pub(crate) fn is_outside(&self, p: Vec3) -> bool {
        (p - self.center).length_squared() > self.radius * self.radius
    }

    /// The cone seen from `p`, `None` when `p` is not outside the sphere.
    #[inline]
    fn cone(&self, p: Vec3) -> Option<Cone> {
        if !self.is_outside(p) {
            return None;
        }
        let v = p - self.center;
        let d2 = v.length_squared();
        let r2 = self.radius * self.radius;
        let d = d2.sqrt();
        let sin2_max = r2 / d2;
        let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
        Some(Cone {
            axis: v / d,
            sin2_max,
            d_over_r: d / self.radius,
            one_minus_cos_max: sin2_max / (1.0 + cos_max),
        })
    }

    /// The solid-angle density of [`Self::sample`] from `p` (uniform over the cone);
    /// `None` when `p` is not outside the sphere.
    #[inline]
    pub(crate) fn pdf(&self, p: Vec3) -> Option<f32> {
        self.cone(p).map(|c| 1.0 / (TAU * c.one_minus_cos_max))
    }

    /// A point of the sphere's visible cap from `p` for the numbers `u`: the point, its
    /// outward unit normal and the density of its direction by solid angle. `None`
    /// when `p` is not outside the sphere.
    #[inline]
    pub(crate) fn sample(&self, p: Vec3, u: Vec2) -> Option<(Vec3, Vec3, f32)> {
        let c = self.cone(p)?;
        let e = u.x * c.one_minus_cos_max;
        let sin2 = e * (2.0 - e);
        let cos_theta = 1.0 - e;
        let k = (sin2 / c.sin2_max).min(1.0);
        let cos_a = (sin2 * c.d_over_r + cos_theta * (1.0 - k).sqrt()).min(1.0);
        let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
        let (s, co) = sin_cos(TAU * u.y);
        let n = Frame::from_normal(c.axis).to_world(Vec3::new(co * sin_a, s * sin_a, cos_a));
        let q = self.center + n * self.radius;
        Some((q, n, 1.0 / (TAU * c.one_minus_cos_max)))
    }
}

/// The object-space centre and radius of a sphere shape whose normals point outward
/// (not flipped), from its bounds (`centre ± r`); `None` for other shapes.
pub(crate) fn outward_sphere(shape: &dyn Shape) -> Option<(Vec3, f32)> {
    if shape.kind() != "sphere" {
        return None;
    }
    let b = shape.bounds();
    let center = (b.min + b.max) * 0.5;
    let radius = (b.max.x - b.min.x) * 0.5;
    let (p, n) = shape.sample_surface(Vec2::new(0.3, 0.7))?;
    (n.dot(p - center) > 0.0 && radius > 0.0 && radius.is_finite()).then_some((center, radius))
}

/// `1 / (4π R²)`, a sphere's density by area (inside it, or for a sphere that is not
/// cone sampled).
#[inline]
pub(crate) fn inverse_area(radius: f32) -> f32 {
    1.0 / (4.0 * PI * radius * radius)
}

#[cfg(test)]
mod tests {
    use super::*;
    use irradia_core::Rng;

    fn ball() -> VisibleSphere {
        VisibleSphere {
            center: Vec3::new(0.3, -0.2, 1.0),
            radius: 0.7,
        }
    }

    /// Every sample lies on the sphere, faces the point (on the visible cap: the
    /// segment from the point meets the sphere first there) and lies in the cone.
    #[test]
    fn samples_lie_on_the_visible_cap() {
        let s = ball();
        let mut rng = Rng::new(1, 2);
        for &dist in &[0.7001f32, 0.75, 1.0, 3.0, 40.0, 3000.0] {
            let p = s.center + Vec3::new(0.3, 0.5, -0.8).normalize() * dist;
            for _ in 0..2000 {
                let (q, n, pdf) = s.sample(p, rng.next_2d()).unwrap();
                assert!(((q - s.center).length() - s.radius).abs() < 2e-5 * (1.0 + dist));
                assert!((n.length() - 1.0).abs() < 1e-5);
                let wi = (q - p).normalize();
                // Facing (the silhouette's grazing samples may round either way).
                assert!(-wi.dot(n) > -1e-3, "dist {dist}: back side");
                let axis = (s.center - p).normalize();
                let sin_max = s.radius / dist;
                let cos_max = (1.0 - sin_max * sin_max).max(0.0).sqrt();
                assert!(
                    wi.dot(axis) >= cos_max - 1e-4,
                    "dist {dist}: outside the cone"
                );
                assert!(pdf > 0.0 && pdf.is_finite());
            }
        }
    }

    /// The density integrates the cone's solid angle to one: the cone's solid angle is
    /// `2π (1 - cos θmax)` (closed form, in f64), also for far, tiny lights where
    /// `1 - cos θmax` computed naively in f32 would cancel.
    #[test]
    fn density_is_one_over_the_cone_solid_angle() {
        let s = ball();
        for &dist in &[0.71f64, 1.0, 5.0, 1e3, 1e5] {
            let p = s.center + Vec3::new(0.0, 0.0, dist as f32);
            let sin_max = s.radius as f64 / dist;
            let omega = 2.0 * std::f64::consts::PI * (1.0 - (1.0 - sin_max * sin_max).sqrt());
            let got = s.pdf(p).unwrap() as f64;
            assert!(
                (got * omega - 1.0).abs() < 2e-3,
                "dist {dist}: {got} vs {}",
                1.0 / omega
            );
        }
        assert!(s.pdf(s.center).is_none());
        assert!(s.pdf(s.center + Vec3::new(0.69, 0.0, 0.0)).is_none());
    }

    /// The directions are uniform in the cone: chi-square of `cos θ` (10 equal bins of
    /// `[cos θmax, 1]`) and of the azimuth about the axis (10 bins), 20,000 samples.
    #[test]
    fn directions_are_uniform_in_the_cone() {
        let s = ball();
        let p = s.center + Vec3::new(1.0, 2.0, 2.0).normalize() * 1.9;
        let axis = (s.center - p).normalize();
        let f = Frame::from_normal(axis);
        let sin_max = s.radius / 1.9;
        let cos_max = (1.0 - sin_max * sin_max).sqrt();
        let mut rng = Rng::new(7, 11);
        let n = 20_000;
        let (mut by_cos, mut by_phi) = ([0usize; 10], [0usize; 10]);
        for _ in 0..n {
            let (q, _, _) = s.sample(p, rng.next_2d()).unwrap();
            let wi = (q - p).normalize();
            let c = wi.dot(axis);
            let x = ((c - cos_max) / (1.0 - cos_max)).clamp(0.0, 0.999_999);
            by_cos[(x * 10.0) as usize] += 1;
            let l = f.to_local(wi);
            let phi = l.y.atan2(l.x) / TAU + 0.5;
            by_phi[((phi * 10.0) as usize).min(9)] += 1;
        }
        // 9 degrees of freedom: P(chi² > 27.9) = 0.001.
        for (name, bins) in [("cos", by_cos), ("phi", by_phi)] {
            let e = n as f64 / 10.0;
            let chi2: f64 = bins.iter().map(|&o| (o as f64 - e).powi(2) / e).sum();
            assert!(chi2 < 27.9, "{name}: chi² {chi2} ({bins:?})");
        }
    }

    /// The cone estimate of the irradiance from a sphere of radiance 1 straight above a
    /// facing point, `E = π sin²θmax` (closed form), agrees within 1%, near and far.
    #[test]
    fn irradiance_from_the_cone_matches_the_closed_form() {
        let s = ball();
        let mut rng = Rng::new(3, 5);
        for &h in &[0.8f32, 1.5, 10.0] {
            let p = s.center - Vec3::Y * h;
            let n = 100_000;
            let mut sum = 0.0f64;
            for _ in 0..n {
                let (q, _, pdf) = s.sample(p, rng.next_2d()).unwrap();
                let wi = (q - p).normalize();
                sum += (wi.y.max(0.0) / pdf) as f64;
            }
            let got = sum / n as f64;
            let want = std::f64::consts::PI * (s.radius as f64 / h as f64).powi(2);
            assert!((got / want - 1.0).abs() < 0.01, "h {h}: {got} vs {want}");
        }
    }
}
