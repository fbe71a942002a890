//! Direct solution of `(I − RF) b = e` by dense LU factorisation with partial pivoting
//! (lecture, "Matrix Form": the formal solution `b = [I − RF]^{-1} e`), once per channel.
//! O(n³): the reference for small meshes.

use super::{Solution, SolveOptions, Solver, System};
use crate::error::{RadiosityError, Result};

pub struct Direct;

/// Largest system the direct solver takes.
pub const MAX_DIRECT: usize = 6000;

impl Solver for Direct {
    fn name(&self) -> &'static str {
        "direct"
    }
    fn solve(&self, sys: &System, _opts: &SolveOptions) -> Result<Solution> {
        let n = sys.n();
        if n > MAX_DIRECT {
            return Err(RadiosityError::Input(format!(
                "{n} elements is too many for the direct solver (O(n³), at most {MAX_DIRECT}); \
                 use --solver gauss-seidel, southwell or hierarchical"
            )));
        }
        let mut b = vec![[0.0; 3]; n];
        let mut a = vec![0.0; n * n];
        for c in 0..3 {
            for i in 0..n {
                let row = sys.ff.row(i);
                for j in 0..n {
                    a[i * n + j] = -sys.rho[i][c] * row[j];
                }
                a[i * n + i] += 1.0;
            }
            let x = lu_solve(&mut a, n, (0..n).map(|i| sys.emission[i][c]).collect()).ok_or_else(
                || {
                    RadiosityError::Input(
                        "I − RF is singular: a reflectance is 1 in a closed room".into(),
                    )
                },
            )?;
            for (bi, xi) in b.iter_mut().zip(x) {
                bi[c] = xi;
            }
        }
        let residual = sys.residual(&b);
        Ok(Solution {
            b,
            history: vec![residual],
            residual,
            ..Default::default()
        })
    }
}

/// Solves `A x = rhs` in place (A is destroyed). None if singular.
pub fn lu_solve(a: &mut [f64], n: usize, mut rhs: Vec<f64>) -> Option<Vec<f64>> {
    for k in 0..n {
        let mut p = k;
        let mut best = a[k * n + k].abs();
        for i in k + 1..n {
            let v = a[i * n + k].abs();
            if v > best {
                best = v;
                p = i;
            }
        }
        if best < 1e-300 {
            return None;
        }
        if p != k {
            for j in 0..n {
                a.swap(k * n + j, p * n + j);
            }
            rhs.swap(k, p);
        }
        let pivot = a[k * n + k];
        let (top, rest) = a.split_at_mut((k + 1) * n);
        let krow = &top[k * n..k * n + n];
        use rayon::prelude::*;
        let rk = rhs[k];
        let updates: Vec<f64> = rest
            .par_chunks_mut(n)
            .map(|row| {
                let m = row[k] / pivot;
                if m != 0.0 {
                    for j in k..n {
                        row[j] -= m * krow[j];
                    }
                }
                m
            })
            .collect();
        for (i, m) in updates.into_iter().enumerate() {
            rhs[k + 1 + i] -= m * rk;
        }
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        let mut s = rhs[i];
        for j in i + 1..n {
            s -= a[i * n + j] * x[j];
        }
        x[i] = s / a[i * n + i];
    }
    Some(x)
}
