//! The path tracer's budget of one render (samples, time, target error), its
//! checkpoint and resume files and its seed, as the command line's `--time`,
//! `--target-error`, `--checkpoint`, `--resume` and `--seed` give them (docs/cli.md):
//! checked and put into [`RenderOptions`] in one place, shared by `irradia render` and
//! the Python binding's `Scene.render`.

use crate::RenderOptions;
use std::path::PathBuf;
use std::time::Duration;

/// The path tracer's options of a render; `None` leaves each at its default.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Budget {
    /// Stop after about this many seconds (at the end of the pass that crosses it).
    pub time: Option<f64>,
    /// Stop when the image's relative error estimate falls to this value.
    pub target_error: Option<f64>,
    /// Write the film here every 30 seconds and at the end.
    pub checkpoint: Option<PathBuf>,
    /// Continue the render saved in this checkpoint.
    pub resume: Option<PathBuf>,
    /// Random stream family instead of the scene's `seed` (0 unless the scene sets one).
    pub seed: Option<u32>,
}

impl Budget {
    /// True when any option was given.
    pub fn any(&self) -> bool {
        self.time.is_some()
            || self.target_error.is_some()
            || self.checkpoint.is_some()
            || self.resume.is_some()
            || self.seed.is_some()
    }

    /// Checks the values before any work starts; `path_traced` tells whether the
    /// scene's integrator is a Monte Carlo one (the options belong to it).
    pub fn validate(&self, path_traced: bool) -> Result<(), String> {
        if let Some(t) = self.time {
            if !(t.is_finite() && t > 0.0) {
                return Err(format!(
                    "--time: must be a positive number of seconds (got {t})"
                ));
            }
        }
        if let Some(e) = self.target_error {
            if !(e.is_finite() && e > 0.0) {
                return Err(format!(
                    "--target-error: must be a positive number (got {e})"
                ));
            }
        }
        if let Some(r) = &self.resume {
            if !r.is_file() {
                return Err(format!(
                    "--resume: {}: no such checkpoint file",
                    r.display()
                ));
            }
        }
        if !path_traced && self.any() {
            return Err("--time, --target-error, --checkpoint, --resume and --seed belong to the path tracer: add --integrator path".into());
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
        options.seed = self.seed;
        options.checkpoint_interval = Duration::from_secs(30);
    }
}
