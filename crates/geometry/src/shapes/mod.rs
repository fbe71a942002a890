//! The shape catalogue, one file per shape.

pub mod sphere;

pub use sphere::Sphere;
