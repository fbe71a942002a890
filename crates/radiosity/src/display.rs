//! Display of a radiosity solution (lecture, "Rendered Image"): vertex radiosity by
//! area-weighted averaging of the elements around each vertex (`mesh::weld`), Gouraud
//! interpolation across triangles by the software rasterizer (`irradia_raster`, unlit
//! per-vertex colours, perspective-correct interpolation, z-buffer), and export of the
//! solved mesh as PLY with vertex colours. The two-pass image (ray-traced mirrors and
//! glass over the same vertex radiosity) is `crate::two_pass`.
//!
//! Pixel values are radiance `L = b / π` (linear), the quantity a path tracer
//! estimates for a diffuse surface, so images compare directly.

use crate::error::{RadiosityError, Result};
use crate::mesh::weld::{weld, DisplayMesh};
use crate::mesh::Element;
use glam::{DMat4, DVec3, Mat4};
use irradia_core::{Image, Rgb};
use irradia_raster::{ColorFormat, Framebuffer, Mesh as RasterMesh, Pipeline, Shading, ViewParams};
use std::f64::consts::PI;
use std::io::Write;
use std::path::Path;

/// A pinhole camera.
#[derive(Clone, Copy, Debug)]
pub struct View {
    pub eye: DVec3,
    pub target: DVec3,
    pub up: DVec3,
    /// Vertical field of view in degrees.
    pub fov_y: f64,
    pub width: u32,
    pub height: u32,
}

impl View {
    /// The Cornell box camera of cornell-box.md: at (278, 273, −800) looking along +z,
    /// focal length 35 mm on a 25 mm film (39.3° field of view).
    pub fn cornell(width: u32, height: u32) -> Self {
        Self {
            eye: DVec3::new(278.0, 273.0, -800.0),
            target: DVec3::new(278.0, 273.0, 0.0),
            up: DVec3::Y,
            fov_y: 2.0 * (0.0125f64 / 0.035).atan().to_degrees(),
            width,
            height,
        }
    }

    fn near_far(&self) -> (f64, f64) {
        (1e-3 * self.eye.distance(self.target).max(1.0), 1e7)
    }

    /// World to clip space (right-handed, looking down −z in view space). The image's
    /// x runs to the left of +z when looking along +z, as in the Cornell photographs.
    pub fn matrix(&self) -> DMat4 {
        let view = DMat4::look_at_rh(self.eye, self.target, self.up);
        let aspect = self.width as f64 / self.height as f64;
        let (near, far) = self.near_far();
        DMat4::perspective_rh(self.fov_y.to_radians(), aspect, near, far) * view
    }

    /// The same camera for the rasterizer.
    pub fn view_params(&self) -> ViewParams {
        let (near, far) = self.near_far();
        ViewParams {
            view: Mat4::look_at_rh(self.eye.as_vec3(), self.target.as_vec3(), self.up.as_vec3()),
            proj: Mat4::perspective_rh(
                self.fov_y.to_radians() as f32,
                self.width as f32 / self.height as f32,
                near as f32,
                far as f32,
            ),
        }
    }

    /// The unit direction of the ray from the eye through the image point `(x, y)` in
    /// pixels (origin at the top left, y down; pixel `(i, j)` has its centre at
    /// `(i + 1/2, j + 1/2)`): the ray the rasterizer's pixel sees.
    pub fn ray_direction(&self, x: f64, y: f64) -> DVec3 {
        let fwd = (self.target - self.eye).normalize();
        let right = fwd.cross(self.up).normalize();
        let up = right.cross(fwd);
        let ty = (0.5 * self.fov_y.to_radians()).tan();
        let tx = ty * self.width as f64 / self.height as f64;
        let sx = 2.0 * x / self.width as f64 - 1.0;
        let sy = 1.0 - 2.0 * y / self.height as f64;
        (fwd + right * (sx * tx) + up * (sy * ty)).normalize()
    }
}

/// Vertex radiosity of the elements (welded display mesh without T-vertices).
pub fn display_mesh(elements: &[Element], b: &[[f64; 3]], scale: f64) -> DisplayMesh {
    weld(elements, b, scale)
}

/// The display mesh as a rasterizer mesh: positions and, as vertex colours, the
/// radiance `b/π`.
pub fn raster_mesh(mesh: &DisplayMesh) -> RasterMesh {
    RasterMesh {
        positions: mesh.positions.iter().map(|p| p.as_vec3()).collect(),
        colors: mesh
            .radiosity
            .iter()
            .map(|b| {
                [
                    (b[0] / PI) as f32,
                    (b[1] / PI) as f32,
                    (b[2] / PI) as f32,
                    1.0,
                ]
            })
            .collect(),
        indices: mesh.triangles.clone(),
        ..RasterMesh::default()
    }
}

/// Renders the display mesh with Gouraud shading: the software rasterizer draws the
/// triangles with their vertex radiance as unlit colours, interpolated
/// perspective-correctly, into a float framebuffer with a z-buffer.
pub fn render_gouraud(mesh: &DisplayMesh, view: &View) -> Result<Image> {
    let mut fb = Framebuffer::new(view.width, view.height, ColorFormat::Rgba32F)
        .map_err(|e| RadiosityError::Input(format!("image size: {e}")))?;
    let mut pipeline = Pipeline::new(view.width, view.height);
    pipeline.shading = Shading::Unlit;
    pipeline.view = view.view_params();
    pipeline
        .render_mesh(&raster_mesh(mesh), &mut fb)
        .map_err(|e| RadiosityError::Failure(format!("rasterizer: {e}")))?;
    Ok(fb.to_image())
}

/// Writes the display mesh as a binary little-endian PLY: position, normal, vertex
/// colour (8-bit sRGB of the radiance `b/π`, clamped) and the radiosity itself as
/// floats; faces as triangles. Written atomically.
pub fn write_ply(mesh: &DisplayMesh, path: &Path) -> Result<()> {
    let mut out: Vec<u8> =
        Vec::with_capacity(mesh.positions.len() * 40 + mesh.triangles.len() * 13 + 512);
    let header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment irradia radiosity solution; radiosity_* in the scene's units, colours are sRGB of radiosity/pi\n\
         element vertex {}\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
         property uchar red\nproperty uchar green\nproperty uchar blue\nproperty float radiosity_r\nproperty float radiosity_g\nproperty float radiosity_b\n\
         element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        mesh.positions.len(),
        mesh.triangles.len()
    );
    out.extend_from_slice(header.as_bytes());
    for (i, p) in mesh.positions.iter().enumerate() {
        for v in [
            p.x,
            p.y,
            p.z,
            mesh.normals[i].x,
            mesh.normals[i].y,
            mesh.normals[i].z,
        ] {
            out.extend_from_slice(&(v as f32).to_le_bytes());
        }
        let b = mesh.radiosity[i];
        let c = Rgb::new((b[0] / PI) as f32, (b[1] / PI) as f32, (b[2] / PI) as f32).to_srgb8();
        out.extend_from_slice(&c);
        for v in b {
            out.extend_from_slice(&(v as f32).to_le_bytes());
        }
    }
    for t in &mesh.triangles {
        out.push(3);
        for k in t {
            out.extend_from_slice(&(*k as i32).to_le_bytes());
        }
    }
    irradia_core::io::write_atomic(path, &out)
        .map_err(|e| RadiosityError::Failure(format!("cannot write {}: {e}", path.display())))?;
    let _ = std::io::sink().flush();
    Ok(())
}
