//! `irradia render`: render a scene file or a built-in scene to PNG, EXR or PFM.

use crate::error::CliError;
use crate::progress::PassStatus;
use crate::scene_arg::{load_scene, SceneArgs};
use clap::{Args, ValueEnum};
use irradia_core::io::{save, Format};
use irradia_render::{Aov, Progress, ProgressFn, RenderOptions};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;

const EXAMPLES: &str = "\
Examples:
  irradia render                                  # built-in 'default' -> render.png
  irradia render --builtin whitted -o whitted.png --threads 2
  irradia render scene.toml -o out.exr --spp 16   # linear float output
  irradia render --builtin csg --width 320 --height 180 --max-depth 3 --quiet
  irradia render --builtin whitted --aov depth,normal -o w.png
      # also writes w.depth.png and w.normal.png (raw values in .exr/.pfm)
  irradia render --builtin cornell --comm local --ranks 2 --threads 1 -o c.png
  mpirun -np 4 irradia render --builtin cornell --comm mpi -o c.png
      # one image on 2 (4) ranks, equal to the one-process render bit for bit

The format is chosen by the output's extension: .png (8-bit sRGB), .exr or .pfm
(linear float). The file is written atomically: a failed render never leaves a
partial image, and an existing file is only replaced by a complete one.
Exit codes: 0 done, 1 failure while working, 2 bad input (scene file, option).";

/// Extra images (`--aov`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum AovArg {
    /// Distance from the camera to the first hit.
    Depth,
    /// World-space shading normal at the first hit.
    Normal,
    /// Index of the first object hit (-1 for the background).
    ObjectId,
    /// Deepest level of the pixel's ray tree.
    RayDepth,
}

impl From<AovArg> for Aov {
    fn from(a: AovArg) -> Aov {
        match a {
            AovArg::Depth => Aov::Depth,
            AovArg::Normal => Aov::Normal,
            AovArg::ObjectId => Aov::ObjectId,
            AovArg::RayDepth => Aov::RayDepth,
        }
    }
}

#[derive(Args, Debug)]
#[command(after_long_help = EXAMPLES)]
pub struct RenderArgs {
    /// Scene file (TOML or JSON). Without it (and without --builtin) the built-in
    /// `default` scene is rendered.
    #[arg(value_name = "SCENE")]
    pub scene: Option<PathBuf>,
    /// Output image; .png, .exr or .pfm.
    #[arg(short, long, value_name = "FILE", default_value = "render.png")]
    pub output: PathBuf,
    #[command(flatten)]
    pub scene_args: SceneArgs,
    /// Worker threads (default: one per core). The image does not depend on it.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// Tile size in pixels (the image does not depend on it).
    #[arg(long, value_name = "PIXELS", default_value_t = 32,
          value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub tile_size: u32,
    /// Also write these images beside the output, as FILE-STEM.NAME.EXT
    /// (comma-separated or repeated).
    #[arg(long, value_name = "AOV", value_delimiter = ',')]
    pub aov: Vec<AovArg>,
    #[command(flatten)]
    pub path: super::render_path::PathArgs,
    #[command(flatten)]
    pub comm: super::render_comm::CommArgs,
    /// Print nothing but errors and the importer's warnings (no progress bar, no
    /// statistics, no notes of what the importer added).
    #[arg(short, long, help_heading = "General options")]
    pub quiet: bool,
}

/// `out.png` + `depth` -> `out.depth.png`.
pub fn aov_path(output: &Path, aov: Aov) -> PathBuf {
    let stem = output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "render".into());
    let ext = output
        .extension()
        .map(|e| e.to_string_lossy().into_owned())
        .unwrap_or_default();
    output.with_file_name(format!("{stem}.{}.{ext}", aov.name()))
}

/// Checks, before rendering, that `path` has a known image extension and that its
/// folder exists and takes new files.
pub fn check_output(path: &Path) -> Result<Format, CliError> {
    let format = Format::from_path(path).map_err(|e| CliError::Input(e.to_string()))?;
    if path.is_dir() {
        return Err(CliError::Input(format!(
            "{}: is a folder, not an image file",
            path.display()
        )));
    }
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if !dir.is_dir() {
        return Err(CliError::Input(format!(
            "{}: cannot write the output: folder {} does not exist",
            path.display(),
            dir.display()
        )));
    }
    // Probe that the folder takes files (the image itself is written atomically later).
    let probe = dir.join(format!(".irradia-probe-{}", std::process::id()));
    match std::fs::File::create(&probe) {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(format)
        }
        Err(e) => Err(CliError::Input(format!(
            "{}: cannot write the output in {}: {e}",
            path.display(),
            dir.display()
        ))),
    }
}

pub fn run(mut args: RenderArgs) -> Result<(), CliError> {
    // Everything that can be wrong with the options is found before rendering.
    let format = check_output(&args.output)?;
    let ranks = args.comm.start(args.threads)?;
    // Under MPI only rank 0 reports and writes.
    args.quiet |= ranks.rank() != 0;
    let aovs: Vec<Aov> = args.aov.iter().map(|&a| a.into()).collect();
    args.path.validate(true)?;
    let scene = load_scene(args.scene.as_ref(), &args.scene_args, args.quiet)?;
    let path_traced = scene.settings.integrator.is_monte_carlo();
    args.path.validate(path_traced)?;
    scene.settings.check_crop().map_err(CliError::Input)?;

    let reporter = Arc::new(crate::progress::Progress::new("render", args.quiet));
    reporter.phase(
        if path_traced {
            "path tracing"
        } else {
            "ray tracing"
        },
        None,
    );
    let progress = (!args.quiet).then(|| {
        let (r, passes) = (reporter.clone(), Arc::new(AtomicU32::new(0)));
        let time = args.path.time;
        let f: ProgressFn = Arc::new(move |p: &Progress| show_progress(&r, &passes, time, p));
        f
    });
    let mut options = RenderOptions {
        threads: args.threads.map(|t| t as usize),
        tile_size: args.tile_size,
        aovs: aovs.clone(),
        progress,
        ..RenderOptions::default()
    };
    args.path.apply(&mut options, args.scene_args.spp.is_some());
    let out = ranks.render(&scene, &options);
    reporter.finish();
    let Some(out) = out? else {
        return Ok(());
    };
    print_shape_warnings(&scene, args.quiet);

    save(&out.image, &args.output).map_err(|e| CliError::Failure(e.to_string()))?;
    let mut written = vec![args.output.clone()];
    for (aov, raw) in &out.aovs {
        let path = aov_path(&args.output, *aov);
        let image = if format == Format::Png {
            aov.display(raw)
        } else {
            raw.clone()
        };
        save(&image, &path).map_err(|e| CliError::Failure(e.to_string()))?;
        written.push(path);
    }

    if !args.quiet {
        let secs = out.elapsed.as_secs_f64().max(1e-9);
        let rays = out.stats.total_rays();
        let (w, h) = (out.image.width(), out.image.height());
        if path_traced {
            if args.path.resume.is_some() && out.stats.samples == 0 {
                eprintln!(
                    "The checkpoint already holds {} samples per pixel; nothing to add.",
                    out.samples
                );
            }
            eprintln!(
                "Path traced {w}x{h} at {} spp in {secs:.3} s ({:?}): {:.2} Msamples/s, {:.2} Mrays/s, relative error {:.4}",
                out.samples,
                out.stop,
                out.stats.camera_rays as f64 / secs / 1e6,
                rays as f64 / secs / 1e6,
                out.relative_error
            );
            if let Some(c) = args.path.checkpoint.as_ref().or(args.path.resume.as_ref()) {
                eprintln!("Checkpoint {}", c.display());
            }
        } else {
            eprintln!("{}", out.stats);
            eprintln!(
                "Rendered {w}x{h} at {} spp in {secs:.3} s: {rays} rays, {:.2} Mrays/s",
                scene.settings.spp.max(1),
                rays as f64 / secs / 1e6
            );
        }
        for p in written {
            eprintln!("Wrote {}", p.display());
        }
    }
    Ok(())
}

/// Reports the render's progress to the one reporter (a bar on a terminal, log lines
/// otherwise): the pixel-samples done when their number is known, and after each pass
/// of a progressive render its samples per pixel, error estimate and the fraction of
/// the sample or time budget (`time`, seconds) used.
fn show_progress(
    r: &crate::progress::Progress,
    passes: &AtomicU32,
    time: Option<f64>,
    p: &Progress,
) {
    if let Some(total) = p.total {
        r.set_length(total);
    }
    r.set_position(p.done);
    if let Some(rep) = p.pass {
        let pass = passes.fetch_add(1, Ordering::Relaxed) + 1;
        let by_samples = (rep.target_samples != u32::MAX && rep.target_samples > 0)
            .then(|| rep.samples as f64 / rep.target_samples as f64);
        let by_time = time.map(|t| rep.elapsed.as_secs_f64() / t);
        let done = match (by_samples, by_time) {
            (Some(a), Some(b)) => Some(a.max(b)),
            (a, b) => a.or(b),
        };
        r.pass(PassStatus {
            pass,
            spp: rep.samples as u64,
            error: rep.relative_error.is_finite().then_some(rep.relative_error),
            done,
        });
    }
}

/// Prints what the shapes noticed while rendering (a Lipschitz bound too small, rays
/// given up), once each.
fn print_shape_warnings(scene: &irradia_scene::Scene, quiet: bool) {
    for instance in scene.accel.instances() {
        for w in instance.shape.take_warnings() {
            if !quiet {
                eprintln!("irradia: warning: {w}");
            }
        }
    }
}
