//! `irradia scenes` (being written).

use crate::error::CliError;
use clap::Args;

#[derive(Args, Debug)]
pub struct ScenesArgs {}

pub fn run(_args: ScenesArgs) -> Result<(), CliError> {
    Err(CliError::Failure("not available yet".into()))
}
