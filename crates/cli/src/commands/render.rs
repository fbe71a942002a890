//! `irradia render` (being written).

use crate::error::CliError;
use clap::Args;

#[derive(Args, Debug)]
pub struct RenderArgs {}

pub fn run(_args: RenderArgs) -> Result<(), CliError> {
    Err(CliError::Failure("not available yet".into()))
}
