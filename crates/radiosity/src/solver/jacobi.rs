//! Jacobi iteration (lecture, "Jacobi's method"): `b^{k+1} = e + RF b^k`, starting from
//! `b^0 = e`. Its residual is the change `b^{k+1} − b^k`, so it costs nothing extra.

use super::{check_convergence, Solution, SolveOptions, Solver, System};
use crate::error::Result;

pub struct Jacobi;

impl Solver for Jacobi {
    fn name(&self) -> &'static str {
        "jacobi"
    }
    fn solve(&self, sys: &System, opts: &SolveOptions) -> Result<Solution> {
        check_convergence(sys)?;
        let n = sys.n();
        let scale = sys.emission_scale();
        let mut b = sys.emission.clone();
        let mut history = Vec::new();
        let mut residual = f64::INFINITY;
        for _ in 0..opts.max_iterations {
            let g = sys.gather(&b);
            let mut r: f64 = 0.0;
            for i in 0..n {
                for c in 0..3 {
                    let nb = sys.emission[i][c] + g[i][c];
                    r = r.max((nb - b[i][c]).abs());
                    b[i][c] = nb;
                }
            }
            // r is the residual of the previous iterate (the change it made).
            residual = r / scale;
            history.push(residual);
            if residual < opts.tolerance {
                break;
            }
        }
        if residual.is_finite() {
            residual = sys.residual(&b);
        }
        Ok(Solution {
            b,
            history,
            residual,
            ..Default::default()
        })
    }
}
