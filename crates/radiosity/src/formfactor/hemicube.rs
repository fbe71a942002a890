//! The hemicube (Cohen and Greenberg 1985, "The hemi-cube: a radiosity solution for
//! complex environments"; lecture, "Hemicube"): around each element's centroid, the
//! other elements are projected onto the five faces of a half cube and drawn into a
//! z-buffer that stores element ids; each pixel adds its precomputed delta form factor
//!
//! top face (x, y, 1): `ΔF = ΔA / (π (x² + y² + 1)²)`,
//! side face (x, 1, z): `ΔF = z ΔA / (π (x² + z² + 1)²)`,
//!
//! to the element it shows. The table is normalised to sum to 1, so rows of a closed
//! enclosure sum to 1 exactly. Elements seen from behind are drawn as occluders that
//! pass no light (the floor under a block with no bottom sees the block's inside and
//! receives nothing).
//!
//! The faces are drawn by the software rasterizer (`irradia_raster`, the lecture's
//! "OpenGL pipeline"): an ID framebuffer with a 32-bit float depth buffer, a 90°
//! frustum per face (the top face `r x r` pixels, the four side faces the upper half of
//! such a frustum, `r x r/2`), homogeneous near-plane clipping, and the rasterizer's
//! top-left fill rule, so elements sharing an edge neither overlap nor leave cracks.
//!
//! Precision: each row first expresses every element corner in the frame of the
//! receiving element's centroid in f64 and only then rounds to f32, so coordinates near
//! the eye keep their relative precision whatever the scene's origin. The near plane
//! sits at 1% of the element's size (only geometry passing within that distance of the
//! centroid, i.e. intersecting the element, is cut away); the far plane beyond the
//! scene. The stored depth `(f/(f−n))(1 − n/z)` then separates surfaces whose distances
//! differ by more than about `6e-8 z/n` (1e-4 of the distance in a 1000-element
//! Cornell box).

use super::{FormFactorMethod, FormFactors};
use crate::error::{RadiosityError, Result};
use crate::mesh::Mesh;
use glam::{DVec3, Mat3, Mat4, Vec3, Vec4};
use irradia_raster::{
    ColorBuffer, ColorFormat, CullMode, DepthFunc, Framebuffer, Mesh as RasterMesh, Pipeline,
    Shading, ViewParams, NO_ID,
};
use std::f64::consts::PI;

/// Item id of back faces (and of the receiving element itself): they occlude but
/// contribute nothing.
const BACK_FACE: u32 = NO_ID - 1;

/// Near plane as a fraction of the receiving element's size (square root of its area).
const NEAR_FRACTION: f64 = 1e-2;

pub struct Hemicube {
    /// Pixels across the top face (sides are `resolution x resolution/2`).
    pub resolution: usize,
    /// Delta form factors in the rasterizer's pixel order (row 0 at the top of the
    /// image): the top face, then the side face (the same table for all four; row 0 is
    /// the side's upper edge, the last row lies on the horizon).
    top: Vec<f64>,
    side: Vec<f64>,
}

/// The five faces as (forward, up) in the receiving element's frame `(s, t, n)` (x, y, z
/// = s, t, n): the top face looks along the normal, the sides along ±s and ±t with the
/// normal up. The camera's right axis is `forward × up` (a right-handed view).
const FACES: [(Vec3, Vec3); 5] = [
    (Vec3::Z, Vec3::Y),
    (Vec3::X, Vec3::Z),
    (Vec3::NEG_X, Vec3::Z),
    (Vec3::Y, Vec3::Z),
    (Vec3::NEG_Y, Vec3::Z),
];

impl Hemicube {
    pub fn new(resolution: usize) -> Self {
        let r = resolution.max(2) & !1;
        let h = r / 2;
        let px = 2.0 / r as f64;
        let da = px * px;
        let mut top = vec![0.0; r * r];
        let mut side = vec![0.0; r * h];
        // Pixel centre (i, j) of an r x r face: x = -1 + (i + 1/2) px, y = 1 - (j + 1/2) px.
        for j in 0..r {
            for i in 0..r {
                let x = -1.0 + (i as f64 + 0.5) * px;
                let y = 1.0 - (j as f64 + 0.5) * px;
                top[j * r + i] = da / (PI * (x * x + y * y + 1.0).powi(2));
            }
        }
        // A side face shows heights z in (0, 1] above the horizon: row j at z = 1 - (j + 1/2) px.
        for j in 0..h {
            for i in 0..r {
                let x = -1.0 + (i as f64 + 0.5) * px;
                let z = 1.0 - (j as f64 + 0.5) * px;
                side[j * r + i] = z * da / (PI * (x * x + z * z + 1.0).powi(2));
            }
        }
        let total: f64 = top.iter().sum::<f64>() + 4.0 * side.iter().sum::<f64>();
        top.iter_mut().for_each(|v| *v /= total);
        side.iter_mut().for_each(|v| *v /= total);
        Self {
            resolution: r,
            top,
            side,
        }
    }

    /// Pixels over the five faces.
    pub fn pixels(&self) -> usize {
        self.top.len() + 4 * self.side.len()
    }

    /// One row of the matrix: form factors from element `i` to all others, drawing the
    /// scene (prepared by [`Scratch::new`]) into `scratch`'s framebuffers.
    pub fn row(&self, mesh: &Mesh, i: usize, row: &mut [f64], scratch: &mut Scratch) {
        let e = &mesh.elements[i];
        let n = e.normal;
        let s = if n.x.abs() > 0.9 { DVec3::Y } else { DVec3::X }
            .cross(n)
            .normalize();
        let t = n.cross(s);
        let c = e.centroid;
        // Every corner in the receiving element's frame, and which elements face it.
        let mut k = 0;
        for (j, ej) in mesh.elements.iter().enumerate() {
            scratch.element_id[j] = if j != i && ej.normal.dot(c - ej.centroid) > 0.0 {
                j as u32
            } else {
                BACK_FACE
            };
            for v in ej.poly.verts() {
                let d = *v - c;
                scratch.mesh.positions[k] =
                    Vec3::new(d.dot(s) as f32, d.dot(t) as f32, d.dot(n) as f32);
                k += 1;
            }
        }
        let near = NEAR_FRACTION * e.area.sqrt();
        let far = 4.0 * scratch.scene_size + near;
        let proj_top =
            Mat4::perspective_rh(std::f32::consts::FRAC_PI_2, 1.0, near as f32, far as f32);
        // The side faces show the upper half of the same frustum: y_ndc' = 2 y_ndc - 1.
        let upper_half = Mat4::from_cols(Vec4::X, 2.0 * Vec4::Y, Vec4::Z, Vec4::W - Vec4::Y);
        let proj_side = upper_half * proj_top;
        for (f, &(fwd, up)) in FACES.iter().enumerate() {
            let right = fwd.cross(up);
            scratch.select(f == 0, fwd, up, right, near as f32);
            let view = Mat4::from_mat3(Mat3::from_cols(right, up, -fwd).transpose());
            let (pipe, fb, table) = if f == 0 {
                (&mut scratch.top, &mut scratch.fb_top, &self.top)
            } else {
                (&mut scratch.side, &mut scratch.fb_side, &self.side)
            };
            pipe.view = ViewParams {
                view,
                proj: if f == 0 { proj_top } else { proj_side },
            };
            fb.clear([0.0; 4]);
            pipe.render_mesh(&scratch.mesh, fb)
                .expect("the hemicube's framebuffers match its pipelines");
            let ColorBuffer::Id(ids) = &fb.color else {
                unreachable!("hemicube framebuffers are ID buffers")
            };
            for (&id, &df) in ids.iter().zip(table) {
                if id < BACK_FACE {
                    row[id as usize] += df;
                }
            }
        }
    }
}

/// Working state of [`Hemicube::row`] (one per worker thread): the elements as one rasterizer mesh (corners
/// rewritten for every row), the two pipelines and their framebuffers.
pub struct Scratch {
    /// Corners of every element; indices and ids of the triangles drawn on one face.
    mesh: RasterMesh,
    /// Element `j` owns corners `first_corner[j]..first_corner[j + 1]`.
    first_corner: Vec<u32>,
    /// The id drawn for each element in the current row.
    element_id: Vec<u32>,
    scene_size: f64,
    top: Pipeline,
    side: Pipeline,
    fb_top: Framebuffer,
    fb_side: Framebuffer,
}

impl Scratch {
    pub fn new(mesh: &Mesh, resolution: usize) -> Result<Self> {
        let r = resolution as u32;
        let mut first_corner = Vec::with_capacity(mesh.len() + 1);
        let mut corners = 0u32;
        for e in &mesh.elements {
            first_corner.push(corners);
            corners += e.poly.verts().len() as u32;
        }
        first_corner.push(corners);
        let pipeline = |w, h| {
            let mut p = Pipeline::new(w, h);
            p.shading = Shading::Unlit;
            p.cull = CullMode::None;
            p.depth_func = DepthFunc::Less;
            p
        };
        let fb = |w, h| {
            Framebuffer::new(w, h, ColorFormat::Id)
                .map_err(|e| RadiosityError::Input(format!("hemicube resolution {r}: {e}")))
        };
        Ok(Self {
            mesh: RasterMesh {
                positions: vec![Vec3::ZERO; corners as usize],
                indices: Vec::with_capacity(2 * mesh.len()),
                ids: Vec::with_capacity(2 * mesh.len()),
                ..RasterMesh::default()
            },
            element_id: vec![BACK_FACE; mesh.len()],
            first_corner,
            scene_size: mesh.scale(),
            top: pipeline(r, r),
            side: pipeline(r, r / 2),
            fb_top: fb(r, r)?,
            fb_side: fb(r, r / 2)?,
        })
    }
}

impl FormFactorMethod for Hemicube {
    fn name(&self) -> &'static str {
        "hemicube"
    }
    fn compute(
        &self,
        mesh: &Mesh,
        progress: Option<&(dyn Fn(usize) + Sync)>,
    ) -> Result<FormFactors> {
        if self.resolution > 8192 {
            return Err(RadiosityError::Input(format!(
                "--hemicube-resolution {} is too large (at most 8192)",
                self.resolution
            )));
        }
        if mesh
            .elements
            .iter()
            .map(|e| e.poly.verts().len())
            .sum::<usize>()
            >= u32::MAX as usize
        {
            return Err(RadiosityError::Input(
                "too many element corners for the hemicube's rasterizer mesh; use --solver hierarchical".into(),
            ));
        }
        // Scratch state for one row at a time per worker: taken from the pool, returned
        // after the row. The first is made here so that a bad size is an error.
        let pool = std::sync::Mutex::new(vec![Scratch::new(mesh, self.resolution)?]);
        FormFactors::compute_rows(mesh.len(), progress, |i, row| {
            let taken = pool.lock().ok().and_then(|mut p| p.pop());
            let mut scratch = taken.unwrap_or_else(|| {
                Scratch::new(mesh, self.resolution).expect("the first scratch had this size")
            });
            self.row(mesh, i, row, &mut scratch);
            if let Ok(mut p) = pool.lock() {
                p.push(scratch);
            }
        })
    }
}

impl Scratch {
    /// Frustum culling in the application, as an OpenGL program would do it: fills the
    /// mesh's triangle list with the elements not wholly outside one plane of the face's
    /// frustum (`z > near`, `|x| <= z`, `-z <= y <= z` on the top face and `0 <= y <= z`
    /// on a side face, in the face's camera axes), fan-triangulated. The rasterizer
    /// clips the rest.
    fn select(&mut self, is_top: bool, fwd: Vec3, up: Vec3, right: Vec3, near: f32) {
        self.mesh.indices.clear();
        self.mesh.ids.clear();
        for (j, w) in self.first_corner.windows(2).enumerate() {
            let mut outside = 0x1fu8;
            for p in &self.mesh.positions[w[0] as usize..w[1] as usize] {
                let (x, y, z) = (p.dot(right), p.dot(up), p.dot(fwd));
                let bottom = if is_top { -z } else { 0.0 };
                outside &= (z < near) as u8
                    | ((x > z) as u8) << 1
                    | ((x < -z) as u8) << 2
                    | ((y > z) as u8) << 3
                    | ((y < bottom) as u8) << 4;
                if outside == 0 {
                    break;
                }
            }
            if outside != 0 {
                continue;
            }
            for q in w[0] + 1..w[1] - 1 {
                self.mesh.indices.push([w[0], q, q + 1]);
                self.mesh.ids.push(self.element_id[j]);
            }
        }
    }
}
