//! `irradia convert`: any scene Irradia reads, written as Irradia's own TOML file.

use crate::error::CliError;
use crate::scene_arg::{check_scene_path, report_import, ImportArgs};
use clap::Args;
use std::path::PathBuf;

const EXAMPLES: &str = "\
Examples:
  irradia convert scene.xml -o scene.toml                # a Mitsuba 3 scene
  irradia convert scene.xml -D spp=64 -o scene.toml      # with a parameter set
  irradia convert model.glb -o model.toml                # a bare model gets a camera and a light
  irradia render scene.toml -o scene.png                 # renders as the original does";

#[derive(Args, Debug)]
#[command(after_long_help = EXAMPLES)]
pub struct ConvertArgs {
    /// The scene to convert: a file of any format `irradia render` reads.
    #[arg(value_name = "SCENE")]
    pub scene: PathBuf,
    /// The TOML file to write (meshes and textures stay where they are and are named
    /// relative to it). An existing file is only replaced with --force.
    #[arg(short, long, value_name = "FILE.toml")]
    pub output: PathBuf,
    /// Replace the output file if it exists.
    #[arg(long)]
    pub force: bool,
    #[command(flatten)]
    pub import: ImportArgs,
}

pub fn run(a: ConvertArgs) -> Result<(), CliError> {
    check_scene_path(&a.scene)?;
    let out = &a.output;
    if out
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        != Some("toml".into())
    {
        return Err(CliError::Input(format!(
            "{}: the converted scene is written as TOML: give a file ending in .toml",
            out.display()
        )));
    }
    let out_dir = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if !out_dir.is_dir() {
        return Err(CliError::Input(format!(
            "{}: the folder {} does not exist",
            out.display(),
            out_dir.display()
        )));
    }
    if out.exists() && !a.force {
        return Err(CliError::Input(format!(
            "{}: exists; give --force to replace it",
            out.display()
        )));
    }
    let imported = irradia_import::import(&a.scene, &a.import.options())?;
    report_import(&imported, false);
    // The scene must be valid before anything is written.
    imported.scene()?;
    let from = match a.scene.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let text = irradia_import::toml_out::to_toml(&imported.tree, &from, &out_dir);
    let header = format!(
        "# Converted by `irradia convert` from {}\n",
        a.scene.display()
    );
    std::fs::write(out, header + &text)
        .map_err(|e| CliError::Failure(format!("{}: cannot write: {e}", out.display())))?;
    eprintln!("irradia: wrote {}", out.display());
    Ok(())
}
