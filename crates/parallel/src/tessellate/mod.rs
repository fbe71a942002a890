//! Scene objects that have no facets of their own, made into triangles for the
//! rasterizer (`irradia parallel --renderer raster --workload SCENE`):
//! - planes ([`plane`]): the part inside the view frustum, out to the far plane, cut
//!   into cells that shrink with distance from the eye (and follow a checker's squares);
//! - every other solid: CSG trees, implicit surfaces, unbounded quadrics ([`solid`]):
//!   marching cubes over the object's bounds, or for an unbounded one over the scene's
//!   finite region plus a margin, with vertices moved onto the true surface by the
//!   shape's own CSG spans.
//!
//! Objects with facets (spheres, boxes, meshes, patches ...) keep using
//! `Shape::facets`; open surfaces without facets cannot be tessellated this way and are
//! reported as skipped.

pub mod plane;
pub mod solid;
pub mod uv;

use glam::{DVec4, Mat4, Vec3};
use irradia_core::{Aabb, Ray};
use irradia_geometry::Shape;

pub use plane::{tessellate_plane, PlaneDetail, PlaneMesh, PlaneView};
pub use solid::{tessellate_solid, SolidMesh};

/// The default of [`Tessellation::resolution`].
pub const DEFAULT_RESOLUTION: u32 = 64;

/// How finely objects without facets are cut.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tessellation {
    /// Marching-cubes cells along the longest side of a solid's box (1 to
    /// [`solid::MAX_CELLS`]); plane cells cover at most `4 * height / resolution`
    /// pixels (at least 2).
    pub resolution: u32,
}

impl Default for Tessellation {
    fn default() -> Self {
        Self {
            resolution: DEFAULT_RESOLUTION,
        }
    }
}

impl Tessellation {
    /// The largest plane cell in pixels for an image `height` pixels high.
    pub fn plane_cell_pixels(&self, height: u32) -> f32 {
        (4.0 * height as f32 / self.resolution.max(1) as f32).max(2.0)
    }
}

/// The frustum of a view (`view_proj` = projection * view) for [`tessellate_plane`]:
/// its eight corners (near and far planes), the eye and the size of a pixel.
///
/// The matrices are inverted in f64: with the far plane a million times farther than
/// the near one, an f32 inverse puts the far corners tens of percent off (or at
/// infinity), and the plane would stop short of the horizon or vanish. The f64
/// inverse of the f32 matrices is the frustum the pipeline's clipper really uses.
pub fn plane_view(view: Mat4, proj: Mat4, height: u32) -> PlaneView {
    let inv = (proj.as_dmat4() * view.as_dmat4()).inverse();
    let corners = std::array::from_fn(|k| {
        let ndc = DVec4::new(
            if k & 1 == 0 { -1.0 } else { 1.0 },
            if k & 2 == 0 { -1.0 } else { 1.0 },
            if k & 4 == 0 { 0.0 } else { 1.0 },
            1.0,
        );
        let h = inv * ndc;
        (h.truncate() / h.w).as_vec3()
    });
    let orthographic = proj.w_axis.w != 0.0 && proj.z_axis.w == 0.0;
    PlaneView {
        corners,
        eye: (!orthographic).then(|| view.inverse().transform_point3(Vec3::ZERO)),
        pixel: 2.0 / (proj.y_axis.y.abs().max(1e-12) * height.max(1) as f32),
    }
}

/// The plane of a plane shape, found from its spans: a point on it and its unit
/// normal (pointing out of the half-space), in object space.
pub fn plane_of(shape: &dyn Shape) -> Option<(Vec3, Vec3)> {
    let mut spans = Vec::new();
    for dir in [Vec3::X, Vec3::Y, Vec3::Z] {
        spans.clear();
        shape.spans(&Ray::new(Vec3::ZERO, dir), &mut spans);
        for s in &spans {
            for b in [&s.enter, &s.exit] {
                if b.t.is_finite() && b.normal.length_squared() > 0.5 {
                    return Some((dir * b.t, b.normal.normalize()));
                }
            }
        }
    }
    None
}

/// The part of a world-space `region` a shape with object-space `bounds` can occupy,
/// in object space (`to_object` maps world to object space).
pub fn object_region(bounds: &Aabb, region: &Aabb, to_object: &glam::Affine3A) -> Aabb {
    if bounds.is_finite() {
        return *bounds;
    }
    region.transformed(to_object).intersection(*bounds)
}
