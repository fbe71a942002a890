//! The shape catalogue, one file per shape.

pub mod cuboid;
pub mod disk;
pub mod plane;
pub mod polygon;
pub mod polyhedron;
pub mod quadric;
pub mod shape_error;
pub mod sphere;
pub mod torus;
pub mod parametric;
pub mod bezier;
pub mod implicit;

pub use cuboid::Cuboid;
pub use disk::Disk;
pub use plane::Plane;
pub use polygon::Polygon;
pub use polyhedron::Polyhedron;
pub use quadric::Quadric;
pub use shape_error::ShapeError;
pub use sphere::Sphere;
pub use torus::Torus;
pub use parametric::{ParametricError, ParametricSurface};
pub use bezier::{teapot_mesh, teapot_patches, BezierPatch, BezierSurface};
pub use implicit::{ImplicitError, ImplicitSurface, RootMethod};
