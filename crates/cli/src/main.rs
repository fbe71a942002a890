//! `irradia`: the command-line front end. One subcommand per job; each lives in its own
//! file under `commands/`.
//!
//! Exit codes: 0 success, 1 a failure while working (I/O, internal), 2 bad input (a
//! scene file, an option, a wall file): the message names the file, line and field.

mod commands;
mod error;
mod output;
mod progress;
mod scene_arg;

use clap::{Parser, Subcommand};

#[derive(Parser, Debug)]
#[command(
    name = "irradia",
    version,
    about = "Irradia: ray tracing, path tracing, radiosity and parallel rendering",
    long_about = None,
    after_long_help = "Run `irradia <COMMAND> --help` for a command's options and examples.\nExit codes: 0 done, 1 failure while working, 2 bad input (scene file, option)."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render a scene file or a built-in scene to an image (PNG, EXR or PFM).
    Render(commands::render::RenderArgs),
    /// Write any scene Irradia reads (Mitsuba XML, pbrt, glTF, OBJ, PLY) as Irradia's TOML.
    Convert(commands::convert::ConvertArgs),
    /// Print the ray tree of one pixel (text, JSON or Graphviz dot).
    TracePixel(commands::trace_pixel::TracePixelArgs),
    /// List the built-in scenes.
    Scenes(commands::scenes::ScenesArgs),
    /// Solve a scene (default: the measured Cornell box) by radiosity; image, PLY, residuals.
    Radiosity(commands::radiosity::RadiosityArgs),
    /// Evaluate a closed-form form factor of the lecture's catalogue (`irradia formfactor list`).
    Formfactor(commands::formfactor::FormFactorArgs),
    /// Render one frame sort-first, sort-middle or sort-last on N ranks and composite it.
    Parallel(commands::parallel::ParallelArgs),
    /// Benchmarks: `irradia bench parallel` (sort-first vs sort-last study, CSV + PNG).
    Bench(commands::bench::BenchArgs),
    /// Render for a tiled wall of projectors or panels: per-display images and a simulated photograph.
    Wall(commands::wall::WallArgs),
}

/// A clap error in one line, like every other error of the command: the message, the
/// tip if any, the usage and where the help is.
fn one_line(e: &clap::Error) -> String {
    let text = e.render().to_string();
    let mut message = String::new();
    let mut tip = None;
    let mut usage = None;
    for line in text.lines().map(str::trim).filter(|l| !l.is_empty()) {
        if let Some(m) = line.strip_prefix("error: ") {
            message = m.to_string();
        } else if let Some(t) = line.strip_prefix("tip: ") {
            tip.get_or_insert_with(|| t.to_string());
        } else if let Some(u) = line.strip_prefix("Usage: ") {
            usage.get_or_insert_with(|| u.to_string());
        } else if message.is_empty() {
            message = line.to_string();
        }
    }
    let mut out = message;
    if let Some(t) = tip {
        out.push_str(&format!(" ({t})"));
    }
    if let Some(u) = usage {
        let command = u
            .split(" [")
            .next()
            .unwrap_or(&u)
            .split(" <")
            .next()
            .unwrap_or(&u);
        out.push_str(&format!("; usage: {u}; see `{command} --help`"));
    }
    out
}

fn main() {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind as K;
            match e.kind() {
                // Help and version are what was asked for, not errors.
                K::DisplayHelp
                | K::DisplayVersion
                | K::DisplayHelpOnMissingArgumentOrSubcommand => e.exit(),
                _ => {
                    eprintln!("irradia: {}", one_line(&e));
                    std::process::exit(2);
                }
            }
        }
    };
    let result = match cli.command {
        Command::Render(a) => commands::render::run(a),
        Command::Convert(a) => commands::convert::run(a),
        Command::TracePixel(a) => commands::trace_pixel::run(a),
        Command::Scenes(a) => commands::scenes::run(a),
        Command::Radiosity(a) => commands::radiosity::run(a),
        Command::Formfactor(a) => commands::formfactor::run(a),
        Command::Parallel(a) => commands::parallel::run(a),
        Command::Bench(a) => commands::bench::run(a),
        Command::Wall(a) => commands::wall::run(a),
    };
    if let Err(e) = result {
        eprintln!("irradia: {e}");
        std::process::exit(e.exit_code());
    }
}
