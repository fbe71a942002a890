//! Texture coordinates for the triangles of a scene object, taken from the shape itself
//! so that the rasterizer's image textures land where the ray tracer puts them.
//!
//! Facets carry no texture coordinates, and each shape parameterises its surface its
//! own way (a polygon by its bounding rectangle, a sphere by longitude and latitude, a
//! plane by its frame, a mesh by its `vt` coordinates). So each triangle asks the shape:
//! three rays through points inside the triangle, along its normal from either side,
//! return the shape's `(u, v)` where they meet the surface, and the affine map through
//! those three values gives the corners' coordinates. Where the shape's `(u, v)` is
//! affine over the triangle (polygons, boxes, planes, meshes) this is exact; on curved
//! surfaces it is the best affine fit inside the facet. Probing inside the triangle,
//! away from its edges, keeps the probes off parameterisation seams that run along
//! facet edges (a sphere's u = 0 meridian); a triangle that still straddles a seam has
//! its probes unwrapped by whole periods of 1 (when that predicts the coordinate at
//! its centre, a fourth probe, better than the probes as they are).

use glam::{Vec2, Vec3};
use irradia_core::Ray;
use irradia_geometry::Instance;

/// Barycentric weight of its own corner in each probe (the other two take
/// `(1 - PROBE) / 2`).
const PROBE: f32 = 2.0 / 3.0;

/// The texture coordinates of the corners of the world-space triangle `p` of
/// `instance`'s surface; `None` when no probe meets the surface.
pub fn triangle_uvs(instance: &Instance, p: [Vec3; 3]) -> Option<[Vec2; 3]> {
    let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
    let size = (p[1] - p[0])
        .length()
        .max((p[2] - p[1]).length())
        .max((p[0] - p[2]).length());
    if n == Vec3::ZERO || size.is_nan() || size <= 0.0 {
        return None;
    }
    let other = (1.0 - PROBE) / 2.0;
    let probes: [Option<Vec2>; 3] = std::array::from_fn(|k| {
        let q = p[k] * PROBE + (p[(k + 1) % 3] + p[(k + 2) % 3]) * other;
        surface_uv(instance, q, n, size)
    });
    let found: Vec<Vec2> = probes.iter().flatten().copied().collect();
    match found.len() {
        0 => None,
        3 => {
            // The probes as they are, or unwrapped across a seam: whichever predicts
            // the coordinate at the centre (the mean of the probes, for an affine map)
            // better.
            let raw = [found[0], found[1], found[2]];
            let first = found[0];
            let unwrapped = raw.map(|u| unwrap(u, first));
            let s = match surface_uv(instance, (p[0] + p[1] + p[2]) / 3.0, n, size) {
                Some(centre) => {
                    let miss = |s: &[Vec2; 3]| {
                        let mean = (s[0] + s[1] + s[2]) / 3.0;
                        (unwrap(centre, mean) - mean).length() + (centre - mean).length()
                    };
                    if miss(&unwrapped) < miss(&raw) {
                        unwrapped
                    } else {
                        raw
                    }
                }
                None => raw,
            };
            let mean = (s[0] + s[1] + s[2]) / 3.0;
            // Probe k = PROBE c_k + other (sum - c_k) = (PROBE - other) c_k + other sum,
            // with PROBE - other = 1/2 and 3 other = 1/2: c_k = 2 probe_k - mean.
            Some([0, 1, 2].map(|k| 2.0 * s[k] - mean))
        }
        _ => {
            // Some probes missed (a triangle hanging over the surface's edge): the
            // mean of the others, constant over the triangle.
            let first = found[0];
            let mean = found.iter().map(|u| unwrap(*u, first)).sum::<Vec2>() / found.len() as f32;
            Some([mean; 3])
        }
    }
}

/// `u` moved by whole periods of 1 to within 1/2 of `reference`, per coordinate.
fn unwrap(u: Vec2, reference: Vec2) -> Vec2 {
    u - (u - reference).round()
}

/// The surface's `(u, v)` nearest to `q` along the line through `q` in direction `n`.
fn surface_uv(instance: &Instance, q: Vec3, n: Vec3, size: f32) -> Option<Vec2> {
    let back = 1e-3 * size;
    let reach = 4.0 * size;
    let mut best: Option<(f32, Vec2)> = None;
    for d in [n, -n] {
        if let Some(h) = instance.intersect(&Ray::new(q - d * back, d), reach) {
            let off = (h.t - back).abs();
            match best {
                Some((b, _)) if b <= off => {}
                _ => best = Some((off, h.uv)),
            }
        }
    }
    best.map(|(_, uv)| uv)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Affine3A;
    use irradia_geometry::shapes::polygon::Polygon;
    use std::sync::Arc;

    #[test]
    fn polygon_corners_take_the_shapes_coordinates() {
        // A 2 x 1 rectangle, moved: its uv runs over [0, 1]^2 along its sides.
        let pts = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let shape = Polygon::new(pts.clone()).unwrap();
        let inst = Instance::new(
            Arc::new(shape),
            Affine3A::from_translation(Vec3::new(0.5, -1.0, 3.0)),
        );
        let world = |q: Vec3| q + Vec3::new(0.5, -1.0, 3.0);
        let tri = [world(pts[0]), world(pts[1]), world(pts[2])];
        let uv = triangle_uvs(&inst, tri).unwrap();
        // Whatever axes the polygon chose, the ray tracer's uv at a point inside is
        // the affine blend of the corners' values.
        let inside = tri[0] * 0.5 + tri[1] * 0.3 + tri[2] * 0.2;
        let h = inst
            .intersect(&Ray::new(inside + Vec3::Z, -Vec3::Z), 10.0)
            .unwrap();
        let blend = uv[0] * 0.5 + uv[1] * 0.3 + uv[2] * 0.2;
        assert!((blend - h.uv).length() < 1e-4, "{blend} vs {}", h.uv);
        for c in uv {
            assert!(
                c.min_element() > -1e-4 && c.max_element() < 1.0 + 1e-4,
                "{c}"
            );
        }
    }
}
