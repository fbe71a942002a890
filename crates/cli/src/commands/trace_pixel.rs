//! `irradia trace-pixel`: the ray tree of one pixel, as text, JSON or Graphviz dot.

use crate::error::CliError;
use crate::scene_arg::{load_scene, SceneArgs};
use clap::{Args, ValueEnum};
use std::path::PathBuf;

const EXAMPLES: &str = "\
Examples:
  irradia trace-pixel --builtin whitted 500 300
  irradia trace-pixel scene.toml 10 20 --format json > tree.json
  irradia trace-pixel --builtin whitted 500 300 --format dot | dot -Tsvg > tree.svg

Pixel (0, 0) is the top-left corner; X grows to the right, Y downwards. The tree is
traced by the renderer's own code (a recording hook), so its radiance is the pixel's
value in `irradia render` with the same options.";

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum TreeFormat {
    /// An indented tree, one ray per block.
    Text,
    /// The tree as nested JSON objects.
    Json,
    /// A Graphviz digraph (render with `dot -Tsvg`).
    Dot,
}

#[derive(Args, Debug)]
#[command(after_long_help = EXAMPLES)]
pub struct TracePixelArgs {
    /// [SCENE] X Y: an optional scene file, then the pixel's column and row.
    #[arg(value_name = "[SCENE] X Y", num_args = 2..=3, required = true)]
    pub positional: Vec<String>,
    #[command(flatten)]
    pub scene_args: SceneArgs,
    /// Output format.
    #[arg(long, value_enum, default_value_t = TreeFormat::Text)]
    pub format: TreeFormat,
    /// Which camera sample of the pixel to trace (with --spp above 1).
    #[arg(long, value_name = "K", default_value_t = 0)]
    pub sample: u32,
}

fn coordinate(s: &str, what: &str) -> Result<u32, CliError> {
    s.parse::<u32>().map_err(|_| {
        CliError::Input(format!(
            "{what} must be a pixel index (a whole number from 0), got '{s}'"
        ))
    })
}

pub fn run(args: TracePixelArgs) -> Result<(), CliError> {
    let p = &args.positional;
    let (file, xs, ys) = match p.len() {
        3 => (Some(PathBuf::from(&p[0])), &p[1], &p[2]),
        _ => (None, &p[0], &p[1]),
    };
    let (x, y) = (coordinate(xs, "X")?, coordinate(ys, "Y")?);
    let scene = load_scene(file.as_ref(), &args.scene_args, false)?;
    let (tree, radiance) = irradia_render::trace_pixel(&scene, x, y, args.sample)?;
    let text = match args.format {
        TreeFormat::Text => format!(
            "pixel ({x}, {y}) sample {}: radiance ({:.4}, {:.4}, {:.4}), {} rays\n{}",
            args.sample,
            radiance.r,
            radiance.g,
            radiance.b,
            tree.count(),
            tree.to_text()
        ),
        TreeFormat::Json => {
            let doc = irradia_render::raytree::pixel_document(x, y, args.sample, radiance, &tree);
            serde_json::to_string_pretty(&doc).map_err(|e| CliError::Failure(e.to_string()))? + "\n"
        }
        TreeFormat::Dot => tree.to_dot(),
    };
    print!("{text}");
    Ok(())
}
