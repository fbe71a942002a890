//! The options of one radiosity job, by the names and with the defaults of the
//! `irradia radiosity` command (docs/cli.md), and their translation into a pipeline
//! [`Config`]: the one place where counts are checked and the element size is chosen,
//! shared by the command line and the Python binding (`irradia.radiosity`), so both
//! give the same answer and the same messages for the same options.

use crate::error::{RadiosityError, Result};
use crate::formfactor::{Method, Params};
use crate::mesh::{MeshOptions, PatchSpec};
use crate::pipeline::Config;
use crate::solver::hierarchical::HierarchicalOptions;
use crate::solver::{SolveOptions, SolverKind};

/// Meshing, form factors and solve, as `irradia radiosity --OPTION` names them.
#[derive(Clone, Debug)]
pub struct JobOptions {
    /// `--form-factors`.
    pub form_factors: Method,
    /// `--solver`.
    pub solver: SolverKind,
    /// `--max-element-area`: largest element area, scene units squared.
    pub max_element_area: Option<f64>,
    /// `--elements`: about this many elements when no area is given.
    pub elements: usize,
    /// `--element-limit`.
    pub element_limit: usize,
    pub hemicube_resolution: usize,
    pub hemisphere_resolution: usize,
    /// `--rays`: ray casting's sample points per receiving vertex.
    pub rays: usize,
    /// `--samples`: Monte Carlo point pairs per element pair.
    pub samples: usize,
    pub visibility_samples: usize,
    pub tolerance: f64,
    pub max_iterations: usize,
    pub bf_epsilon: f64,
    pub link_rays: usize,
    /// `--adaptive`: rounds of adaptive subdivision.
    pub adaptive: usize,
    pub seed: u64,
    /// Run every other matrix solver too, for their residual histories (`--convergence`).
    pub compare_solvers: bool,
    /// Keep the form-factor matrix in the report (matrix methods).
    pub keep_form_factors: bool,
}

impl Default for JobOptions {
    /// The command's defaults.
    fn default() -> Self {
        Self {
            form_factors: Method::Hemicube,
            solver: SolverKind::GaussSeidel,
            max_element_area: None,
            elements: 1000,
            element_limit: 2_000_000,
            hemicube_resolution: 128,
            hemisphere_resolution: 64,
            rays: 16,
            samples: 16,
            visibility_samples: 4,
            tolerance: 1e-6,
            max_iterations: 10_000,
            bf_epsilon: 1e-4,
            link_rays: 4,
            adaptive: 0,
            seed: 1,
            compare_solvers: false,
            keep_form_factors: false,
        }
    }
}

impl JobOptions {
    /// Every count and tolerance, before any work (messages name the command's options).
    #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN must fail the checks
    pub fn check(&self) -> Result<()> {
        for (name, v) in [
            ("--hemicube-resolution", self.hemicube_resolution),
            ("--hemisphere-resolution", self.hemisphere_resolution),
            ("--rays", self.rays),
            ("--samples", self.samples),
            ("--elements", self.elements),
        ] {
            if v == 0 {
                return Err(RadiosityError::Input(format!("{name} must be at least 1")));
            }
        }
        if !(self.tolerance > 0.0) || !(self.bf_epsilon > 0.0) {
            return Err(RadiosityError::Input(
                "--tolerance and --bf-epsilon must be positive".into(),
            ));
        }
        Ok(())
    }

    /// The pipeline configuration for the patches `specs` (the element area follows
    /// from `--elements` and the patches' total area unless given).
    #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN must fail the checks
    pub fn config(&self, specs: &[PatchSpec]) -> Result<Config> {
        self.check()?;
        let area = self
            .max_element_area
            .unwrap_or(crate::job::total_area(specs) / self.elements as f64);
        if !(area > 0.0) || !area.is_finite() {
            return Err(RadiosityError::Input(format!(
                "--max-element-area must be a positive number (got {area})"
            )));
        }
        Ok(Config {
            mesh: MeshOptions {
                max_element_area: Some(area),
                max_elements: self.element_limit,
            },
            method: self.form_factors,
            params: Params {
                hemicube_resolution: self.hemicube_resolution,
                hemisphere_resolution: self.hemisphere_resolution,
                rays: self.rays,
                samples: self.samples,
                visibility_samples: self.visibility_samples,
                gauss_points: 3,
                seed: self.seed,
            },
            solver: self.solver,
            solve: SolveOptions {
                tolerance: self.tolerance,
                max_iterations: self.max_iterations,
            },
            hierarchical: HierarchicalOptions {
                bf_epsilon: self.bf_epsilon,
                // --elements N: the leaf area that gives N leaves.
                target_leaves: self.max_element_area.is_none().then_some(self.elements),
                visibility_rays: self.link_rays,
                tolerance: self.tolerance,
                max_iterations: self.max_iterations,
                seed: self.seed,
                ..Default::default()
            },
            compare_solvers: self.compare_solvers && self.solver != SolverKind::Hierarchical,
            adaptive_rounds: self.adaptive,
            keep_form_factors: self.keep_form_factors,
            ..Default::default()
        })
    }
}
