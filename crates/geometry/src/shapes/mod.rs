//! The shape catalogue, one file per shape.

pub mod sphere;
pub mod torus;

pub use sphere::Sphere;
pub use torus::Torus;
