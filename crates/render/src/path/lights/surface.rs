//! Uniform-by-area points on an emissive object: its own sampler or its facets, and
//! the facets carried to world space once for next-event estimation ([`super`]).

use super::area_jacobian;
use glam::{Vec2, Vec3};
use irradia_core::sampling;
use irradia_geometry::Instance;

/// Uniform-by-area points on an emissive shape, in object space: the shape's own
/// sampler when it has one, otherwise its planar facets (exact for polygons, boxes and
/// polyhedra; an approximation of curved shapes, documented in docs/path-tracing.md).
#[derive(Clone, Debug)]
pub(super) enum SurfaceSampler {
    Exact,
    Facets {
        triangles: Vec<[Vec3; 3]>,
        cdf: Vec<f32>,
    },
}

/// The facets of an emissive instance carried to world space once, at setup, so a
/// light sample costs one table lookup and one barycentric combination (no transform,
/// Jacobian or normalisation per sample; Pharr, Jakob, Humphreys, PBRT 4th ed., 12.5:
/// precompute what sampling needs). The distribution is the one [`SurfaceSampler`]
/// samples (uniform by object-space area; an affine map keeps points uniform inside
/// each triangle), so the estimator is unchanged.
#[derive(Clone, Debug)]
pub(super) struct WorldFacets {
    /// World-space corners of each triangle.
    pub(super) triangles: Vec<[Vec3; 3]>,
    /// Unit world-space normal of each triangle.
    pub(super) normals: Vec<Vec3>,
    /// Density by world area of each triangle's points (`1 / (area · Jacobian)`).
    pub(super) pdf_area: Vec<f32>,
    /// Cumulative object-space area, as in [`SurfaceSampler::Facets`].
    pub(super) cdf: Vec<f32>,
}

impl WorldFacets {
    pub(super) fn new(inst: &Instance, triangles: &[[Vec3; 3]], cdf: &[f32], area: f32) -> Self {
        let m = inst.to_world();
        let normal_to_world = inst.to_object().matrix3.transpose();
        let mut out = WorldFacets {
            triangles: Vec::with_capacity(triangles.len()),
            normals: Vec::with_capacity(triangles.len()),
            pdf_area: Vec::with_capacity(triangles.len()),
            cdf: cdf.to_vec(),
        };
        for &[a, p, q] in triangles {
            let n_obj = (p - a).cross(q - a).normalize();
            out.triangles.push([a, p, q].map(|v| m.transform_point3(v)));
            out.normals
                .push(Vec3::from(normal_to_world * glam::Vec3A::from(n_obj)).normalize());
            out.pdf_area.push(1.0 / (area * area_jacobian(inst, n_obj)));
        }
        out
    }

    /// A world point, its unit normal and its density by area.
    #[inline]
    pub(super) fn sample(&self, u: Vec2) -> Option<(Vec3, Vec3, f32)> {
        let (i, u) = self.pick(u)?;
        let b = sampling::uniform_triangle(u);
        let [a, p, q] = self.triangles[i];
        Some((
            a * (1.0 - b.x - b.y) + p * b.x + q * b.y,
            self.normals[i],
            self.pdf_area[i],
        ))
    }

    /// The triangle `sample` chooses for `u`, and the point in it to warp with
    /// [`sampling::uniform_triangle`] (`u.x` rescaled into the triangle's share).
    #[inline]
    pub(super) fn pick(&self, u: Vec2) -> Option<(usize, Vec2)> {
        let total = *self.cdf.last()?;
        let x = u.x * total;
        // The same index as a binary search of the sorted table; counting avoids a
        // branch that mispredicts half of the time for a quad's two triangles.
        let i = if self.cdf.len() <= 16 {
            self.cdf.iter().map(|&c| (c <= x) as usize).sum::<usize>()
        } else {
            self.cdf.partition_point(|&c| c <= x)
        }
        .min(self.triangles.len() - 1);
        let lo = if i == 0 { 0.0 } else { self.cdf[i - 1] };
        let ux = ((x - lo) / (self.cdf[i] - lo)).clamp(0.0, 1.0 - f32::EPSILON);
        Some((i, Vec2::new(ux, u.y)))
    }
}

impl SurfaceSampler {
    /// The sampler and the object-space area it samples. A shape whose facets are
    /// exactly its surface (rectangles, polygons, boxes) is sampled by its facets even
    /// when it has its own sampler: the same uniform density over the same surface,
    /// and the wide kernel samples facet emitters ([`super::wide`]).
    pub(super) fn for_shape(shape: &dyn irradia_geometry::Shape) -> Option<(Self, f32)> {
        let exact = shape.sample_surface(Vec2::splat(0.5)).is_some();
        if let (Some(area), true, false) = (shape.area(), exact, shape.facets_exact()) {
            return Some((SurfaceSampler::Exact, area));
        }
        let facets = shape.facets(64)?;
        let mut triangles = Vec::new();
        for face in &facets.faces {
            for k in 1..face.len().saturating_sub(1) {
                let v = |i: usize| facets.vertices[face[i] as usize];
                triangles.push([v(0), v(k), v(k + 1)]);
            }
        }
        let mut acc = 0.0;
        let cdf: Vec<f32> = triangles
            .iter()
            .map(|t| {
                acc += 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length();
                acc
            })
            .collect();
        (acc > 0.0).then_some((SurfaceSampler::Facets { triangles, cdf }, acc))
    }

    pub(super) fn sample(
        &self,
        shape: &dyn irradia_geometry::Shape,
        u: Vec2,
    ) -> Option<(Vec3, Vec3)> {
        match self {
            SurfaceSampler::Exact => shape.sample_surface(u),
            SurfaceSampler::Facets { triangles, cdf } => {
                let total = *cdf.last()?;
                let x = u.x * total;
                let i = cdf.partition_point(|&c| c <= x).min(triangles.len() - 1);
                let lo = if i == 0 { 0.0 } else { cdf[i - 1] };
                let ux = ((x - lo) / (cdf[i] - lo)).clamp(0.0, 1.0 - f32::EPSILON);
                let b = sampling::uniform_triangle(Vec2::new(ux, u.y));
                let [a, p, q] = triangles[i];
                let n = (p - a).cross(q - a).normalize();
                Some((a * (1.0 - b.x - b.y) + p * b.x + q * b.y, n))
            }
        }
    }
}
