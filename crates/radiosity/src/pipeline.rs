//! The whole radiosity job, as `irradia radiosity` runs it: meshing, form factors, solve,
//! display, with the time of each phase and the final residual.

use crate::error::{RadiosityError, Result};
use crate::formfactor::{self, Diagnostics, FormFactors, Method, Params};
use crate::mesh::weld::DisplayMesh;
use crate::mesh::{Mesh, MeshOptions, PatchSpec};
use crate::solver::hierarchical::{self, HierarchicalOptions, HierarchicalResult};
use crate::solver::{Solution, SolveOptions, SolverKind, System};
use std::time::{Duration, Instant};

/// Progress callbacks (the CLI draws them as a bar; tests ignore them).
pub trait Progress: Sync {
    /// A new phase with `total` steps (0: unknown).
    fn phase(&self, name: &str, total: u64);
    /// Steps done in the current phase.
    fn set(&self, done: u64);
}

pub struct NoProgress;
impl Progress for NoProgress {
    fn phase(&self, _: &str, _: u64) {}
    fn set(&self, _: u64) {}
}

/// What to compute.
#[derive(Clone, Debug)]
pub struct Config {
    pub mesh: MeshOptions,
    pub method: Method,
    pub params: Params,
    pub solver: SolverKind,
    pub solve: SolveOptions,
    pub hierarchical: HierarchicalOptions,
    /// Also run every other matrix solver on the same matrix (for the convergence
    /// chart); only the chosen solver's answer is returned.
    pub compare_solvers: bool,
    /// Rounds of adaptive subdivision after the first solve (matrix solvers).
    pub adaptive_rounds: usize,
    /// Relative radiosity jump that makes an element split in adaptive subdivision.
    pub adaptive_tolerance: f64,
    /// Keep the final form-factor matrix in [`Report::form_factors`] (matrix solvers).
    pub keep_form_factors: bool,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            mesh: MeshOptions::default(),
            method: Method::Hemicube,
            params: Params::default(),
            solver: SolverKind::GaussSeidel,
            solve: SolveOptions::default(),
            hierarchical: HierarchicalOptions::default(),
            compare_solvers: false,
            adaptive_rounds: 0,
            adaptive_tolerance: 0.05,
            keep_form_factors: false,
        }
    }
}

/// What came out.
pub struct Report {
    /// The final elements (adaptive or hierarchical leaves included).
    pub mesh: Mesh,
    pub solution: Solution,
    /// Row sums and reciprocity of the form factors (matrix methods).
    pub diagnostics: Option<Diagnostics>,
    /// (phase, wall time), in order.
    pub timings: Vec<(String, Duration)>,
    /// (solver, residual per iteration) for every solver that ran.
    pub histories: Vec<(String, Vec<f64>)>,
    pub notes: Vec<String>,
    /// The final form-factor matrix, when [`Config::keep_form_factors`] asked for it
    /// (none for the hierarchical solver, which has no matrix).
    pub form_factors: Option<FormFactors>,
}

impl Report {
    /// Radiosity to show (Southwell's ambient term included).
    pub fn display_radiosity(&self) -> &[[f64; 3]] {
        self.solution.display.as_deref().unwrap_or(&self.solution.b)
    }
    pub fn display_mesh(&self) -> DisplayMesh {
        crate::display::display_mesh(
            &self.mesh.elements,
            self.display_radiosity(),
            self.mesh.scale(),
        )
    }
    /// Area-weighted mean radiosity of each input polygon (by `PatchSpec` index).
    pub fn surface_means(&self, specs: usize) -> Vec<[f64; 3]> {
        let mut sum = vec![[0.0; 3]; specs];
        let mut area = vec![0.0; specs];
        for (e, b) in self.mesh.elements.iter().zip(&self.solution.b) {
            let s = self.mesh.patches[e.patch as usize].source as usize;
            for c in 0..3 {
                sum[s][c] += e.area * b[c];
            }
            area[s] += e.area;
        }
        sum.iter()
            .zip(&area)
            .map(|(s, a)| std::array::from_fn(|c| s[c] / a.max(1e-300)))
            .collect()
    }
}

/// Meshing, then the hierarchical solve by `solve` (the one-process solver, or a
/// distributed one whose ranks other than 0 return `None`): the report of
/// `irradia radiosity --solver hierarchical`, `None` where `solve` gave none.
pub fn run_hierarchical(
    specs: &[PatchSpec],
    cfg: &Config,
    progress: &dyn Progress,
    solve: impl FnOnce(&Mesh, HierarchicalOptions) -> Result<Option<HierarchicalResult>>,
) -> Result<Option<Report>> {
    let t = Instant::now();
    progress.phase("meshing", 0);
    // The hierarchy cuts the patches itself: no elements below them (at 1,000,000
    // elements they took 0.4 s and 150 MB for nothing).
    if let Some(a) = cfg.mesh.max_element_area {
        if a.is_nan() || a <= 0.0 {
            return Err(RadiosityError::Input(format!(
                "--max-element-area must be positive (got {a})"
            )));
        }
    }
    let patches_only = MeshOptions {
        max_element_area: None,
        ..cfg.mesh
    };
    let mesh = Mesh::build(specs, patches_only)?;
    let timings = vec![("meshing".to_string(), t.elapsed())];
    hierarchical_report(mesh, timings, cfg, progress, solve)
}

fn hierarchical_report(
    mesh: Mesh,
    mut timings: Vec<(String, Duration)>,
    cfg: &Config,
    progress: &dyn Progress,
    solve: impl FnOnce(&Mesh, HierarchicalOptions) -> Result<Option<HierarchicalResult>>,
) -> Result<Option<Report>> {
    let mut h = cfg.hierarchical;
    if let Some(a) = cfg.mesh.max_element_area {
        h.max_element_area = a;
    }
    h.max_elements = cfg.mesh.max_elements;
    let t = Instant::now();
    progress.phase("hierarchical radiosity (links, form factors, solve)", 0);
    let Some(r) = solve(&mesh, h)? else {
        return Ok(None);
    };
    let total = t.elapsed();
    timings.push((
        "hierarchical: links (oracle, form factors, shadow rays)".to_string(),
        r.link_time,
    ));
    timings.push(("hierarchical: gather + push-pull".to_string(), r.solve_time));
    timings.push((
        "hierarchical: tree and leaves".to_string(),
        total.saturating_sub(r.link_time + r.solve_time),
    ));
    let notes = r.solution.notes.clone();
    let hist = r.solution.history.clone();
    Ok(Some(Report {
        mesh: r.mesh,
        solution: r.solution,
        diagnostics: None,
        timings,
        histories: vec![("hierarchical".into(), hist)],
        notes,
        form_factors: None,
    }))
}

/// Runs meshing, form factors and the solve.
pub fn run(specs: &[PatchSpec], cfg: &Config, progress: &dyn Progress) -> Result<Report> {
    if cfg.solver == SolverKind::Hierarchical {
        let solve =
            |mesh: &Mesh, h: HierarchicalOptions| hierarchical::solve(mesh, h, None).map(Some);
        let report = run_hierarchical(specs, cfg, progress, solve)?;
        return Ok(report.expect("the one-process solve has a result"));
    }
    let mut timings = Vec::new();
    let mut notes = Vec::new();
    let t = Instant::now();
    progress.phase("meshing", 0);
    let mut mesh = Mesh::build(specs, cfg.mesh)?;
    timings.push(("meshing".to_string(), t.elapsed()));

    let method = formfactor::method(cfg.method, cfg.params);
    let mut round = 0;
    loop {
        let t = Instant::now();
        let n = mesh.len();
        progress.phase(
            &format!("form factors ({}, {} elements)", method.name(), n),
            n as u64,
        );
        let cb = |d: usize| progress.set(d as u64);
        let ff = method.compute(&mesh, Some(&cb))?;
        timings.push((format!("form factors ({})", method.name()), t.elapsed()));
        let t = Instant::now();
        let diag = ff.diagnostics(&mesh);
        timings.push(("form-factor diagnostics".to_string(), t.elapsed()));
        let sys = System::new(&mesh, &ff);
        let t = Instant::now();
        progress.phase(&format!("solve ({})", cfg.solver.name()), 0);
        let solver = cfg.solver.matrix_solver().expect("matrix solver");
        let solution = solver.solve(&sys, &cfg.solve)?;
        timings.push((format!("solve ({})", cfg.solver.name()), t.elapsed()));
        let mut histories = vec![(cfg.solver.name().to_string(), solution.history.clone())];
        if cfg.compare_solvers {
            for k in SolverKind::ALL {
                if k == cfg.solver
                    || k == SolverKind::Hierarchical
                    || (k == SolverKind::Direct && n > 3000)
                {
                    continue;
                }
                let t = Instant::now();
                let s = k.matrix_solver().unwrap().solve(&sys, &cfg.solve)?;
                timings.push((format!("solve ({}, for comparison)", k.name()), t.elapsed()));
                histories.push((k.name().to_string(), s.history));
            }
        }
        if round < cfg.adaptive_rounds {
            let t = Instant::now();
            // Elements may shrink to 1/64 of the requested size (three splits).
            let min_area = cfg.mesh.max_element_area.unwrap_or(mesh.total_area()) / 64.0;
            let (refined, split) =
                crate::mesh::adaptive::refine(&mesh, &solution.b, cfg.adaptive_tolerance, min_area);
            timings.push(("adaptive subdivision".to_string(), t.elapsed()));
            notes.push(format!(
                "adaptive round {}: split {split} of {} elements",
                round + 1,
                mesh.len()
            ));
            round += 1;
            if split > 0 && refined.len() <= cfg.mesh.max_elements {
                mesh = refined;
                continue;
            }
        }
        notes.extend(solution.notes.iter().cloned());
        return Ok(Report {
            mesh,
            solution,
            diagnostics: Some(diag),
            timings,
            histories,
            notes,
            form_factors: cfg.keep_form_factors.then_some(ff),
        });
    }
}
