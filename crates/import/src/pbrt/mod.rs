//! pbrt-v4 scenes (`.pbrt`) read into Irradia's schema (docs/importers.md, "pbrt-v4").
//!
//! `lexer` and `parser` turn text into directives with byte offsets (the `pbrt4` crate
//! was considered: it reports no positions, so errors could not name a line and
//! column); `builder` runs them against pbrt's graphics state (the CTM, attributes,
//! named coordinate systems, materials, textures, object definitions) and writes the
//! tree; `view`, `materials`, `textures`, `shapes` and `lights` translate one kind of
//! directive each; `spectra` turns pbrt's spectra into RGB; `coverage` counts what a
//! file uses and how each use was treated.
//!
//! **Handedness.** pbrt's camera space is left-handed (x right, y up, z forward) and
//! Irradia's right-handed (x right, y up, looking down −z). A world is neither; only
//! the camera decides which way an image is mirrored. The importer keeps the image
//! as pbrt shows it by mirroring the whole world when needed: with `W` pbrt's
//! world-from-camera matrix, a camera whose `W` keeps handedness (a plain `LookAt`)
//! gets the world mirrored by `z → −z` (POV-Ray's rule in docs/scene-format.md); a
//! camera whose `W` already flips it (the `Scale -1 1 1` before `LookAt` that exporters
//! from right-handed tools write) keeps the world's coordinates unchanged.

mod builder;
pub mod coverage;
mod lexer;
mod lights;
mod materials;
mod params;
mod parser;
mod shapes;
mod spectra;
mod textures;
mod transform;
mod view;

pub use coverage::{Coverage, Status};
pub use parser::DIRECTIVES;

use crate::{Imported, Options};
use irradia_scene::SceneError;
use std::path::Path;

/// An error at a byte offset of the file being read (the builder adds the file).
#[derive(Clone, Debug)]
pub(crate) struct At {
    pub pos: usize,
    pub message: String,
}

impl At {
    pub fn new(pos: usize, message: impl Into<String>) -> At {
        At {
            pos,
            message: message.into(),
        }
    }
}

/// Reads `path` (a pbrt-v4 scene) into Irradia's schema, following `Include` and
/// `Import`.
pub fn import(path: &Path, opts: &Options) -> Result<Imported, SceneError> {
    let text = crate::read_text(path)?;
    let mut b = builder::Builder::new(path, &text, builder::Mode::Full);
    let _ = opts;
    b.run()?;
    Ok(b.finish(text))
}

/// Parses pbrt text in memory into Irradia's schema without touching the file system:
/// `Include`/`Import` are skipped with a note and no referenced file (mesh, image) is
/// opened. The fuzz target's entry point.
pub fn parse_str(text: &str, origin: &Path) -> Result<Imported, SceneError> {
    let mut b = builder::Builder::new(origin, text, builder::Mode::InMemory);
    b.run()?;
    Ok(b.finish(text.to_string()))
}

/// The coverage of a file (parse-only, in memory, not stopping at errors): every
/// directive and type it uses, counted, with how the importer treats it.
pub fn coverage_str(text: &str, origin: &Path) -> Coverage {
    let mut b = builder::Builder::new(origin, text, builder::Mode::Survey);
    let _ = b.run();
    b.coverage()
}

/// The closest of `valid` to `got` (edit distance at most a third of its length).
pub(crate) fn closest<'a>(got: &str, valid: &[&'a str]) -> Option<&'a str> {
    irradia_scene::file::reader::closest(got, valid)
}
