//! Solvers of the radiosity equation `b_i = e_i + ρ_i Σ_j F_ij b_j` (lecture, "Solving
//! the Radiosity Equation"), per RGB channel, one method per file:
//!
//! - `direct`: dense LU with partial pivoting of `I − RF` (the reference for small n);
//! - `jacobi`: `b^{k+1} = e + RF b^k`;
//! - `gauss_seidel`: the same sweep with immediate updates;
//! - `series`: the Neumann series `e + RFe + (RF)²e + …` with its truncation bound;
//! - `southwell`: progressive refinement by shooting the largest unshot energy, with
//!   the ambient term for display (Cohen, Chen, Wallace, Greenberg 1988);
//! - `hierarchical`: Hanrahan, Salzman, Aupperle (1991), links between a hierarchy of
//!   elements refined by the BF criterion, without the n² matrix.
//!
//! Every solver records the residual `max_i |e_i + ρ_i Σ_j F_ij b_j − b_i| / max_i e_i`
//! (largest over channels) after each iteration.

pub mod direct;
pub mod gauss_seidel;
pub mod hierarchical;
pub mod jacobi;
pub mod series;
pub mod southwell;

use crate::error::Result;
use crate::formfactor::FormFactors;
use crate::mesh::Mesh;

/// The linear system of one mesh and form-factor matrix.
pub struct System<'a> {
    pub ff: &'a FormFactors,
    pub rho: Vec<[f64; 3]>,
    pub emission: Vec<[f64; 3]>,
    pub area: Vec<f64>,
}

impl<'a> System<'a> {
    pub fn new(mesh: &Mesh, ff: &'a FormFactors) -> Self {
        Self {
            ff,
            rho: (0..mesh.len()).map(|i| mesh.reflectance(i)).collect(),
            emission: (0..mesh.len()).map(|i| mesh.emission(i)).collect(),
            area: mesh.elements.iter().map(|e| e.area).collect(),
        }
    }
    pub fn n(&self) -> usize {
        self.ff.n
    }
    /// Largest emission over elements and channels (the residual's scale).
    pub fn emission_scale(&self) -> f64 {
        self.emission
            .iter()
            .flat_map(|e| e.iter().copied())
            .fold(0.0, f64::max)
            .max(1e-300)
    }
    /// `(RF b)_i` for all i and channels.
    pub fn gather(&self, b: &[[f64; 3]]) -> Vec<[f64; 3]> {
        use rayon::prelude::*;
        (0..self.n())
            .into_par_iter()
            .map(|i| {
                let row = self.ff.row(i);
                let mut s = [0.0; 3];
                for (f, bj) in row.iter().zip(b) {
                    s[0] += f * bj[0];
                    s[1] += f * bj[1];
                    s[2] += f * bj[2];
                }
                [
                    self.rho[i][0] * s[0],
                    self.rho[i][1] * s[1],
                    self.rho[i][2] * s[2],
                ]
            })
            .collect()
    }
    /// The relative residual of `b`.
    pub fn residual(&self, b: &[[f64; 3]]) -> f64 {
        let g = self.gather(b);
        let mut r: f64 = 0.0;
        for i in 0..self.n() {
            for c in 0..3 {
                r = r.max((self.emission[i][c] + g[i][c] - b[i][c]).abs());
            }
        }
        r / self.emission_scale()
    }
}

/// Stopping rule shared by the iterative solvers.
#[derive(Clone, Copy, Debug)]
pub struct SolveOptions {
    /// Stop when the relative residual is below this.
    pub tolerance: f64,
    pub max_iterations: usize,
}

impl Default for SolveOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-6,
            max_iterations: 10_000,
        }
    }
}

/// A solution and how it was reached.
#[derive(Clone, Debug, Default)]
pub struct Solution {
    /// Radiosity per element and channel.
    pub b: Vec<[f64; 3]>,
    /// Relative residual after each iteration (sweep, term or shot).
    pub history: Vec<f64>,
    /// Final relative residual.
    pub residual: f64,
    /// Radiosity to display, where it differs from `b` (Southwell's ambient term).
    pub display: Option<Vec<[f64; 3]>>,
    /// Extra facts for the report (series truncation bound, link counts, ...).
    pub notes: Vec<String>,
}

/// The interface of the matrix solvers.
pub trait Solver {
    fn name(&self) -> &'static str;
    fn solve(&self, sys: &System, opts: &SolveOptions) -> Result<Solution>;
}

/// The solvers by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SolverKind {
    Direct,
    Jacobi,
    GaussSeidel,
    Series,
    Southwell,
    Hierarchical,
}

impl SolverKind {
    pub const ALL: [SolverKind; 6] = [
        SolverKind::Direct,
        SolverKind::Jacobi,
        SolverKind::GaussSeidel,
        SolverKind::Series,
        SolverKind::Southwell,
        SolverKind::Hierarchical,
    ];
    pub fn name(self) -> &'static str {
        match self {
            SolverKind::Direct => "direct",
            SolverKind::Jacobi => "jacobi",
            SolverKind::GaussSeidel => "gauss-seidel",
            SolverKind::Series => "series",
            SolverKind::Southwell => "southwell",
            SolverKind::Hierarchical => "hierarchical",
        }
    }
    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == s)
    }
    /// The matrix solver (None for hierarchical, which builds no matrix).
    pub fn matrix_solver(self) -> Option<Box<dyn Solver>> {
        Some(match self {
            SolverKind::Direct => Box::new(direct::Direct),
            SolverKind::Jacobi => Box::new(jacobi::Jacobi),
            SolverKind::GaussSeidel => Box::new(gauss_seidel::GaussSeidel),
            SolverKind::Series => Box::new(series::Series),
            SolverKind::Southwell => Box::new(southwell::Southwell),
            SolverKind::Hierarchical => return None,
        })
    }
}

/// Warns (as a message) when reflectance times row sum reaches 1 somewhere: the
/// iterative solvers would not converge.
pub fn check_convergence(sys: &System) -> Result<f64> {
    let mut q: f64 = 0.0;
    for i in 0..sys.n() {
        let s: f64 = sys.ff.row(i).iter().sum();
        for c in 0..3 {
            q = q.max(sys.rho[i][c] * s);
        }
    }
    if q >= 1.0 {
        return Err(crate::error::RadiosityError::Input(format!(
            "reflectance times form-factor row sum reaches {q:.4} (>= 1): the iteration would not converge; \
             lower the reflectances or use form factors whose rows sum to at most 1"
        )));
    }
    Ok(q)
}
