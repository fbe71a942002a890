//! `irradia scenes`: list the built-in scenes, or print one's scene file.

use crate::error::CliError;
use clap::Args;

const EXAMPLES: &str = "\
Examples:
  irradia scenes                       # names and descriptions
  irradia scenes --show whitted > my.toml   # a built-in as a scene file to edit
  irradia render my.toml -o my.png";

#[derive(Args, Debug)]
#[command(after_long_help = EXAMPLES)]
pub struct ScenesArgs {
    /// Print the scene file (TOML) of this built-in instead of the list.
    #[arg(long, value_name = "NAME")]
    pub show: Option<String>,
}

pub fn run(args: ScenesArgs) -> Result<(), CliError> {
    if let Some(name) = args.show {
        return match irradia_scene::builtin::source(&name) {
            Some(text) => {
                print!("{text}");
                Ok(())
            }
            None => {
                // Let the loader phrase the error (it lists the valid names).
                irradia_scene::builtin::load(&name)?;
                Err(CliError::Input(format!("unknown built-in scene '{name}'")))
            }
        };
    }
    let list = irradia_scene::builtin::names();
    let width = list.iter().map(|(n, _)| n.len()).max().unwrap_or(0);
    for (name, description) in list {
        println!("{name:<width$}  {description}");
    }
    Ok(())
}
