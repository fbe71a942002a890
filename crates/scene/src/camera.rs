//! Cameras: perspective (look-at and field of view) and orthographic.
//!
//! Irradia is right-handed with +y up; an unrotated camera looks down -z.

use glam::{Vec2, Vec3};
use irradia_core::Ray;

/// Which image axis the field of view spans.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FovAxis {
    Horizontal,
    Vertical,
    /// The smaller of the two image axes (Mitsuba's convention).
    Smaller,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Pinhole with the full field of view in degrees across `axis`.
    Perspective { fov_degrees: f32, axis: FovAxis },
    /// Parallel rays; `height` is the world-space height of the view.
    Orthographic { height: f32 },
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub look_at: Vec3,
    pub up: Vec3,
    pub projection: Projection,
}

/// A camera prepared for one image size: generates primary rays.
#[derive(Clone, Copy, Debug)]
pub struct CameraRays {
    origin: Vec3,
    /// Unit basis: right, up, forward.
    right: Vec3,
    up: Vec3,
    forward: Vec3,
    /// Half extents of the image plane at distance 1 (perspective) or in world units.
    half: Vec2,
    ortho: bool,
    width: f32,
    height: f32,
}

impl Camera {
    /// The camera's basis and image-plane extents for an image of `width` x `height`.
    pub fn rays(&self, width: u32, height: u32) -> CameraRays {
        let forward = (self.look_at - self.eye).normalize();
        let right = forward.cross(self.up).normalize();
        let up = right.cross(forward);
        let aspect = width as f32 / height as f32;
        let (half, ortho) = match self.projection {
            Projection::Perspective { fov_degrees, axis } => {
                let t = (fov_degrees.to_radians() * 0.5).tan();
                let horizontal = match axis {
                    FovAxis::Horizontal => true,
                    FovAxis::Vertical => false,
                    FovAxis::Smaller => width <= height,
                };
                let half = if horizontal {
                    Vec2::new(t, t / aspect)
                } else {
                    Vec2::new(t * aspect, t)
                };
                (half, false)
            }
            Projection::Orthographic { height: h } => (Vec2::new(0.5 * h * aspect, 0.5 * h), true),
        };
        CameraRays {
            origin: self.eye,
            right,
            up,
            forward,
            half,
            ortho,
            width: width as f32,
            height: height as f32,
        }
    }
}

impl CameraRays {
    /// The primary ray through image position `(x, y)` in pixels (continuous: the centre
    /// of pixel (i, j) is (i + 0.5, j + 0.5)), y down. Directions are unit length.
    #[inline]
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        let sx = (2.0 * x / self.width - 1.0) * self.half.x;
        let sy = (1.0 - 2.0 * y / self.height) * self.half.y;
        if self.ortho {
            Ray::new(self.origin + self.right * sx + self.up * sy, self.forward)
        } else {
            Ray::new(
                self.origin,
                (self.forward + self.right * sx + self.up * sy).normalize(),
            )
        }
    }

    pub fn forward(&self) -> Vec3 {
        self.forward
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_ray_looks_at_target_and_fov_spans_the_axis() {
        let cam = Camera {
            eye: Vec3::new(0.0, 0.0, 5.0),
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            projection: Projection::Perspective {
                fov_degrees: 90.0,
                axis: FovAxis::Horizontal,
            },
        };
        let r = cam.rays(200, 100);
        assert!((r.ray(100.0, 50.0).dir - -Vec3::Z).length() < 1e-6);
        let edge = r.ray(200.0, 50.0).dir;
        assert!(
            (edge.x - edge.z.abs()).abs() < 1e-5,
            "45 degrees to the right edge: {edge}"
        );
        let top = r.ray(100.0, 0.0).dir;
        assert!(top.y > 0.0);
    }
}
