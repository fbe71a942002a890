//! Display of a radiosity solution (lecture, "Rendered Image"): vertex radiosity by
//! area-weighted averaging of the elements around each vertex (`mesh::weld`), Gouraud
//! interpolation across triangles with a z-buffer, and export of the solved mesh as PLY
//! with vertex colours.
//!
//! Pixel values are radiance `L = b / π` (linear), the quantity a path tracer
//! estimates for a diffuse surface, so images compare directly.

use crate::error::{RadiosityError, Result};
use crate::mesh::weld::{weld, DisplayMesh};
use crate::mesh::Element;
use glam::{DMat4, DVec3, DVec4};
use irradia_core::{Image, Rgb};
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

    /// World to clip space (right-handed, looking down −z in view space). The image's
    /// x runs to the left of +z when looking along +z, as in the Cornell photographs.
    pub fn matrix(&self) -> DMat4 {
        let view = DMat4::look_at_rh(self.eye, self.target, self.up);
        let aspect = self.width as f64 / self.height as f64;
        let proj = DMat4::perspective_rh(
            self.fov_y.to_radians(),
            aspect,
            1e-3 * self.eye.distance(self.target).max(1.0),
            1e7,
        );
        proj * view
    }
}

/// Vertex radiosity of the elements (welded display mesh without T-vertices).
pub fn display_mesh(elements: &[Element], b: &[[f64; 3]], scale: f64) -> DisplayMesh {
    weld(elements, b, scale)
}

/// Renders the display mesh with Gouraud shading and a z-buffer (perspective-correct
/// interpolation of vertex radiance).
pub fn render_gouraud(mesh: &DisplayMesh, view: &View) -> Result<Image> {
    let (w, h) = (view.width as usize, view.height as usize);
    let mut img = Image::new(view.width, view.height)
        .map_err(|e| RadiosityError::Input(format!("image size: {e}")))?;
    let mut depth = vec![f64::INFINITY; w * h];
    let m = view.matrix();
    // Clip-space vertices.
    let clip: Vec<DVec4> = mesh.positions.iter().map(|p| m * p.extend(1.0)).collect();
    let colour: Vec<[f64; 3]> = mesh
        .radiosity
        .iter()
        .map(|b| [b[0] / PI, b[1] / PI, b[2] / PI])
        .collect();
    let mut poly: Vec<(DVec4, [f64; 3])> = Vec::with_capacity(8);
    let mut tmp: Vec<(DVec4, [f64; 3])> = Vec::with_capacity(8);
    for t in &mesh.triangles {
        poly.clear();
        for &k in t {
            poly.push((clip[k as usize], colour[k as usize]));
        }
        // Clip against the near plane (z > -w in GL conventions).
        tmp.clear();
        for i in 0..poly.len() {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            let (da, db) = (a.0.z + a.0.w, b.0.z + b.0.w);
            if da >= 0.0 {
                tmp.push(a);
            }
            if (da >= 0.0) != (db >= 0.0) {
                let s = da / (da - db);
                let c = std::array::from_fn(|c| a.1[c] + (b.1[c] - a.1[c]) * s);
                tmp.push((a.0 + (b.0 - a.0) * s, c));
            }
        }
        if tmp.len() < 3 {
            continue;
        }
        // To screen: (x_px, y_px, z_ndc, 1/w, colour/w).
        let scr: Vec<([f64; 4], [f64; 3])> = tmp
            .iter()
            .map(|(p, c)| {
                let iw = 1.0 / p.w;
                let x = (p.x * iw * 0.5 + 0.5) * w as f64;
                let y = (0.5 - p.y * iw * 0.5) * h as f64;
                ([x, y, p.z * iw, iw], [c[0] * iw, c[1] * iw, c[2] * iw])
            })
            .collect();
        for k in 1..scr.len() - 1 {
            raster_triangle(
                &scr[0],
                &scr[k],
                &scr[k + 1],
                w,
                h,
                &mut depth,
                img.pixels_mut(),
            );
        }
    }
    Ok(img)
}

type SV = ([f64; 4], [f64; 3]);

fn raster_triangle(a: &SV, b: &SV, c: &SV, w: usize, h: usize, depth: &mut [f64], px: &mut [Rgb]) {
    let area = (b.0[0] - a.0[0]) * (c.0[1] - a.0[1]) - (b.0[1] - a.0[1]) * (c.0[0] - a.0[0]);
    if area == 0.0 || !area.is_finite() {
        return;
    }
    let xmin = a.0[0].min(b.0[0]).min(c.0[0]).floor().max(0.0) as usize;
    let ymin = a.0[1].min(b.0[1]).min(c.0[1]).floor().max(0.0) as usize;
    let xmax = a.0[0].max(b.0[0]).max(c.0[0]).ceil().min(w as f64).max(0.0) as usize;
    let ymax = a.0[1].max(b.0[1]).max(c.0[1]).ceil().min(h as f64).max(0.0) as usize;
    let e = |p: &SV, q: &SV, x: f64, y: f64| {
        (q.0[0] - p.0[0]) * (y - p.0[1]) - (q.0[1] - p.0[1]) * (x - p.0[0])
    };
    for y in ymin..ymax {
        for x in xmin..xmax {
            let (fx, fy) = (x as f64 + 0.5, y as f64 + 0.5);
            let (w0, w1, w2) = (
                e(b, c, fx, fy) / area,
                e(c, a, fx, fy) / area,
                e(a, b, fx, fy) / area,
            );
            if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                continue;
            }
            let z = w0 * a.0[2] + w1 * b.0[2] + w2 * c.0[2];
            let k = y * w + x;
            if z >= depth[k] || z > 1.0 {
                continue;
            }
            depth[k] = z;
            let iw = w0 * a.0[3] + w1 * b.0[3] + w2 * c.0[3];
            let col: [f64; 3] =
                std::array::from_fn(|ch| (w0 * a.1[ch] + w1 * b.1[ch] + w2 * c.1[ch]) / iw);
            px[k] = Rgb::new(col[0] as f32, col[1] as f32, col[2] as f32);
        }
    }
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
