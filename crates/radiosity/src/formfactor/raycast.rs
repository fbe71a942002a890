//! Ray casting from elements to vertices (Wallace, Elmquist, Haines 1989, "A ray tracing
//! algorithm for progressive radiosity"): the form factor from a receiving point (a
//! vertex of the receiving element) to a source element is estimated from `k` sample
//! points on the source, each standing for a disk of area `A_j / k`:
//!
//! `F_{dA_v → A_j} ≈ Σ_s V_s (A_j/k) cos θ_v cos θ_s / (π r_s² + A_j/k)`,
//!
//! with visibility `V_s` from a shadow ray through the BVH. The element-to-element
//! factor is the mean over the receiving element's vertices. The samples are jittered
//! on a stratified grid, so the error falls as `k^(-1/2)` or faster.
//!
//! A vertex on the edge between two walls lies on both; it is moved a hair (1e-4 of the
//! way) towards its element's centroid so that its shadow rays do not start inside the
//! neighbouring wall.

use super::{FormFactorMethod, FormFactors};
use crate::error::Result;
use crate::formfactor::contour::{faces, point_to_polygon};
use crate::mesh::subdivide::subdivide;
use crate::mesh::Mesh;
use crate::visibility::Visibility;
use irradia_core::sampling::hash64;
use irradia_core::Rng;

pub struct RayCast {
    pub rays: usize,
    pub seed: u64,
}

impl FormFactorMethod for RayCast {
    fn name(&self) -> &'static str {
        "raycast"
    }
    fn compute(
        &self,
        mesh: &Mesh,
        progress: Option<&(dyn Fn(usize) + Sync)>,
    ) -> Result<FormFactors> {
        let vis = Visibility::new(mesh);
        let els = &mesh.elements;
        let n = els.len();
        let k = self.rays.max(1);
        let side = (k as f64).sqrt().ceil() as usize;
        FormFactors::compute_rows(n, progress, |i, row| {
            let ei = &els[i];
            let verts: Vec<_> = ei
                .poly
                .verts()
                .iter()
                .map(|v| *v + (ei.centroid - *v) * 1e-4)
                .collect();
            for (j, ej) in els.iter().enumerate() {
                if j == i || !verts.iter().any(|v| faces(*v, ej.centroid, ej.normal)) {
                    continue;
                }
                let mut rng = Rng::new(hash64(self.seed ^ ((i as u64) << 32 | j as u64)), 7);
                let cells = subdivide(&ej.poly, (side, side));
                let mut total = 0.0;
                for v in &verts {
                    if !faces(*v, ej.centroid, ej.normal) {
                        continue;
                    }
                    for cell in &cells {
                        let df = point_to_polygon(*v, ei.normal, cell.verts());
                        if df <= 0.0 {
                            continue;
                        }
                        let y = cell.sample(rng.next_f64(), rng.next_f64());
                        if vis.visible(*v, ei.normal, y, ej.normal) {
                            total += df;
                        }
                    }
                }
                row[j] = total / verts.len() as f64;
            }
        })
    }
}
