//! The built-in scenes: TOML files in `crates/scene/scenes/`, embedded in the binary,
//! so every built-in is also an example of the scene format.

use crate::error::SceneError;
use crate::file::{load_str, SceneSyntax};
use crate::scene::Scene;
use std::path::PathBuf;

/// (name, one-line description, TOML text).
const SCENES: &[(&str, &str, &str)] = &[
    (
        "default",
        "a showcase: mirror and glass, CSG, quadrics, a teapot, an implicit surface, soft shadows",
        include_str!("../scenes/default.toml"),
    ),
    (
        "whitted",
        "Whitted's 1980 scene: mirror and glass spheres over a checker (POV-Ray's whitted.pov)",
        include_str!("../scenes/whitted.toml"),
    ),
    (
        "csg",
        "CSG: cube minus sphere, Steinmetz solid, union of spheres (POV-Ray's csg.pov)",
        include_str!("../scenes/csg.toml"),
    ),
    (
        "quadrics",
        "every named quadric (clipped) and a general quadric from its ten coefficients",
        include_str!("../scenes/quadrics.toml"),
    ),
    (
        "polyhedra",
        "tetrahedron, octahedron, dodecahedron as half-spaces; non-convex polygons",
        include_str!("../scenes/polyhedra.toml"),
    ),
    (
        "teapot",
        "the Utah teapot from its 32 Bezier patches, with a soft area-light shadow",
        include_str!("../scenes/teapot.toml"),
    ),
    (
        "implicit",
        "implicit surfaces from expressions: a gyroid slab, metaballs, a quartic torus",
        include_str!("../scenes/implicit.toml"),
    ),
    (
        "cornell",
        "the RGB Cornell box of Mitsuba 3, path traced (512x512, 64 spp, max depth 8)",
        include_str!("../scenes/cornell.toml"),
    ),
    (
        "materials",
        "every physically based BSDF (Mitsuba 3's plugins) on one ball, with labels, path traced",
        include_str!("../scenes/materials.toml"),
    ),
    (
        "cornell-measured",
        "the measured Cornell box (millimetres), the reference scene of radiosity",
        include_str!("../scenes/cornell-measured.toml"),
    ),
];

/// The built-in scenes: (name, one-line description).
/// Files the built-in scenes name (an environment map), embedded in the binary so that
/// a built-in renders wherever the binary is.
const ASSETS: &[(&str, &[u8])] = &[(
    "gallery_sky.hdr",
    include_bytes!("../scenes/gallery_sky.hdr"),
)];

/// The embedded file a built-in scene calls `name`.
pub fn asset(name: &str) -> Option<&'static [u8]> {
    ASSETS.iter().find(|a| a.0 == name).map(|a| a.1)
}

pub fn names() -> Vec<(&'static str, &'static str)> {
    SCENES.iter().map(|(n, d, _)| (*n, *d)).collect()
}

/// The TOML text of a built-in scene (to print or copy as a starting point).
pub fn source(name: &str) -> Option<&'static str> {
    SCENES.iter().find(|s| s.0 == name).map(|s| s.2)
}

/// Loads a built-in scene by name; an unknown name is an error listing the valid ones.
pub fn load(name: &str) -> Result<Scene, SceneError> {
    let Some(text) = source(name) else {
        let valid: Vec<&str> = SCENES.iter().map(|s| s.0).collect();
        return Err(SceneError::input(
            "",
            crate::file::reader::unknown_name_message("built-in scene", name, &valid),
        ));
    };
    load_str(text, SceneSyntax::Toml, &origin(name))
}

/// The name a built-in scene goes by in messages: `builtin:NAME.toml`.
pub fn origin(name: &str) -> PathBuf {
    PathBuf::from(format!("builtin:{name}.toml"))
}
