//! irradia-import: the scenes people already have, read into Irradia's own scene.
//!
//! Every format goes through one seam. An importer parses its file into the same
//! positioned document tree ([`irradia_scene::file::tree::Node`]) that the TOML and
//! JSON readers produce, in Irradia's schema (docs/scene-format.md); the scene crate's
//! one reader ([`irradia_scene::load_tree`]) validates it into a [`Scene`]. Syntax and
//! schema stay apart: an importer knows its format, never the renderer, and
//! `irradia convert` writes the same tree as TOML ([`toml_out`]).
//!
//! An importer raises an error (file, line, column; exit code 2) for what its format
//! does not define (an unknown plugin, parameter or directive) and a warning for a
//! known feature that Irradia does not render; [`Options::strict`] turns warnings into
//! errors.

pub mod gltf;
pub mod mitsuba;
pub mod model;
pub mod obj;
pub mod pbrt;
pub mod ply;
pub mod toml_out;

use irradia_scene::file::tree::Node;
use irradia_scene::{load_tree, Scene, SceneError, SceneSyntax};
use std::path::{Path, PathBuf};

/// The scene formats Irradia reads, by file extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Irradia's own TOML or JSON.
    Irradia(SceneSyntax),
    /// Wavefront OBJ with its MTL materials.
    Obj,
    /// glTF 2.0, JSON (`.gltf`) or binary (`.glb`).
    Gltf,
    /// A PLY mesh.
    Ply,
    /// Mitsuba 3's XML scene format.
    Mitsuba,
    /// pbrt-v4's scene format (`.pbrt`).
    Pbrt,
}

/// Every extension [`Format::of`] accepts, for messages and `--help`.
pub const EXTENSIONS: &[&str] = &[
    "toml", "json", "xml", "pbrt", "obj", "gltf", "glb", "ply", "ply.gz",
];

impl Format {
    /// The format named by `path`'s extension.
    pub fn of(path: &Path) -> Result<Format, SceneError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .unwrap_or_default();
        let gz_ply = ext == "gz"
            && path
                .file_stem()
                .and_then(|s| s.to_str())
                .is_some_and(|s| s.to_ascii_lowercase().ends_with(".ply"));
        Ok(match ext.as_str() {
            "toml" => Format::Irradia(SceneSyntax::Toml),
            "json" => Format::Irradia(SceneSyntax::Json),
            "obj" => Format::Obj,
            "gltf" | "glb" => Format::Gltf,
            "ply" => Format::Ply,
            "gz" if gz_ply => Format::Ply,
            "xml" => Format::Mitsuba,
            "pbrt" => Format::Pbrt,
            _ => {
                let list: Vec<String> = EXTENSIONS.iter().map(|e| format!(".{e}")).collect();
                return Err(SceneError::input(
                    "",
                    format!(
                        "unknown scene file extension: Irradia reads {}",
                        list.join(", ")
                    ),
                )
                .with_file(path));
            }
        })
    }
}

/// How a scene is imported.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Values for a scene's parameters (Mitsuba's `-D name=value`, its `$name`s and
    /// `<default>`s), in the order given.
    pub defines: Vec<(String, String)>,
    /// Refuse a scene that uses a feature Irradia does not render, instead of warning.
    pub strict: bool,
}

/// A scene file read into Irradia's schema.
#[derive(Clone, Debug)]
pub struct Imported {
    /// The scene as a document tree in Irradia's schema.
    pub tree: Node,
    /// The text the tree's positions are byte offsets into (empty for binary files).
    pub text: String,
    /// The file imported.
    pub origin: PathBuf,
    /// Features of the file that Irradia does not render (each names its place).
    pub warnings: Vec<SceneError>,
    /// What the importer added that the file did not say (a camera framing a bare
    /// model, a default light), one line each.
    pub notes: Vec<String>,
}

impl Imported {
    /// The validated scene.
    pub fn scene(&self) -> Result<Scene, SceneError> {
        load_tree(&self.tree, &self.text, &self.origin)
    }

    /// Fails with the first warning when `strict` asks for it.
    fn check_strict(self, strict: bool) -> Result<Imported, SceneError> {
        match self.warnings.first() {
            Some(w) if strict => {
                let mut e = w.clone();
                e.message = format!("{} (refused by --strict)", e.message);
                Err(e)
            }
            _ => Ok(self),
        }
    }
}

/// Reads `path` (any format of [`Format`]) into Irradia's schema.
pub fn import(path: &Path, opts: &Options) -> Result<Imported, SceneError> {
    let format = Format::of(path)?;
    let imported = match format {
        Format::Irradia(syntax) => import_irradia(path, syntax)?,
        Format::Obj => obj::import(path)?,
        Format::Gltf => gltf::import(path)?,
        Format::Ply => ply::import(path)?,
        Format::Mitsuba => mitsuba::import(path, opts)?,
        Format::Pbrt => pbrt::import(path, opts)?,
    };
    imported.check_strict(opts.strict)
}

/// Reads `path` (any format of [`Format`]) as a validated scene, with the importer's
/// warnings and notes.
pub fn load(path: &Path, opts: &Options) -> Result<(Scene, Imported), SceneError> {
    let imported = import(path, opts)?;
    let scene = imported.scene()?;
    Ok((scene, imported))
}

/// Reads a whole text file; a missing or non-UTF-8 file is bad input (exit 2), other
/// failures are I/O errors (exit 1).
pub fn read_text(path: &Path) -> Result<String, SceneError> {
    std::fs::read_to_string(path).map_err(|e| io_error(path, &e))
}

/// Reads a whole file's bytes, errors as [`read_text`].
pub fn read_bytes(path: &Path) -> Result<Vec<u8>, SceneError> {
    std::fs::read(path).map_err(|e| io_error(path, &e))
}

fn io_error(path: &Path, e: &std::io::Error) -> SceneError {
    let mut err = SceneError::io(path, e);
    if matches!(
        e.kind(),
        std::io::ErrorKind::NotFound | std::io::ErrorKind::InvalidData
    ) {
        err.kind = irradia_scene::ErrorKind::BadInput;
    }
    err
}

fn import_irradia(path: &Path, syntax: SceneSyntax) -> Result<Imported, SceneError> {
    use irradia_scene::file::{json_tree, tree};
    let text = read_text(path)?;
    let tree = match syntax {
        SceneSyntax::Toml => tree::parse_toml(&text),
        SceneSyntax::Json => json_tree::parse_json(&text),
    }
    .map_err(|e| e.with_file(path))?;
    Ok(Imported {
        tree,
        text,
        origin: path.to_path_buf(),
        warnings: Vec::new(),
        notes: Vec::new(),
    })
}

/// Checks that a scene file argument names a file that exists: a folder or a missing
/// file is bad input, said in one line (the command line and the Python binding give
/// the same message).
pub fn check_path(path: &Path) -> Result<(), SceneError> {
    if path.is_dir() {
        let exts: Vec<String> = EXTENSIONS.iter().map(|e| format!(".{e}")).collect();
        return Err(SceneError::input(
            "",
            format!(
                "{}: is a directory, not a scene file (give a file ending in {})",
                path.display(),
                exts.join(", ")
            ),
        ));
    }
    if !path.exists() {
        return Err(SceneError::input(
            "",
            format!("{}: no such scene file", path.display()),
        ));
    }
    Ok(())
}
