//! The path tracer's options of `irradia render`: sample, time and error budgets,
//! checkpoints and `--resume` (the driver in `irradia_render` runs them).

use crate::error::CliError;
use clap::Args;
use irradia_render::RenderOptions;
use std::path::PathBuf;
use std::time::Duration;

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
    /// are independent estimates of the same image; 0 (the default) is the usual image.
    #[arg(long, value_name = "N")]
    pub seed: Option<u32>,
}

impl PathArgs {
    /// True when any path-tracer option was given.
    pub fn any(&self) -> bool {
        self.time.is_some()
            || self.target_error.is_some()
            || self.checkpoint.is_some()
            || self.resume.is_some()
            || self.seed.is_some()
    }

    /// Checks the values before any work starts.
    pub fn validate(&self) -> Result<(), CliError> {
        if let Some(t) = self.time {
            if !(t.is_finite() && t > 0.0) {
                return Err(CliError::Input(format!(
                    "--time: must be a positive number of seconds (got {t})"
                )));
            }
        }
        if let Some(e) = self.target_error {
            if !(e.is_finite() && e > 0.0) {
                return Err(CliError::Input(format!(
                    "--target-error: must be a positive number (got {e})"
                )));
            }
        }
        if let Some(r) = &self.resume {
            if !r.is_file() {
                return Err(CliError::Input(format!(
                    "--resume: {}: no such checkpoint file",
                    r.display()
                )));
            }
        }
        Ok(())
    }

    /// Sets the budgets, checkpoint and resume file in `options`. `spp_given` tells
    /// whether the user fixed the sample count: with only a time or error budget,
    /// samples are not capped.
    pub fn apply(&self, options: &mut RenderOptions, spp_given: bool) {
        let budget = self.time.is_some() || self.target_error.is_some();
        if budget && !spp_given {
            options.spp = Some(u32::MAX);
        }
        options.time_limit = self.time.map(Duration::from_secs_f64);
        options.target_error = self.target_error;
        options.checkpoint = self.checkpoint.clone();
        options.resume = self.resume.clone();
        options.seed = self.seed.unwrap_or(0);
        options.checkpoint_interval = Duration::from_secs(30);
    }
}
