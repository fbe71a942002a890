//! Choosing the scene (a file, a built-in, or the default built-in) and overriding
//! its settings from the command line: shared by the subcommands that render.

use crate::error::CliError;
use clap::{Args, ValueEnum};
use irradia_scene::Scene;
use std::path::{Path, PathBuf};

/// Options that pick a scene and override its image settings.
#[derive(Args, Debug, Clone, Default)]
pub struct SceneArgs {
    /// Render a built-in scene (see `irradia scenes`) instead of a file.
    #[arg(long, value_name = "NAME")]
    pub builtin: Option<String>,
    /// Image width in pixels (overrides the scene's).
    #[arg(long, value_name = "W", value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub width: Option<u32>,
    /// Image height in pixels (overrides the scene's).
    #[arg(long, value_name = "H", value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub height: Option<u32>,
    /// Samples per pixel (overrides the scene's; stratified).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub spp: Option<u32>,
    /// Integrator (overrides the scene's `render.integrator`): the recursive Whitted
    /// ray tracer, or the path tracer that solves the rendering equation.
    #[arg(long, value_name = "NAME")]
    pub integrator: Option<IntegratorArg>,
    /// Maximum ray depth, camera rays being depth 1 (overrides the scene's).
    #[arg(long, value_name = "D", value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub max_depth: Option<u32>,
    #[command(flatten)]
    pub import: ImportArgs,
}

/// Options for reading scene files of other renderers (Mitsuba XML, pbrt, glTF, ...).
#[derive(Args, Debug, Clone, Default)]
pub struct ImportArgs {
    /// Set a scene parameter (Mitsuba's `$name` and `<default name=...>`); repeatable.
    #[arg(short = 'D', long = "define", value_name = "NAME=VALUE", value_parser = parse_define)]
    pub defines: Vec<(String, String)>,
    /// Refuse a scene that uses a feature Irradia does not render (default: warn and
    /// render the rest).
    #[arg(long)]
    pub strict: bool,
}

impl ImportArgs {
    pub fn options(&self) -> irradia_import::Options {
        irradia_import::Options {
            defines: self.defines.clone(),
            strict: self.strict,
        }
    }
}

fn parse_define(s: &str) -> Result<(String, String), String> {
    match s.split_once('=') {
        Some((name, value)) if !name.trim().is_empty() => {
            Ok((name.trim().to_string(), value.to_string()))
        }
        _ => Err(format!("expected NAME=VALUE, got '{s}'")),
    }
}

/// The integrators `--integrator` accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum IntegratorArg {
    /// The recursive ray tracer of the lecture (Phong shading, shadow rays, mirrors, glass).
    Whitted,
    /// The Monte Carlo path tracer (next-event estimation, MIS, Russian roulette).
    Path,
}

/// A scene file argument names a file that exists (a folder or a missing file is bad
/// input, said in one line: [`irradia_import::check_path`]).
pub fn check_scene_path(path: &Path) -> Result<(), CliError> {
    Ok(irradia_import::check_path(path)?)
}

/// Reads a scene file of any format Irradia imports; prints the importer's warnings
/// and (unless `quiet`) its notes of what it added on stderr, one line each.
pub fn import_scene(path: &Path, args: &ImportArgs, quiet: bool) -> Result<Scene, CliError> {
    check_scene_path(path)?;
    let (scene, imported) = irradia_import::load(path, &args.options())?;
    report_import(&imported, quiet);
    Ok(scene)
}

/// The importer's warnings (always: something in the file is not rendered) and notes
/// (what it added or read differently; not when `quiet`), on stderr.
pub fn report_import(imported: &irradia_import::Imported, quiet: bool) {
    for w in &imported.warnings {
        eprintln!("irradia: warning: {w}");
    }
    if quiet {
        return;
    }
    for n in &imported.notes {
        eprintln!("irradia: {n}");
    }
}

/// Loads the scene named by `file` or `args.builtin` (the built-in `default` when
/// neither is given) and applies the overrides; `quiet` silences the importer's notes.
pub fn load_scene(
    file: Option<&PathBuf>,
    args: &SceneArgs,
    quiet: bool,
) -> Result<Scene, CliError> {
    let mut scene = match (file, &args.builtin) {
        (Some(_), Some(_)) => {
            return Err(CliError::Input(
                "give either a scene file or --builtin, not both".into(),
            ))
        }
        (Some(path), None) => import_scene(path, &args.import, quiet)?,
        (None, Some(name)) => irradia_scene::builtin::load(name)?,
        (None, None) => irradia_scene::builtin::load("default")?,
    };
    irradia_scene::Overrides {
        width: args.width,
        height: args.height,
        spp: args.spp,
        integrator: args.integrator.map(|i| match i {
            IntegratorArg::Whitted => irradia_scene::Integrator::Whitted,
            IntegratorArg::Path => irradia_scene::Integrator::Path,
        }),
        max_depth: args.max_depth,
    }
    .apply(&mut scene)?;
    Ok(scene)
}
