//! Area lights for the rasterizer: a rectangle or a sphere is replaced by a fixed set of
//! sample points, each a small one-sided Lambertian emitter ([`RasterLight::Emitter`])
//! carrying its share of the light's area (the "many point lights" approximation of an
//! area light, as in Keller's instant radiosity, 1997, without the shadows).
//!
//! A patch of area `dA` and radiance `L` seen from a point `p` at distance `r`, at
//! angle `θ_l` from its normal, gives irradiance `L dA cos θ_l / r²` on a surface facing
//! it. Summing over the patches is a midpoint-rule quadrature of the exact irradiance
//! `∫ L cos θ_l cos θ_s / r² dA`, so the raster image converges to the ray tracer's
//! (which integrates the same thing with stratified random shadow rays) as the number of
//! points grows:
//!
//! - rectangle: the centres of a `u x v` grid of equal cells, `u = ceil(sqrt(n))`,
//!   `v = ceil(n / u)` (so `u v >= n` points, each `A / (u v)`);
//! - sphere: `n` points of a Fibonacci (golden-angle) spiral over the sphere (Swinehart
//!   1998; González 2010), each `4 π r² / n`, with outward normals. Points on the far side
//!   face away from the shaded point (`cos θ_l <= 0`) and give nothing, which is exactly
//!   the part of the sphere hidden by itself.
//!
//! The number of points is the light's `samples` (its shadow-ray count in the Whitted
//! tracer), at most [`MAX_POINTS`] per light, unless the caller asks for another.

use crate::lighting::RasterLight;
use glam::Vec3;
use irradia_core::Rgb;
use irradia_scene::Light;

/// Most sample points one area light becomes (per-vertex or per-pixel lighting costs
/// one evaluation per point).
pub const MAX_POINTS: u32 = 1024;

/// The grid `u x v` used for `n` points of a rectangle.
pub fn rect_grid(n: u32) -> (u32, u32) {
    let n = n.clamp(1, MAX_POINTS);
    let u = (n as f32).sqrt().ceil() as u32;
    (u, n.div_ceil(u))
}

/// The sample points of a one-sided rectangle `corner + s edge_u + t edge_v` emitting
/// `radiance` on the side of `edge_u x edge_v`, about `n` of them.
pub fn rect_points(
    corner: Vec3,
    edge_u: Vec3,
    edge_v: Vec3,
    radiance: Rgb,
    n: u32,
) -> Vec<RasterLight> {
    let c = edge_u.cross(edge_v);
    let area = c.length();
    if area <= 0.0 || !area.is_finite() {
        return Vec::new();
    }
    let normal = c / area;
    let (u, v) = rect_grid(n);
    let share = radiance * (area / (u * v) as f32);
    let mut out = Vec::with_capacity((u * v) as usize);
    for j in 0..v {
        for i in 0..u {
            let s = (i as f32 + 0.5) / u as f32;
            let t = (j as f32 + 0.5) / v as f32;
            out.push(RasterLight::Emitter {
                position: corner + edge_u * s + edge_v * t,
                normal,
                color: share,
            });
        }
    }
    out
}

/// The sample points of a sphere emitting `radiance` outwards, `n` of them.
pub fn sphere_points(center: Vec3, radius: f32, radiance: Rgb, n: u32) -> Vec<RasterLight> {
    let n = n.clamp(1, MAX_POINTS);
    let share = radiance * (4.0 * std::f32::consts::PI * radius * radius / n as f32);
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    (0..n)
        .map(|k| {
            // Equal-area bands in z (Archimedes), golden-angle steps in azimuth.
            let z = 1.0 - (2.0 * k as f32 + 1.0) / n as f32;
            let s = (1.0 - z * z).max(0.0).sqrt();
            let phi = golden * k as f32;
            let normal = Vec3::new(s * phi.cos(), s * phi.sin(), z);
            RasterLight::Emitter {
                position: center + radius * normal,
                normal,
                color: share,
            }
        })
        .collect()
}

/// One scene light as pipeline lights: point, directional and spot lights map one to
/// one (spots with the smooth falloff whatever their profile); rectangles and spheres
/// become sample points, `points` of them when given, otherwise the light's own
/// `samples`; a projector becomes a spot; `constant` and `envmap` give nothing.
pub fn scene_light(light: &Light, points: Option<u32>) -> Vec<RasterLight> {
    match *light {
        Light::Point {
            position,
            intensity,
        } => vec![RasterLight::Point {
            position,
            color: intensity,
        }],
        Light::Directional {
            direction,
            irradiance,
        } => vec![RasterLight::Directional {
            direction: direction.normalize(),
            color: irradiance,
        }],
        Light::Spot {
            position,
            direction,
            intensity,
            cos_inner,
            cos_outer,
            ..
        } => vec![RasterLight::Spot {
            position,
            direction: direction.normalize(),
            color: intensity,
            cos_inner,
            cos_outer,
        }],
        // A projector as a spot light of its mean intensity on the axis, cut off at
        // the cone inscribed in its frustum (the pipeline has no projected images).
        Light::Projector(ref p) => {
            let cos = 1.0 / (1.0 + p.half.x.min(p.half.y).powi(2)).sqrt();
            vec![RasterLight::Spot {
                position: p.position,
                direction: p.forward,
                color: p.irradiance.mean() * (std::f32::consts::PI * p.scale),
                cos_inner: cos,
                cos_outer: cos,
            }]
        }
        // Lights at infinity do not light the pipeline's surfaces.
        Light::Constant { .. } | Light::Envmap(_) => Vec::new(),
        Light::Rect {
            corner,
            edge_u,
            edge_v,
            radiance,
            samples,
        } => rect_points(corner, edge_u, edge_v, radiance, points.unwrap_or(samples)),
        Light::Sphere {
            center,
            radius,
            radiance,
            samples,
        } => sphere_points(center, radius, radiance, points.unwrap_or(samples)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn total(points: &[RasterLight]) -> f32 {
        points
            .iter()
            .map(|p| match p {
                RasterLight::Emitter { color, .. } => color.r,
                _ => panic!("area lights become emitters"),
            })
            .sum()
    }

    #[test]
    fn the_points_share_the_whole_area() {
        for n in [1, 4, 7, 64] {
            let r = rect_points(Vec3::ZERO, Vec3::X * 2.0, Vec3::Z * 3.0, Rgb::splat(1.0), n);
            assert!(r.len() as u32 >= n);
            assert!((total(&r) - 6.0).abs() < 1e-4, "{n}: {}", total(&r));
            let s = sphere_points(Vec3::ONE, 0.5, Rgb::splat(1.0), n);
            assert_eq!(s.len() as u32, n);
            let area = 4.0 * std::f32::consts::PI * 0.25;
            assert!((total(&s) - area).abs() < 1e-4 * area);
        }
    }

    #[test]
    fn sphere_points_lie_on_the_sphere_and_cover_it_evenly() {
        let s = sphere_points(Vec3::new(1.0, 2.0, 3.0), 2.0, Rgb::splat(1.0), 200);
        let mut mean = Vec3::ZERO;
        for p in &s {
            let RasterLight::Emitter {
                position, normal, ..
            } = *p
            else {
                unreachable!()
            };
            assert!(((position - Vec3::new(1.0, 2.0, 3.0)).length() - 2.0).abs() < 1e-5);
            assert!((normal.length() - 1.0).abs() < 1e-5);
            mean += normal;
        }
        assert!((mean / 200.0).length() < 0.01, "{mean}");
    }
}
