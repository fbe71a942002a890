//! Monte Carlo area-to-area form factors: `N` pairs of points, uniform on each element,
//!
//! `F_ij ≈ (A_j / N) Σ V cos θ_i cos θ_j / (π r²)`,
//!
//! with visibility `V` by shadow rays. The same point pairs serve both directions
//! (`A_i F_ij = A_j F_ji` is the one integral `G_ij`), so reciprocity holds exactly and
//! only closure (rows summing to 1) shows the sampling error, which falls as `N^(-1/2)`.
//!
//! For elements that share an edge the integrand `1/r²` has infinite variance; as in
//! Wallace et al. (1989) each sample stands for a disk of area `√(A_i A_j) / N`, and the
//! kernel becomes `cos θ_i cos θ_j / (π r² + √(A_i A_j)/N)`: bounded, with a bias that
//! vanishes as N grows.

use super::{FormFactorMethod, FormFactors};
use crate::error::Result;
use crate::mesh::Mesh;
use crate::visibility::Visibility;
use irradia_core::sampling::hash64;
use irradia_core::Rng;
use std::f64::consts::PI;

pub struct MonteCarlo {
    pub samples: usize,
    pub seed: u64,
}

impl FormFactorMethod for MonteCarlo {
    fn name(&self) -> &'static str {
        "montecarlo"
    }
    fn compute(
        &self,
        mesh: &Mesh,
        progress: Option<&(dyn Fn(usize) + Sync)>,
    ) -> Result<FormFactors> {
        let vis = Visibility::new(mesh);
        let els = &mesh.elements;
        let n = els.len();
        let k = self.samples.max(1);
        let side = (k as f64).sqrt().ceil() as usize;
        let mut m = FormFactors::compute_rows(n, progress, |i, row| {
            let ei = &els[i];
            for (j, ej) in els.iter().enumerate().skip(i + 1) {
                let mut rng = Rng::new(hash64(self.seed ^ ((i as u64) << 32 | j as u64)), 11);
                let mut g = 0.0;
                let disk = (ei.area * ej.area).sqrt() / k as f64;
                for s in 0..k {
                    let (cx, cy) = (s % side, (s / side) % side);
                    let x = ei.poly.sample(
                        (cx as f64 + rng.next_f64()) / side as f64,
                        (cy as f64 + rng.next_f64()) / side as f64,
                    );
                    let y = ej.poly.sample(rng.next_f64(), rng.next_f64());
                    let d = y - x;
                    let r2 = d.length_squared();
                    if r2 == 0.0 {
                        continue;
                    }
                    let r = r2.sqrt();
                    let ci = ei.normal.dot(d) / r;
                    let cj = -ej.normal.dot(d) / r;
                    if ci <= 0.0 || cj <= 0.0 {
                        continue;
                    }
                    if vis.visible(x, ei.normal, y, ej.normal) {
                        g += ci * cj / (PI * r2 + disk);
                    }
                }
                // G_ij / A_i = A_j * mean
                row[j] = ej.area * g / k as f64;
            }
        })?;
        for i in 0..n {
            for j in i + 1..n {
                m.f[j * n + i] = m.f[i * n + j] * els[i].area / els[j].area;
            }
        }
        Ok(m)
    }
}
