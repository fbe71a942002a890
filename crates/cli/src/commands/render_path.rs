//! The path tracer's side of `irradia render`: sample, time and error budgets, a
//! progress bar with samples and the error estimate, checkpoints and `--resume`.

use crate::error::CliError;
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use irradia_core::Image;
use irradia_render::path::{self, Film, PathParams, ProgressiveOptions, StopReason};
use irradia_scene::Scene;
use std::io::IsTerminal;
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
}

impl PathArgs {
    /// True when any path-tracer option was given.
    pub fn any(&self) -> bool {
        self.time.is_some()
            || self.target_error.is_some()
            || self.checkpoint.is_some()
            || self.resume.is_some()
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
}

/// What the path tracer did, for the summary line.
pub struct PathSummary {
    pub image: Image,
    pub samples: u32,
    pub paths: u64,
    pub rays: u64,
    pub seconds: f64,
    pub relative_error: f64,
    pub stop: StopReason,
}

/// Path-traces `scene`. `spp_given` tells whether the user fixed the sample count:
/// with only a time or error budget, samples are not capped.
pub fn run(
    scene: &Scene,
    args: &PathArgs,
    spp_given: bool,
    threads: Option<usize>,
    quiet: bool,
) -> Result<PathSummary, CliError> {
    let s = &scene.settings;
    let params = PathParams {
        max_depth: s.max_depth.max(1),
        ..PathParams::default()
    };
    let budget = args.time.is_some() || args.target_error.is_some();
    let spp = if budget && !spp_given {
        u32::MAX
    } else {
        s.spp.max(1)
    };
    let fingerprint = path::progressive::fingerprint(scene, &params);
    let film = match &args.resume {
        Some(p) => {
            Film::load_checkpoint(p, fingerprint).map_err(|e| CliError::Input(e.to_string()))?
        }
        None => Film::new(s.width, s.height).map_err(|e| CliError::Input(e.to_string()))?,
    };
    if film.samples() >= spp && !quiet {
        eprintln!(
            "The checkpoint already holds {} samples per pixel; nothing to add.",
            film.samples()
        );
    }
    let options = ProgressiveOptions {
        spp,
        time_limit: args.time.map(Duration::from_secs_f64),
        target_error: args.target_error,
        checkpoint: args.checkpoint.clone().or_else(|| args.resume.clone()),
        checkpoint_interval: Duration::from_secs(30),
        seed: 0,
    };
    let bar = (!quiet && std::io::stderr().is_terminal()).then(|| {
        let len = if spp == u32::MAX { 0 } else { spp as u64 };
        let pb = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
        let template = if spp == u32::MAX {
            "{spinner} {pos} spp  {msg}  {elapsed_precise}"
        } else {
            "{bar:40} {pos}/{len} spp  {msg}  {elapsed_precise} eta {eta}"
        };
        pb.set_style(
            ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        pb.set_position(film.samples() as u64);
        pb
    });
    let run = || {
        path::render(scene, &params, &options, film, |report, _| {
            if let Some(pb) = &bar {
                pb.set_position(report.samples as u64);
                pb.set_message(format!("error {:.4}", report.relative_error));
            }
        })
    };
    let result = match threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| CliError::Failure(format!("cannot start {n} threads: {e}")))?
            .install(run),
        None => run(),
    }
    .map_err(|e| CliError::Failure(format!("cannot write the checkpoint: {e}")))?;
    if let Some(pb) = bar {
        pb.finish_and_clear();
    }
    let mut image = result.film.image();
    irradia_render::labels::draw_labels(scene, &mut image);
    Ok(PathSummary {
        image,
        samples: result.film.samples(),
        paths: result.counters.paths,
        rays: result.counters.rays + result.counters.shadow_rays,
        seconds: result.elapsed.as_secs_f64(),
        relative_error: result.film.relative_error(),
        stop: result.stop,
    })
}
