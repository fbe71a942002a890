//! irradia-geometry: every shape of the lecture's "Computing Intersections" slides, with
//! exact intersection, normals, bounds and the entry/exit spans that CSG combines, plus
//! instancing (affine transforms) and the scene-level acceleration structure.
//!
//! Shapes never know about materials: a hit reports which shape, which primitive inside
//! it and which CSG leaf, and the scene maps those to materials.

pub mod accel;
mod accel_stream;
pub mod bvh;
pub mod csg;
pub mod expr;
pub mod flat_meshes;
pub mod generators;
pub mod group;
pub mod instance;
pub mod io;
pub mod mesh;
pub mod packet;
pub mod query;
pub mod roots;
pub mod shape;
pub mod shapes;
pub mod triangle;

pub use accel::{Accel, SceneHit};
pub use csg::{Csg, CsgOp, CsgOperand};
pub use group::ShapeGroup;
pub use instance::Instance;
pub use mesh::{MeshError, TriangleMesh};
pub use query::{ObjectSet, RayQuery, RaySegment};
pub use shape::{Boundary, CastHit, Facets, Hit, Shape, Span};
