//! The shape catalogue, one file per shape.
//!
//! Constructors of the shapes-and-CSG part (all check their input and return
//! `Result<_, ShapeError>`; solids have inside = the side their normals point away from):
//! - `Sphere::try_new(center, radius)` (`Sphere::new` panics on bad input).
//! - `Quadric::new([A, B, C, D, E, F, G, H, I, J])`: `Ax² + By² + Cz² + Dxy + Exz + Fyz
//!   + Gx + Hy + Iz + J = 0` (POV-Ray's order), solid where `≤ 0`.
//! - Named quadrics, axis of symmetry `y`: `Quadric::ellipsoid(center, radii)`,
//!   `cylinder(radius)`, `cone(slope)` (apex at the origin, radius `slope·|y|`),
//!   `paraboloid(k)` (`y = k(x² + z²)`), `hyperboloid_one_sheet(a, c)`,
//!   `hyperboloid_two_sheets(a, c)`; `.transformed(&Affine3A)` places any of them.
//! - Capped solids between two points: `Quadric::capped_cylinder(a, b, radius)` (POV-Ray's
//!   `cylinder`), `Quadric::capped_cone(a, radius_a, b, radius_b)` (POV-Ray's `cone`).
//! - Clipping (keeps `n·p ≤ d`, capped so the result is a closed solid):
//!   `q.clipped_by_plane(normal, offset)`, `q.clipped_by_box(min, max)`; `q.open()` keeps
//!   only the quadric surface (not a solid).
//! - `Plane::new(normal, offset)`: the half-space `n̂·p ≤ offset` (POV-Ray's `plane`).
//! - `Cuboid::new(corner_a, corner_b)`: the box (POV-Ray's `box`).
//! - `Polyhedron::new(&[(normal, offset)])`: convex, the intersection of `n·p ≤ d`;
//!   `Polyhedron::platonic(4 | 6 | 8 | 12 | 20)` with inradius 1.
//! - `Polygon::new(vertices)`: planar, convex or not, even-odd rule (open surface).
//! - `Disk::new(center, normal, radius)`, `.with_hole(inner_radius)` (open surface).
//! - Mitsuba 3's shapes, with Mitsuba's parameterisation (uv) and normals:
//!   `Rectangle::flipped(flip)` (`[-1, 1]²` at z = 0), `Cube::new(flip)` (`[-1, 1]³`),
//!   `Tube::new(p0, p1, radius)` (Mitsuba's open `cylinder`), `SdfGrid::new(dims,
//!   values, normals)` (a signed distance grid over `[0, 1]³`); `Sphere` and `Disk`
//!   report Mitsuba's uv and take `with_flipped_normals`.
//! - CSG (`crate::csg`): `Csg::union | intersection | difference | merge(operands)`, each
//!   operand `CsgOperand::shape(Arc<dyn Shape>, to_parent)` or `CsgOperand::node(csg,
//!   to_parent)`; `csg.leaf_count()`, `csg.leaf_paths()` map `Hit::leaf` to operands.

pub mod bezier;
pub mod cube;
pub mod cuboid;
pub mod disk;
pub mod implicit;
pub mod mitsuba_frame;
pub mod parametric;
pub mod plane;
pub mod polygon;
pub mod polyhedron;
pub mod quadric;
pub mod rectangle;
pub mod sdfgrid;
pub mod shape_error;
pub mod sphere;
pub mod torus;
pub mod tube;

pub use bezier::{teapot_mesh, teapot_patches, BezierPatch, BezierSurface};
pub use cube::Cube;
pub use cuboid::Cuboid;
pub use disk::Disk;
pub use implicit::{ImplicitError, ImplicitSurface, RootMethod};
pub use parametric::{ParametricError, ParametricSurface};
pub use plane::Plane;
pub use polygon::Polygon;
pub use polyhedron::Polyhedron;
pub use quadric::Quadric;
pub use rectangle::Rectangle;
pub use sdfgrid::{SdfGrid, SdfNormals};
pub use shape_error::ShapeError;
pub use sphere::Sphere;
pub use torus::Torus;
pub use tube::Tube;
