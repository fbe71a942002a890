//! The path tracer's options of `irradia render`: sample, time and error budgets,
//! checkpoints and `--resume` (the driver in `irradia_render` runs them).

use crate::error::CliError;
use clap::Args;
use irradia_render::{Budget, RenderOptions};
use std::path::PathBuf;

/// Options of the path tracer (used when the scene's integrator is `path`).
#[derive(Args, Debug, Clone, Default)]
#[command(next_help_heading = "Path tracing (integrator = path)")]
pub struct PathArgs {
    /// Stop after about this many seconds (at the end of the pass that crosses it).
    #[arg(long, value_name = "SECONDS")]
    pub time: Option<f64>,
    /// Stop when the image's relative error estimate falls to E (e.g. 0.01).
    #[arg(long, value_name = "E")]
    pub target_error: Option<f64>,
    /// Write the film to FILE every 30 seconds and at the end, for --resume.
    #[arg(long, value_name = "FILE")]
    pub checkpoint: Option<PathBuf>,
    /// Continue an interrupted render from its checkpoint (and keep writing it).
    #[arg(long, value_name = "FILE")]
    pub resume: Option<PathBuf>,
    /// Random stream family (Mitsuba's sampler `seed`): renders with different seeds
    /// are independent estimates of the same image; overrides the scene's `seed` (0 unless set).
    #[arg(long, value_name = "N")]
    pub seed: Option<u32>,
}

impl PathArgs {
    /// The options as the render library's [`Budget`], which checks and applies them.
    pub fn budget(&self) -> Budget {
        Budget {
            time: self.time,
            target_error: self.target_error,
            checkpoint: self.checkpoint.clone(),
            resume: self.resume.clone(),
            seed: self.seed,
        }
    }

    /// Checks the values before any work starts (`path_traced`: the scene's integrator
    /// is the path tracer, which the options belong to).
    pub fn validate(&self, path_traced: bool) -> Result<(), CliError> {
        self.budget().validate(path_traced).map_err(CliError::Input)
    }

    /// Sets the budgets, checkpoint and resume file in `options`.
    pub fn apply(&self, options: &mut RenderOptions, spp_given: bool) {
        self.budget().apply(options, spp_given)
    }
}
