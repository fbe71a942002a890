//! The hemicube (Cohen and Greenberg 1985, "The hemi-cube: a radiosity solution for
//! complex environments"; lecture, "Hemicube"): around each element's centroid, the
//! other elements are projected onto the five faces of a half cube and drawn into a
//! z-buffer that stores element ids; each pixel adds its precomputed delta form factor
//!
//! top face (x, y, 1): `ΔF = ΔA / (π (x² + y² + 1)²)`,
//! side face (x, 1, z): `ΔF = z ΔA / (π (x² + z² + 1)²)`,
//!
//! to the element it shows. The table is normalised to sum to 1, so rows of a closed
//! enclosure sum to 1 exactly. Occlusion is the z-buffer's. Elements seen from behind
//! are drawn as occluders that pass no light (the floor under a block with no bottom
//! sees the block's inside and receives nothing).

use super::{FormFactorMethod, FormFactors};
use crate::error::{RadiosityError, Result};
use crate::mesh::Mesh;
use crate::zbuffer::{ItemBuffer, NO_ITEM};
use glam::DVec3;
use std::f64::consts::PI;

/// Item id of back faces: they occlude but contribute nothing.
const BACK_FACE: u32 = u32::MAX - 1;

pub struct Hemicube {
    /// Pixels across the top face (sides are `resolution x resolution/2`).
    pub resolution: usize,
    /// Delta form factors: top face, then the half side face (same for all four).
    top: Vec<f64>,
    side: Vec<f64>,
}

impl Hemicube {
    pub fn new(resolution: usize) -> Self {
        let r = resolution.max(2) & !1;
        let da = (2.0 / r as f64).powi(2);
        let mut top = vec![0.0; r * r];
        let mut side = vec![0.0; r * r / 2];
        for j in 0..r {
            for i in 0..r {
                let x = -1.0 + (i as f64 + 0.5) * 2.0 / r as f64;
                let y = -1.0 + (j as f64 + 0.5) * 2.0 / r as f64;
                top[j * r + i] = da / (PI * (x * x + y * y + 1.0).powi(2));
            }
        }
        for j in 0..r / 2 {
            for i in 0..r {
                let x = -1.0 + (i as f64 + 0.5) * 2.0 / r as f64;
                let z = (j as f64 + 0.5) * 2.0 / r as f64;
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

    /// The delta form factors summed before normalisation differ from 1 by the
    /// discretisation error; exposed for the docs.
    pub fn pixels(&self) -> usize {
        self.top.len() + 4 * self.side.len()
    }

    /// One row of the matrix: form factors from element `i` to all others.
    pub fn row(
        &self,
        mesh: &Mesh,
        i: usize,
        row: &mut [f64],
        buf: &mut ItemBuffer,
        buf_side: &mut ItemBuffer,
    ) {
        let e = &mesh.elements[i];
        let n = e.normal;
        let s = if n.x.abs() > 0.9 { DVec3::Y } else { DVec3::X }
            .cross(n)
            .normalize();
        let t = n.cross(s);
        let c = e.centroid;
        let near = 1e-9 * mesh.scale();
        let r = self.resolution as f64;
        // Camera axes of the five faces: (right, up, forward) in terms of (s, t, n).
        let faces: [(DVec3, DVec3, DVec3, bool); 5] = [
            (s, t, n, true),
            (t, n, s, false),
            (-t, n, -s, false),
            (-s, n, t, false),
            (s, n, -t, false),
        ];
        let mut cam: Vec<DVec3> = Vec::with_capacity(8);
        let mut clipped: Vec<DVec3> = Vec::with_capacity(8);
        let mut screen: Vec<[f64; 3]> = Vec::with_capacity(8);
        let mut scratch: Vec<DVec3> = Vec::with_capacity(12);
        for (fi, &(right, up, fwd, is_top)) in faces.iter().enumerate() {
            let b = if is_top { &mut *buf } else { &mut *buf_side };
            b.clear();
            for (j, ej) in mesh.elements.iter().enumerate() {
                if j == i {
                    continue;
                }
                // An element seen from behind (the inside of a block without a bottom,
                // a one-sided wall) still hides what lies beyond it but passes no light.
                let item = if ej.normal.dot(c - ej.centroid) > 0.0 {
                    j as u32
                } else {
                    BACK_FACE
                };
                cam.clear();
                cam.extend(ej.poly.verts().iter().map(|v| {
                    let d = *v - c;
                    DVec3::new(d.dot(right), d.dot(up), d.dot(fwd))
                }));
                if cam.iter().all(|p| p.z < near) {
                    continue;
                }
                // Clip to the face's frustum: |x| <= z and -z <= y <= z on the top face,
                // 0 <= y <= z on a side face (its lower half lies below the horizon).
                // The planes pass through the eye, so the projected polygon stays inside
                // [-1, 1]² and shared edges of neighbours project consistently.
                clipped.clear();
                clipped.extend_from_slice(&cam);
                let planes: [DVec3; 4] = [
                    DVec3::new(-1.0, 0.0, 1.0),
                    DVec3::new(1.0, 0.0, 1.0),
                    DVec3::new(0.0, -1.0, 1.0),
                    if is_top {
                        DVec3::new(0.0, 1.0, 1.0)
                    } else {
                        DVec3::new(0.0, 1.0, 0.0)
                    },
                ];
                for pl in planes {
                    clip_plane(&clipped, pl, &mut scratch);
                    std::mem::swap(&mut clipped, &mut scratch);
                    if clipped.len() < 3 {
                        break;
                    }
                }
                clipped.retain(|p| p.z >= near);
                if clipped.len() < 3 {
                    continue;
                }
                screen.clear();
                for p in &clipped {
                    let (u, v) = (p.x / p.z, p.y / p.z);
                    let py = if is_top {
                        (v + 1.0) * 0.5 * r
                    } else {
                        v * 0.5 * r
                    };
                    screen.push([(u + 1.0) * 0.5 * r, py, 1.0 / p.z]);
                }
                b.draw(&screen, item);
            }
            let table = if fi == 0 { &self.top } else { &self.side };
            for (k, &it) in b.item.iter().enumerate() {
                if it != NO_ITEM && it != BACK_FACE {
                    row[it as usize] += table[k];
                }
            }
        }
    }
}

/// Sutherland-Hodgman clip of a loop to `plane · p >= 0`.
fn clip_plane(poly: &[DVec3], plane: DVec3, out: &mut Vec<DVec3>) {
    out.clear();
    for k in 0..poly.len() {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        let (da, db) = (plane.dot(a), plane.dot(b));
        if da >= 0.0 {
            out.push(a);
        }
        if (da >= 0.0) != (db >= 0.0) {
            out.push(a + (b - a) * (da / (da - db)));
        }
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
        let r = self.resolution;
        thread_local! {
            static BUFS: std::cell::RefCell<Option<(usize, ItemBuffer, ItemBuffer)>> = const { std::cell::RefCell::new(None) };
        }
        FormFactors::compute_rows(mesh.len(), progress, |i, row| {
            BUFS.with(|cell| {
                let mut slot = cell.borrow_mut();
                if slot.as_ref().map(|s| s.0) != Some(r) {
                    *slot = Some((r, ItemBuffer::new(r, r), ItemBuffer::new(r, r / 2)));
                }
                let (_, top, side) = slot.as_mut().unwrap();
                self.row(mesh, i, row, top, side);
            })
        })
    }
}
