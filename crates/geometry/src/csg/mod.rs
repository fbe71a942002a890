//! Constructive solid geometry by combining spans along the ray (Roth, "Ray casting
//! for modeling solids", 1982; lecture: "Ray casting has become the standard way to
//! visualize quadrics ... in CSG systems").
//!
//! - [`op`]: union, intersection, difference, merge as Boolean functions.
//! - [`combine`]: merging two span lists; the tie rule for coincident surfaces and the
//!   flipped normals of subtracted faces are documented there.
//! - [`node`]: the CSG node, a `Shape` over placed operands, with leaf numbering.
//! - [`resolve`]: the surface at the one boundary a ray reports, after combining
//!   spans by their parameters alone.
//! - [`window`]: the bounds test that skips operands a ray cannot meet.
//! - [`ball`]: the bounding ball of a union of spheres, tested before their boxes.
//! - [`scratch`]: per-thread span buffers (no allocation per ray).

pub mod ball;
pub mod combine;
pub mod node;
pub mod op;
mod resolve;
pub mod scratch;
pub mod window;

pub use combine::{combine, combine_walk, complement};
pub use node::{Csg, CsgOperand};
pub use op::CsgOp;
