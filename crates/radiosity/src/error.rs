//! Errors of the radiosity crate. Every message says what to change.

use thiserror::Error;

#[derive(Debug, Error)]
pub enum RadiosityError {
    /// Bad input: a patch or option the user must change (the CLI exits with code 2).
    #[error("{0}")]
    Input(String),
    /// A failure while working (I/O).
    #[error("{0}")]
    Failure(String),
}

impl RadiosityError {
    pub fn is_input(&self) -> bool {
        matches!(self, RadiosityError::Input(_))
    }
}

pub type Result<T> = std::result::Result<T, RadiosityError>;
