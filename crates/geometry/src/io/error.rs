//! The one error type of mesh files.

use std::fmt;
use std::path::{Path, PathBuf};

/// A problem with a mesh file: `path[:line]: [field: ]message`.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshFileError {
    pub path: PathBuf,
    /// 1-based line of a text file (OBJ, ASCII PLY, any PLY header).
    pub line: Option<usize>,
    /// 1-based column (in characters) on `line`, where the reader knows it; not part
    /// of the message (importers place it in their own `file:line:col`).
    pub column: Option<usize>,
    /// What was being read: "v: y", "face 12: vertex_indices", "element vertex".
    pub field: Option<String>,
    pub message: String,
}

impl MeshFileError {
    pub fn new(
        path: &Path,
        line: Option<usize>,
        field: Option<String>,
        message: impl Into<String>,
    ) -> Self {
        Self {
            path: path.to_path_buf(),
            line,
            column: None,
            field,
            message: message.into(),
        }
    }
}

impl MeshFileError {
    /// The error with a column on its line.
    pub fn at_column(mut self, column: usize) -> Self {
        self.column = Some(column);
        self
    }
}

impl fmt::Display for MeshFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.path.display())?;
        if let Some(l) = self.line {
            write!(f, ":{l}")?;
        }
        if let Some(field) = &self.field {
            write!(f, ": {field}")?;
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for MeshFileError {}
