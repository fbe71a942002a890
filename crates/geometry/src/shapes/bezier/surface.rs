//! A set of bicubic Bézier patches as a shape: hit through its crack-free tessellation
//! (a `TriangleMesh` with its own BVH and the watertight triangle test), shaded with the
//! exact patch normal at the hit's patch parameters.
//!
//! Why tessellate instead of intersecting the patches directly (Newton on `(u, v, t)` or
//! Bézier clipping): a direct solver can miss near patch seams and silhouettes unless it
//! is guarded, and cracks between patches are exactly what the teapot must not show. The
//! tessellation shares bit-identical vertices along shared edges (see `tessellate.rs`),
//! so no ray can pass between two patches. The price is a geometric deviation from the
//! true surface, bounded by [`BezierSurface::max_deviation`] (measured at build time),
//! which shrinks as `1 / level²`.

// `!(a < b)` comparisons are deliberate: they are also true when a value is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::patch::BezierPatch;
use super::tessellate::{tessellate, PatchTriangles};
use crate::mesh::{MeshError, TriangleMesh};
use crate::shape::{Facets, Hit, Shape, Span};
use irradia_core::{Aabb, Ray};

#[derive(Clone, Debug)]
pub struct BezierSurface {
    patches: Vec<BezierPatch>,
    mesh: TriangleMesh,
    triangle_patch: Vec<u32>,
    level: u32,
    max_deviation: f32,
}

/// Why a patch set could not be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BezierError {
    #[error("a Bézier surface needs at least one patch")]
    NoPatches,
    #[error("patch {patch}: control point {point} is not finite")]
    NotFinite { patch: usize, point: usize },
    #[error("the tessellation level must be between 1 and 256, got {0}")]
    BadLevel(u32),
    #[error("tessellation: {0}")]
    Mesh(#[from] MeshError),
}

impl BezierSurface {
    /// Tessellates `patches` into `level × level` cells each (1..=256; 8 to 16 is
    /// plenty for the teapot at screen resolution).
    pub fn new(patches: Vec<BezierPatch>, level: u32) -> Result<Self, BezierError> {
        if patches.is_empty() {
            return Err(BezierError::NoPatches);
        }
        if !(1..=256).contains(&level) {
            return Err(BezierError::BadLevel(level));
        }
        for (pi, p) in patches.iter().enumerate() {
            if let Some(k) = p.points.iter().position(|c| !c.is_finite()) {
                return Err(BezierError::NotFinite {
                    patch: pi,
                    point: k,
                });
            }
        }
        let tris = tessellate(&patches, level);
        let max_deviation = measure_deviation(&patches, &tris);
        let PatchTriangles {
            positions,
            normals,
            uvs,
            indices,
            triangle_patch,
        } = tris;
        let mesh = TriangleMesh::new(positions, indices, Some(normals), Some(uvs))?;
        Ok(Self {
            patches,
            mesh,
            triangle_patch,
            level,
            max_deviation,
        })
    }

    /// The Utah teapot (32 patches, y up, standing on y = 0) at tessellation `level`.
    pub fn teapot(level: u32) -> Result<Self, BezierError> {
        Self::new(super::teapot::teapot_patches(), level)
    }

    pub fn patches(&self) -> &[BezierPatch] {
        &self.patches
    }

    pub fn mesh(&self) -> &TriangleMesh {
        &self.mesh
    }

    pub fn level(&self) -> u32 {
        self.level
    }

    /// Largest distance measured between a triangle's centre and the patch point at the
    /// same parameters: how far the tessellation departs from the exact surface.
    pub fn max_deviation(&self) -> f32 {
        self.max_deviation
    }
}

/// The patch parameters of the point of the patch nearest to `p` (a point on the
/// tessellation), from the interpolated guess `(u, v)`: a few Gauss-Newton steps on
/// `|P(u, v) - p|²` (solve `[Pu Pv] δ = p - P` in the least-squares sense), clamped to the
/// unit square. The linear interpolation of vertex parameters across a triangle is only
/// first-order right; this makes the uv (and so the shading normal) exact up to the
/// tessellation's deviation. Steps that do not reduce the distance are rejected.
fn refine_parameters(patch: &BezierPatch, p: glam::DVec3, u: f64, v: f64) -> (f64, f64) {
    let (mut u, mut v) = (u.clamp(0.0, 1.0), v.clamp(0.0, 1.0));
    let mut dist = (patch.eval(u, v) - p).length_squared();
    for _ in 0..4 {
        let d = patch.derivatives(u, v);
        let r = p - d.p;
        let (a, b, c) = (d.du.dot(d.du), d.du.dot(d.dv), d.dv.dot(d.dv));
        let det = a * c - b * b;
        if !(det.abs() > 1e-12 * (a * c).max(f64::MIN_POSITIVE)) {
            break;
        }
        let (ru, rv) = (d.du.dot(r), d.dv.dot(r));
        let nu = (u + (c * ru - b * rv) / det).clamp(0.0, 1.0);
        let nv = (v + (a * rv - b * ru) / det).clamp(0.0, 1.0);
        let nd = (patch.eval(nu, nv) - p).length_squared();
        if !(nd < dist) {
            break;
        }
        (u, v, dist) = (nu, nv, nd);
    }
    (u, v)
}

fn measure_deviation(patches: &[BezierPatch], tris: &PatchTriangles) -> f32 {
    let mut worst = 0.0f64;
    for (t, idx) in tris.indices.iter().enumerate() {
        let patch = &patches[tris.triangle_patch[t] as usize];
        let c = idx.iter().fold(glam::DVec3::ZERO, |a, &i| {
            a + tris.positions[i as usize].as_dvec3()
        }) / 3.0;
        let uv = idx
            .iter()
            .fold(glam::Vec2::ZERO, |a, &i| a + tris.uvs[i as usize])
            / 3.0;
        let p = patch.eval(uv.x as f64, uv.y as f64);
        worst = worst.max((p - c).length());
    }
    worst as f32
}

impl Shape for BezierSurface {
    fn kind(&self) -> &'static str {
        "bezier"
    }

    fn bounds(&self) -> Aabb {
        self.mesh.bounds()
    }

    /// The mesh hit, with `prim` set to the patch index, `uv` to the patch parameters and
    /// the shading normal to the exact patch normal there (turned to the side of the
    /// triangle's normal, which follows the patch orientation).
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let mut h = self.mesh.intersect(ray, t_max)?;
        let patch_index = self.triangle_patch[h.prim as usize];
        let patch = &self.patches[patch_index as usize];
        let (u, v) = refine_parameters(patch, h.point.as_dvec3(), h.uv.x as f64, h.uv.y as f64);
        h.uv = glam::Vec2::new(u as f32, v as f32);
        let n = patch.normal(u, v);
        if n.is_finite() {
            h.shading_normal = if n.dot(h.normal) < 0.0 { -n } else { n };
        }
        h.prim = patch_index;
        Some(h)
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.mesh.occluded(ray, t_max)
    }

    /// Patches bound no solid in general (the teapot has an open seam around its lid).
    fn is_solid(&self) -> bool {
        false
    }

    fn spans(&self, _ray: &Ray, _out: &mut Vec<Span>) {}

    fn facets(&self, detail: u32) -> Option<Facets> {
        // About `detail` segments around a full turn: the teapot has 4 patches around.
        let level = (detail / 4).clamp(1, 64);
        let t = tessellate(&self.patches, level);
        Some(Facets {
            vertices: t.positions,
            faces: t.indices.iter().map(|f| f.to_vec()).collect(),
            normals: t.normals,
        })
    }
}
