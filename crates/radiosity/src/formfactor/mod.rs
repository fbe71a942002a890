//! Form factors: `F[i][j]`, the fraction of the energy leaving element `i` that arrives
//! at element `j` (lecture, "Form Factor Integral"):
//!
//! `F_ij = (1/A_i) ∫_{A_i} ∫_{A_j} V cos θ_i cos θ_j / (π r²) dA_j dA_i`.
//!
//! One method per file behind [`FormFactorMethod`]:
//! - `analytic/`: the lecture's closed-form catalogue ("Form Factor Examples 1-3") and,
//!   as a matrix method, the analytic inner integral (point to polygon) with Gauss
//!   quadrature over the sending element;
//! - `contour`: the closed-form point-to-polygon (contour integral) formula at centroids;
//! - `hemisphere`: the Nusselt analogue, integrated numerically by ray casting;
//! - `hemicube`: Cohen and Greenberg's hemicube with precomputed delta form factors,
//!   drawn with the software rasterizer (`irradia_raster`) into an ID buffer;
//! - `raycast`: Wallace, Elmquist, Haines (1989), from sample points on the source
//!   element to the receiving element's vertices, through the BVH;
//! - `montecarlo`: Monte Carlo area-to-area integration.
//!
//! Every method's result reports its row sums (1 in a closed enclosure) and its
//! reciprocity error (`A_i F_ij = A_j F_ji`).

pub mod analytic;
pub mod contour;
pub mod hemicube;
pub mod hemisphere;
pub mod montecarlo;
pub mod raycast;

use crate::error::{RadiosityError, Result};
use crate::mesh::Mesh;
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Largest dense matrix the form-factor methods will allocate (bytes).
pub const MAX_MATRIX_BYTES: usize = 8 << 30;

/// A dense form-factor matrix, row-major.
#[derive(Clone, Debug)]
pub struct FormFactors {
    pub n: usize,
    pub f: Vec<f64>,
}

/// Row sums and reciprocity error of a form-factor matrix.
#[derive(Clone, Copy, Debug, Default)]
pub struct Diagnostics {
    pub row_sum_min: f64,
    pub row_sum_max: f64,
    /// Area-weighted mean row sum (1 for a closed enclosure).
    pub row_sum_mean: f64,
    /// `Σ_{i<j} |A_i F_ij − A_j F_ji| / Σ_{i<j} (A_i F_ij + A_j F_ji)/2`.
    pub reciprocity_relative: f64,
    /// `max_{i,j} |A_i F_ij − A_j F_ji| / max_i A_i`.
    pub reciprocity_max: f64,
}

impl std::fmt::Display for Diagnostics {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "row sums {:.6} .. {:.6} (area-weighted mean {:.6}); reciprocity error {:.3e} relative, {:.3e} max",
            self.row_sum_min, self.row_sum_max, self.row_sum_mean, self.reciprocity_relative, self.reciprocity_max
        )
    }
}

impl FormFactors {
    /// A zero matrix, after checking that it fits in memory.
    pub fn zeros(n: usize) -> Result<Self> {
        let bytes = n.checked_mul(n).and_then(|x| x.checked_mul(8));
        match bytes {
            Some(b) if b <= MAX_MATRIX_BYTES => Ok(Self { n, f: vec![0.0; n * n] }),
            _ => Err(RadiosityError::Input(format!(
                "{n} elements need a {n} x {n} form-factor matrix ({:.1} GiB), more than the {} GiB limit; \
                 use a larger --max-element-area or --solver hierarchical, which needs no matrix",
                (n as f64).powi(2) * 8.0 / (1u64 << 30) as f64,
                MAX_MATRIX_BYTES >> 30
            ))),
        }
    }
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.f[i * self.n + j]
    }
    #[inline]
    pub fn row(&self, i: usize) -> &[f64] {
        &self.f[i * self.n..(i + 1) * self.n]
    }
    pub fn row_sums(&self) -> Vec<f64> {
        (0..self.n).map(|i| self.row(i).iter().sum()).collect()
    }

    /// Fills the matrix row by row in parallel; `progress` counts finished rows.
    pub fn compute_rows(
        n: usize,
        progress: Option<&(dyn Fn(usize) + Sync)>,
        row: impl Fn(usize, &mut [f64]) + Sync,
    ) -> Result<Self> {
        let mut m = Self::zeros(n)?;
        let done = AtomicUsize::new(0);
        if n > 0 {
            m.f.par_chunks_mut(n).enumerate().for_each(|(i, r)| {
                row(i, r);
                let d = done.fetch_add(1, Ordering::Relaxed) + 1;
                if let Some(p) = progress {
                    p(d);
                }
            });
        }
        Ok(m)
    }

    pub fn diagnostics(&self, mesh: &Mesh) -> Diagnostics {
        let n = self.n;
        let sums = self.row_sums();
        let area: Vec<f64> = mesh.elements.iter().map(|e| e.area).collect();
        let total: f64 = area.iter().sum();
        let amax = area.iter().copied().fold(0.0, f64::max).max(1e-300);
        let (mut num, mut den, mut mx) = (0.0, 0.0, 0.0f64);
        for i in 0..n {
            for j in i + 1..n {
                let a = area[i] * self.get(i, j);
                let b = area[j] * self.get(j, i);
                num += (a - b).abs();
                den += 0.5 * (a + b);
                mx = mx.max((a - b).abs() / amax);
            }
        }
        Diagnostics {
            row_sum_min: sums.iter().copied().fold(f64::INFINITY, f64::min),
            row_sum_max: sums.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            row_sum_mean: sums.iter().zip(&area).map(|(s, a)| s * a).sum::<f64>()
                / total.max(1e-300),
            reciprocity_relative: if den > 0.0 { num / den } else { 0.0 },
            reciprocity_max: mx,
        }
    }
}

/// The form-factor methods that produce a matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    Analytic,
    Contour,
    Hemisphere,
    Hemicube,
    RayCast,
    MonteCarlo,
}

impl Method {
    pub const ALL: [Method; 6] = [
        Method::Analytic,
        Method::Contour,
        Method::Hemisphere,
        Method::Hemicube,
        Method::RayCast,
        Method::MonteCarlo,
    ];
    pub fn name(self) -> &'static str {
        match self {
            Method::Analytic => "analytic",
            Method::Contour => "contour",
            Method::Hemisphere => "hemisphere",
            Method::Hemicube => "hemicube",
            Method::RayCast => "raycast",
            Method::MonteCarlo => "montecarlo",
        }
    }
    pub fn parse(s: &str) -> Option<Method> {
        Self::ALL.into_iter().find(|m| m.name() == s)
    }
}

/// Parameters shared by the methods (each uses the ones that apply to it).
#[derive(Clone, Copy, Debug)]
pub struct Params {
    /// Hemicube: pixels across the top face.
    pub hemicube_resolution: usize,
    /// Hemisphere: cells across the unit disk of the Nusselt projection.
    pub hemisphere_resolution: usize,
    /// Ray casting: sample points on the source element per receiving vertex.
    pub rays: usize,
    /// Monte Carlo: point pairs per element pair.
    pub samples: usize,
    /// Analytic / contour: rays to points of the other element to estimate visibility
    /// (0: assume every pair sees each other, as in an empty convex room).
    pub visibility_samples: usize,
    /// Analytic: Gauss points per direction over the sending element.
    pub gauss_points: usize,
    pub seed: u64,
}

impl Default for Params {
    fn default() -> Self {
        Self {
            hemicube_resolution: 128,
            hemisphere_resolution: 128,
            rays: 16,
            samples: 16,
            visibility_samples: 4,
            gauss_points: 3,
            seed: 1,
        }
    }
}

/// The interface every matrix method implements.
pub trait FormFactorMethod: Sync {
    fn name(&self) -> &'static str;
    /// The full matrix for the mesh's elements, with occlusion where the method has it.
    fn compute(
        &self,
        mesh: &Mesh,
        progress: Option<&(dyn Fn(usize) + Sync)>,
    ) -> Result<FormFactors>;
}

/// The method object for a method name and parameters.
pub fn method(m: Method, p: Params) -> Box<dyn FormFactorMethod> {
    match m {
        Method::Analytic => Box::new(analytic::polygon::AnalyticPolygon {
            gauss_points: p.gauss_points,
            visibility_samples: p.visibility_samples,
        }),
        Method::Contour => Box::new(contour::Contour {
            visibility_samples: p.visibility_samples,
        }),
        Method::Hemisphere => Box::new(hemisphere::Hemisphere {
            resolution: p.hemisphere_resolution,
        }),
        Method::Hemicube => Box::new(hemicube::Hemicube::new(p.hemicube_resolution)),
        Method::RayCast => Box::new(raycast::RayCast {
            rays: p.rays,
            seed: p.seed,
        }),
        Method::MonteCarlo => Box::new(montecarlo::MonteCarlo {
            samples: p.samples,
            seed: p.seed,
        }),
    }
}
