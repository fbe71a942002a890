//! `irradia trace-pixel` (being written).

use crate::error::CliError;
use clap::Args;

#[derive(Args, Debug)]
pub struct TracePixelArgs {}

pub fn run(_args: TracePixelArgs) -> Result<(), CliError> {
    Err(CliError::Failure("not available yet".into()))
}
