//! The camera transform: view (world to eye) and projection (eye to clip space).
//!
//! Conventions: right-handed, the eye looks down -z, and the projection maps the near
//! plane to NDC depth 0 and the far plane to 1 (glam's `perspective_rh`), so the
//! stored depth is `z_clip / w_clip` in [0, 1].

use glam::{Mat4, Vec3, Vec4};
use irradia_scene::Camera;

/// The transforms of the geometry stage.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewParams {
    /// World to eye space.
    pub view: Mat4,
    /// Eye to clip space.
    pub proj: Mat4,
}

impl Default for ViewParams {
    fn default() -> Self {
        Self::look_at_perspective(
            Vec3::new(0.0, 0.0, 3.0),
            Vec3::ZERO,
            Vec3::Y,
            45.0,
            1.0,
            0.1,
            100.0,
        )
    }
}

impl ViewParams {
    /// A pinhole looking from `eye` at `target`, vertical field of view in degrees.
    pub fn look_at_perspective(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fovy_degrees: f32,
        aspect: f32,
        near: f32,
        far: f32,
    ) -> Self {
        Self {
            view: Mat4::look_at_rh(eye, target, up),
            proj: Mat4::perspective_rh(fovy_degrees.to_radians(), aspect, near, far),
        }
    }

    /// The same view as a scene [`Camera`] rendered at `width` x `height`, so the
    /// rasterizer's pixel (i, j) sees what the ray caster's ray through (i+0.5, j+0.5)
    /// sees.
    pub fn from_camera(camera: &Camera, width: u32, height: u32, near: f32, far: f32) -> Self {
        let aspect = width as f32 / height as f32;
        let view = Mat4::look_at_rh(camera.eye, camera.look_at, camera.up);
        // The field of view comes from the scene's one resolution of it; a thin lens
        // is drawn as its pinhole (everything in focus).
        let proj = match camera.fov_y_radians(width, height) {
            Some(fov_y) => Mat4::perspective_rh(fov_y, aspect, near, far),
            None => {
                let half = camera.half_extents(width, height);
                Mat4::orthographic_rh(-half.x, half.x, -half.y, half.y, near, far)
            }
        };
        Self { view, proj }
    }

    /// World to clip space.
    pub fn view_proj(&self) -> Mat4 {
        self.proj * self.view
    }

    /// True for a parallel projection (the eye direction is the same everywhere).
    pub fn is_orthographic(&self) -> bool {
        self.proj.w_axis.w != 0.0 && self.proj.z_axis.w == 0.0
    }

    /// The eye-space distance along the view axis (positive in front of the eye) of a
    /// stored depth value, by inverting the projection.
    pub fn eye_depth(&self, ndc_depth: f32) -> f32 {
        let p = self.proj.inverse() * Vec4::new(0.0, 0.0, ndc_depth, 1.0);
        -p.z / p.w
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use irradia_scene::{FovAxis, Projection};

    /// The rasterizer's projection puts a point where the scene's camera ray through a
    /// pixel finds it, for every field-of-view axis and both image orientations (both
    /// ask the scene's one resolution of the axis).
    #[test]
    fn projection_matches_the_scenes_rays_for_every_fov_axis() {
        let axes = [
            FovAxis::Horizontal,
            FovAxis::Vertical,
            FovAxis::Diagonal,
            FovAxis::Smaller,
            FovAxis::Larger,
        ];
        for axis in axes {
            for (w, h) in [(160u32, 90u32), (90, 160)] {
                let camera = Camera::new(
                    Vec3::new(1.0, 2.0, 6.0),
                    Vec3::new(0.0, 0.5, 0.0),
                    Vec3::Y,
                    Projection::Perspective {
                        fov_degrees: 50.0,
                        axis,
                    },
                );
                let view = ViewParams::from_camera(&camera, w, h, 0.1, 100.0);
                let rays = camera.rays(w, h);
                for (x, y) in [(3.5f32, 7.25f32), (80.0, 45.0), (150.5, 88.0)] {
                    let r = rays.ray(x, y);
                    let p = r.origin + r.dir * 4.0;
                    let c = view.view_proj() * p.extend(1.0);
                    let (nx, ny) = (c.x / c.w, c.y / c.w);
                    let px = (nx + 1.0) * 0.5 * w as f32;
                    let py = (1.0 - ny) * 0.5 * h as f32;
                    assert!(
                        (px - x).abs() < 1e-3 && (py - y).abs() < 1e-3,
                        "{axis:?} {w}x{h}: ({x}, {y}) projects to ({px}, {py})"
                    );
                }
            }
        }
    }
}
