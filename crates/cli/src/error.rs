//! The CLI's error: a message and the exit code it maps to.

use std::fmt;

#[derive(Debug)]
pub enum CliError {
    /// Bad input from the user (scene file, option, wall file): exit code 2.
    Input(String),
    /// A failure while working (I/O, out of memory): exit code 1.
    Failure(String),
}

impl CliError {
    pub fn exit_code(&self) -> i32 {
        match self {
            CliError::Input(_) => 2,
            CliError::Failure(_) => 1,
        }
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CliError::Input(m) | CliError::Failure(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for CliError {}

impl From<irradia_scene::SceneError> for CliError {
    /// Malformed scenes are the user's input (exit 2); unreadable files are failures.
    fn from(e: irradia_scene::SceneError) -> Self {
        if e.is_bad_input() {
            CliError::Input(e.to_string())
        } else {
            CliError::Failure(e.to_string())
        }
    }
}

impl From<irradia_render::RenderError> for CliError {
    fn from(e: irradia_render::RenderError) -> Self {
        use irradia_render::RenderError as E;
        match e {
            E::Image(_) | E::PixelOutside { .. } | E::Settings(_) | E::Resume(_) => {
                CliError::Input(e.to_string())
            }
            E::Threads(_) | E::CheckpointWrite(_) => CliError::Failure(e.to_string()),
            #[allow(unreachable_patterns)]
            _ => CliError::Failure(e.to_string()),
        }
    }
}
