//! The series (Neumann) expansion (lecture, "Series Approximation"):
//! `b = e + RFe + (RF)²e + …`, summed until the next term is below the tolerance.
//!
//! Truncation bound: with `q = ‖RF‖_∞ = max_i ρ_i Σ_j F_ij < 1`, the terms after the
//! K-th sum to at most `‖(RF)^{K+1} e‖_∞ / (1 − q)`. The residual of the partial sum
//! `S_K` is exactly the next term `(RF)^{K+1} e`.

use super::{check_convergence, Solution, SolveOptions, Solver, System};
use crate::error::Result;

pub struct Series;

impl Solver for Series {
    fn name(&self) -> &'static str {
        "series"
    }
    fn solve(&self, sys: &System, opts: &SolveOptions) -> Result<Solution> {
        let q = check_convergence(sys)?;
        let n = sys.n();
        let scale = sys.emission_scale();
        let mut sum = sys.emission.clone();
        let mut term = sys.emission.clone();
        let mut history = Vec::new();
        let mut next_norm = f64::INFINITY;
        let mut terms = 1;
        for _ in 0..opts.max_iterations {
            term = sys.gather(&term);
            next_norm = term
                .iter()
                .flat_map(|t| t.iter().map(|v| v.abs()))
                .fold(0.0, f64::max);
            history.push(next_norm / scale);
            if next_norm / scale < opts.tolerance {
                break;
            }
            for i in 0..n {
                for c in 0..3 {
                    sum[i][c] += term[i][c];
                }
            }
            terms += 1;
        }
        let bound = next_norm / (1.0 - q);
        let residual = next_norm / scale;
        Ok(Solution {
            b: sum,
            history,
            residual,
            display: None,
            notes: vec![format!(
                "series: {terms} terms; ‖RF‖∞ = {q:.4}; truncation bound on the omitted terms {bound:.3e} \
                 ({:.3e} relative to the largest emission)",
                bound / scale
            )],
        })
    }
}

/// The truncation bound `‖(RF)^{K+1} e‖ / (1 − q)` for a given next-term norm.
pub fn truncation_bound(next_term_norm: f64, q: f64) -> f64 {
    next_term_norm / (1.0 - q)
}
