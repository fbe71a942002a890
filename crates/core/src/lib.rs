//! irradia-core: the ground floor every other Irradia crate stands on.
//!
//! Vectors come from `glam` (SIMD where it pays); this crate adds the ray, the
//! axis-aligned box, RGB colour, orthonormal frames, deterministic sampling, and the
//! floating-point image with its PNG / EXR / PFM files (written atomically).

pub mod aabb;
pub mod atan;
pub mod color;
pub mod frame;
pub mod image;
pub mod io;
pub mod pages;
pub mod ray;
pub mod sampling;
pub mod sincos;
pub mod text;

pub use aabb::Aabb;
pub use atan::atan2;
pub use color::Rgb;
pub use frame::Frame;
pub use glam::{Affine3A, DVec3, Mat3, Mat3A, Mat4, Vec2, Vec3, Vec3A, Vec4};
pub use image::{Image, ImageError};
pub use ray::{offset_ray_origin, Ray};
pub use sampling::Rng;
pub use sincos::sin_cos;
