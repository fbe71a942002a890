//! Bicubic Bézier patches and the Utah teapot.
//!
//! Summary / public API:
//! - [`BezierPatch::new([Vec3; 16])`](BezierPatch): evaluation (`eval`), derivatives,
//!   exact normals including collapsed edges (`normal`).
//! - [`BezierSurface::new(patches, level) -> Result<_, BezierError>`](BezierSurface): a
//!   `Shape` hit through a crack-free tessellation (`level × level` cells per patch)
//!   with exact shading normals; `prim` of a hit is the patch index, `uv` its parameters.
//!   Not a solid (no CSG spans).
//! - [`BezierSurface::teapot(level)`](BezierSurface::teapot), [`teapot_patches()`] (the 32
//!   patches, y up, standing on y = 0, 3.15 tall), [`teapot_mesh(level)`] (the
//!   tessellated teapot as a plain `TriangleMesh`, e.g. as a benchmark generator:
//!   `32 · 2 · level²` triangles minus those dropped at the poles).
//! - [`tessellate(patches, level)`](tessellate()) for any patch set.

mod patch;
mod surface;
mod teapot;
mod tessellate;

pub use patch::{cubic_point, BezierPatch, PatchDerivatives};
pub use surface::{BezierError, BezierSurface};
pub use teapot::{teapot_patches, TEAPOT_INDICES, TEAPOT_POINTS};
pub use tessellate::{tessellate, PatchTriangles};

use crate::mesh::TriangleMesh;

/// The Utah teapot tessellated at `level` (>= 1) as a triangle mesh with exact vertex
/// normals and per-patch uvs.
pub fn teapot_mesh(level: u32) -> TriangleMesh {
    let t = tessellate(&teapot_patches(), level.max(1));
    TriangleMesh::new(t.positions, t.indices, Some(t.normals), Some(t.uvs))
        .expect("the built-in teapot data is valid")
}
