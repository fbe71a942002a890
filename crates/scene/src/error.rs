//! Errors from loading a scene: where (file, line, column, field) and what.

use std::fmt;
use std::path::{Path, PathBuf};

/// Whether an error is the user's input (exit code 2) or a failure to read (exit 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// The scene (or a file it names) is malformed, out of range or inconsistent.
    BadInput,
    /// A file could not be read for a reason other than its content (permissions, I/O).
    Io,
}

/// A scene error, displayed as `scene.toml:12:5: objects[2].radius: must be positive (got -1)`.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    pub kind: ErrorKind,
    /// The scene file (or `builtin:NAME`); `None` for text loaded without a name.
    pub file: Option<PathBuf>,
    /// 1-based line and column of the offending value, when known.
    pub line: Option<usize>,
    pub column: Option<usize>,
    /// Dotted path of the field, e.g. `objects[2].radius`; empty for the whole file.
    pub field: String,
    pub message: String,
}

impl SceneError {
    /// A bad-input error with no position yet.
    pub fn input(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            kind: ErrorKind::BadInput,
            file: None,
            line: None,
            column: None,
            field: field.into(),
            message: message.into(),
        }
    }

    /// An I/O failure reading `file`.
    pub fn io(file: &Path, err: &std::io::Error) -> Self {
        Self {
            kind: ErrorKind::Io,
            file: Some(file.to_path_buf()),
            line: None,
            column: None,
            field: String::new(),
            message: format!("cannot read the file: {err}"),
        }
    }

    /// True when the error is the user's input (the CLI exits with code 2), false for
    /// an I/O failure (exit code 1).
    pub fn is_bad_input(&self) -> bool {
        self.kind == ErrorKind::BadInput
    }

    pub fn with_file(mut self, file: &Path) -> Self {
        if self.file.is_none() {
            self.file = Some(file.to_path_buf());
        }
        self
    }

    pub fn at(mut self, line: usize, column: usize) -> Self {
        self.line = Some(line);
        self.column = Some(column);
        self
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(file) = &self.file {
            write!(f, "{}", file.display())?;
            if let Some(line) = self.line {
                write!(f, ":{line}")?;
                if let Some(col) = self.column {
                    write!(f, ":{col}")?;
                }
            }
            f.write_str(": ")?;
        } else if let Some(line) = self.line {
            write!(f, "line {line}")?;
            if let Some(col) = self.column {
                write!(f, ":{col}")?;
            }
            f.write_str(": ")?;
        }
        if !self.field.is_empty() {
            write!(f, "{}: ", self.field)?;
        }
        f.write_str(&self.message)
    }
}

impl std::error::Error for SceneError {}
