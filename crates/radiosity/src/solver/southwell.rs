//! Progressive refinement by shooting (Southwell iteration; Cohen, Chen, Wallace,
//! Greenberg 1988, "A progressive refinement approach to fast radiosity image
//! generation"). Each step takes the element with the most unshot power `ΔB_i A_i` and
//! distributes it: `b_j += ρ_j F_ji ΔB_i`, `ΔB_j += ρ_j F_ji ΔB_i`. The unshot
//! radiosity is exactly the residual of the current solution.
//!
//! The ambient term for display: `ambient = R Σ_i ΔB_i A_i / Σ_i A_i` with the
//! inter-reflection factor `R = 1 / (1 − ρ_avg)` (area-weighted mean reflectance);
//! each element shows `b_i + ρ_i ambient`. It assumes a closed room (form-factor rows
//! summing to 1); a warning is added to the notes when they do not.

use super::{check_convergence, Solution, SolveOptions, Solver, System};
use crate::error::Result;

pub struct Southwell;

impl Solver for Southwell {
    fn name(&self) -> &'static str {
        "southwell"
    }
    fn solve(&self, sys: &System, opts: &SolveOptions) -> Result<Solution> {
        check_convergence(sys)?;
        let n = sys.n();
        let scale = sys.emission_scale();
        let mut b = sys.emission.clone();
        let mut unshot = sys.emission.clone();
        let mut history = Vec::new();
        let max_shots = opts.max_iterations.max(1).saturating_mul(n.max(1));
        let mut residual = 1.0;
        for _ in 0..max_shots {
            let (mut best, mut bi) = (-1.0, 0);
            for (i, (u, area)) in unshot.iter().zip(&sys.area).enumerate() {
                let p = (u[0] + u[1] + u[2]) * area;
                if p > best {
                    best = p;
                    bi = i;
                }
            }
            let shoot = unshot[bi];
            unshot[bi] = [0.0; 3];
            for j in 0..n {
                let f = sys.ff.get(j, bi);
                if f == 0.0 {
                    continue;
                }
                for c in 0..3 {
                    let d = sys.rho[j][c] * f * shoot[c];
                    b[j][c] += d;
                    unshot[j][c] += d;
                }
            }
            residual = unshot
                .iter()
                .flat_map(|u| u.iter().copied())
                .fold(0.0, f64::max)
                / scale;
            history.push(residual);
            if residual < opts.tolerance {
                break;
            }
        }
        // Ambient term for display.
        let total_area: f64 = sys.area.iter().sum();
        let mut rho_avg = [0.0; 3];
        let mut unshot_avg = [0.0; 3];
        for ((rho, u), area) in sys.rho.iter().zip(&unshot).zip(&sys.area) {
            for c in 0..3 {
                rho_avg[c] += rho[c] * area / total_area;
                unshot_avg[c] += u[c] * area / total_area;
            }
        }
        let ambient: [f64; 3] = std::array::from_fn(|c| unshot_avg[c] / (1.0 - rho_avg[c]));
        let display = (0..n)
            .map(|i| std::array::from_fn(|c| b[i][c] + sys.rho[i][c] * ambient[c]))
            .collect();
        let mut notes = vec![format!(
            "southwell: {} shots; ambient term ({:.4e}, {:.4e}, {:.4e})",
            history.len(),
            ambient[0],
            ambient[1],
            ambient[2]
        )];
        let mean_row: f64 = (0..n)
            .map(|i| sys.ff.row(i).iter().sum::<f64>() * sys.area[i])
            .sum::<f64>()
            / total_area;
        if mean_row < 0.99 {
            notes.push(format!(
                "warning: the enclosure is not closed (form-factor rows sum to {mean_row:.3} on average); the \
                 ambient term assumes a closed room and overestimates the light; close the scene or ignore \
                 the ambient term (it only affects the display of an unconverged solution)"
            ));
        }
        Ok(Solution {
            b,
            history,
            residual,
            display: Some(display),
            notes,
        })
    }
}
