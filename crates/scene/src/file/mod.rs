//! Scene files: TOML and JSON with one schema (docs/scene-format.md), parsed into a
//! positioned tree, then read field by field into a validated [`Scene`].

pub mod attributes;
pub mod bsdfs;
pub mod emitters;
pub mod generators;
pub mod json_tree;
pub mod labels;
pub mod lights;
pub mod materials;
pub mod objects;
pub mod reader;
pub mod shapes;
pub mod surfaces;
pub mod textures;
pub mod transform;
pub mod tree;
pub mod view;

use crate::error::SceneError;
use crate::scene::Scene;
use reader::{Doc, Val};
use std::path::Path;

/// The syntax of a scene file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneSyntax {
    Toml,
    Json,
}

impl SceneSyntax {
    /// The format named by a path's extension (`.toml`, `.json`).
    pub fn from_path(path: &Path) -> Result<SceneSyntax, SceneError> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .as_deref()
        {
            Some("toml") => Ok(SceneSyntax::Toml),
            Some("json") => Ok(SceneSyntax::Json),
            _ => Err(
                SceneError::input("", "unknown scene file extension: use .toml or .json")
                    .with_file(path),
            ),
        }
    }
}

/// Loads a scene file; the format follows the extension, and relative paths inside
/// (meshes, image textures) are resolved against the file's folder.
pub fn load_file(path: &Path) -> Result<Scene, SceneError> {
    let format = SceneSyntax::from_path(path)?;
    let text = std::fs::read_to_string(path).map_err(|e| {
        let mut err = SceneError::io(path, &e);
        if matches!(
            e.kind(),
            std::io::ErrorKind::NotFound | std::io::ErrorKind::InvalidData
        ) {
            // A missing or non-UTF-8 scene is the user's input, not a machine failure.
            err.kind = crate::error::ErrorKind::BadInput;
        }
        err
    })?;
    load_str(&text, format, path)
}

/// Loads a scene from text. `origin` names it in messages and its folder is where
/// relative paths are resolved.
pub fn load_str(text: &str, format: SceneSyntax, origin: &Path) -> Result<Scene, SceneError> {
    let tree = match format {
        SceneSyntax::Toml => tree::parse_toml(text),
        SceneSyntax::Json => json_tree::parse_json(text),
    }
    .map_err(|e| e.with_file(origin))?;
    load_tree(&tree, text, origin)
}

/// Reads a scene from its document tree: the seam every scene format goes through.
/// The TOML and JSON readers parse into a [`tree::Node`]; importers of other formats
/// (Mitsuba XML, pbrt, glTF, ...) build one in Irradia's schema. Positions in `tree`
/// are byte offsets into `text`, the text of `origin` (empty text for binary files:
/// errors then name line 1), and relative paths are resolved against `origin`'s folder.
pub fn load_tree(tree: &tree::Node, text: &str, origin: &Path) -> Result<Scene, SceneError> {
    let doc = Doc {
        text,
        file: Some(origin.to_path_buf()),
        dir: origin.parent().map(Path::to_path_buf).unwrap_or_default(),
    };
    let mut scene = read_scene(&doc, tree)?;
    scene.source = Some(origin.to_path_buf());
    Ok(scene)
}

fn read_scene(doc: &Doc, tree: &tree::Node) -> Result<Scene, SceneError> {
    let root = Val::root(doc, tree).table()?;
    let settings = view::read_settings(root.get("image"), root.get("render"))?;
    let camera = view::read_camera(root.get("camera"), &root)?;
    let materials = materials::read_materials(root.get("materials"))?;
    let lights = lights::read_lights(root.get("lights"))?;
    let mut mats = objects::MaterialTable::new(materials);
    let groups = objects::read_shape_groups(root.get("shape_groups"), &mut mats)?;
    let (objects, instances) = objects::read_objects(root.get("objects"), &mut mats, &groups)?;
    let labels = labels::read_labels(root.get("labels"))?;
    root.finish()?;
    let mut scene = Scene::new(camera, settings, mats.materials, lights, objects, instances);
    scene.labels = labels;
    Ok(scene)
}
