//! Wavefront OBJ with its MTL materials, as a scene.
//!
//! The geometry stays in the OBJ file: each `usemtl` group becomes one object
//! `{ type = "mesh", path = "model.obj", group = "name", material = "name" }`, with
//! `flip_tex_coords = true` when it has texture coordinates (the
//! scene reader loads the group's faces with `tobj`), so `irradia convert` writes a
//! small file that points at the original. Each MTL material becomes a Mitsuba-style
//! BSDF by the rule of [`mtl`]. A file without a camera or light gets the framing
//! camera and the environment light of [`crate::model`].
//!
//! Errors: a malformed statement, an unknown statement, or an unknown MTL directive
//! names the file, line and column. Known statements that Irradia does not render
//! (`l`, `p`, free-form curves and surfaces) and MTL directives it does not map
//! (`Ka`, `Tf`, `map_Ks`, ...) are warnings.

pub mod mtl;

use crate::model::{self, Bounds};
use crate::{read_text, Imported};
use irradia_geometry::io::obj::{check_obj, parse_obj_groups, tokens};
use irradia_scene::file::tree::Node;
use irradia_scene::SceneError;
use std::collections::HashMap;
use std::path::Path;

/// Statements read as geometry or grouping.
const READ: &[&str] = &["v", "vt", "vn", "f", "o", "g", "s", "usemtl", "mtllib"];
/// Statements of the format that Irradia does not render: a warning each (once).
const NOT_RENDERED: &[&str] = &[
    "l",
    "p",
    "vp",
    "cstype",
    "deg",
    "bmat",
    "step",
    "curv",
    "curv2",
    "surf",
    "parm",
    "trim",
    "hole",
    "scrv",
    "sp",
    "end",
    "con",
    "mg",
    "lod",
    "bevel",
    "c_interp",
    "d_interp",
    "usemap",
    "maplib",
    "shadow_obj",
    "trace_obj",
    "ctech",
    "stech",
];

/// Imports `path`.
pub fn import(path: &Path) -> Result<Imported, SceneError> {
    let text = read_text(path)?;
    parse_str(&text, path)
}

/// Imports OBJ text as if read from `origin` (its `mtllib` files are read relative to
/// `origin`'s folder, and the objects refer to `origin` by name).
pub fn parse_str(text: &str, origin: &Path) -> Result<Imported, SceneError> {
    let mut warnings = Vec::new();
    check_statements(text, origin, &mut warnings)?;
    check_obj(text, origin).map_err(model::mesh_error)?;
    let dir = origin.parent().unwrap_or(Path::new(""));
    // MTL files: checked with positions here, read by tobj below.
    let mut libs: Vec<mtl::MtlFile> = Vec::new();
    for (line, name) in mtllib_lines(text) {
        let p = dir.join(&name);
        match std::fs::read(&p) {
            Ok(bytes) => {
                let mtl_text = String::from_utf8_lossy(&bytes).into_owned();
                let file = mtl::check(&mtl_text, &p, &mut warnings)?;
                libs.push(file);
            }
            Err(e) => warnings.push(
                SceneError::input(
                    "mtllib",
                    format!("cannot read {}: {e}; its materials are grey", p.display()),
                )
                .at(line, 1)
                .with_file(origin),
            ),
        }
    }
    let loader = irradia_geometry::io::obj::mtl_loader(origin);
    let data = parse_obj_groups(text, origin, loader).map_err(model::mesh_error)?;
    let uses_mtl = text
        .lines()
        .any(|l| tokens(l).next().is_some_and(|(_, k)| k == "usemtl"));

    let mut tree = Node::table(0);
    let mut materials = Node::table(0);
    let mut names: HashMap<String, String> = HashMap::new();
    let mut lit = false;
    for m in &data.materials {
        let lib = libs.iter().find(|l| l.materials.contains(&m.name));
        let mtl_dir = lib
            .and_then(|l| l.path.parent())
            .unwrap_or(dir)
            .to_path_buf();
        let node = mtl::material(m, &mtl_dir, dir, &mut warnings, origin);
        if m.emissive.is_some_and(|e| e.iter().any(|&x| x > 0.0)) {
            lit = true;
        }
        let key = unique_key(&m.name, &names);
        names.insert(m.name.clone(), key.clone());
        materials.set(&key, node);
    }
    let file_name = model::rel_name(origin, dir);
    let mut bounds = Bounds::default();
    for g in &data.groups {
        for p in &g.mesh.positions {
            bounds.add(*p);
        }
        let mut obj = Node::table(0);
        obj.put("type", "mesh", 0)
            .put("path", file_name.as_str(), 0);
        if g.mesh.uvs.is_some() {
            // OBJ's texture origin is the image's bottom-left corner (Mitsuba's default).
            obj.put("flip_tex_coords", true, 0);
        }
        if uses_mtl {
            obj.put("group", g.material.clone().unwrap_or_default(), 0);
        }
        if let Some(m) = g.material.as_ref().filter(|m| !names.contains_key(*m)) {
            warnings.push(
                SceneError::input(
                    "usemtl",
                    format!("no MTL file defines material `{m}`: its faces are grey"),
                )
                .with_file(origin),
            );
        }
        if let Some(key) = g.material.as_ref().and_then(|m| names.get(m)) {
            obj.put("material", key.as_str(), 0).put(
                "name",
                g.material.clone().unwrap_or_default(),
                0,
            );
        }
        tree.push("objects", obj);
    }
    if data.groups.is_empty() {
        return Err(SceneError::input("", "the file has no faces").with_file(origin));
    }
    if !names.is_empty() {
        tree.set("materials", materials);
    }
    let mut notes = Vec::new();
    model::complete_bare_model(&mut tree, bounds, lit, &mut notes);
    Ok(Imported {
        tree,
        text: text.to_string(),
        origin: origin.to_path_buf(),
        warnings,
        notes,
    })
}

/// A material key that is a valid, unused name (`default` is Irradia's fallback).
fn unique_key(name: &str, used: &HashMap<String, String>) -> String {
    let base = if name.is_empty() { "material" } else { name };
    let mut key = base.to_string();
    let mut k = 2;
    while used.values().any(|v| v == &key) {
        key = format!("{base}_{k}");
        k += 1;
    }
    key
}

/// `(line, name)` of every `mtllib` statement (each may name several files).
fn mtllib_lines(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let content = raw.split('#').next().unwrap_or("");
        let mut tok = tokens(content);
        if tok.next().map(|t| t.1) == Some("mtllib") {
            // tobj reads the rest of the line as one name; so does this.
            let name = content.trim_start()[6..].trim();
            if !name.is_empty() {
                out.push((n + 1, name.to_string()));
            }
        }
    }
    out
}

/// Unknown statements are errors; known ones that do not render, warnings (once each).
fn check_statements(
    text: &str,
    origin: &Path,
    warnings: &mut Vec<SceneError>,
) -> Result<(), SceneError> {
    let mut warned: Vec<&str> = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let content = raw.split('#').next().unwrap_or("");
        let Some((col, key)) = tokens(content).next() else {
            continue;
        };
        if READ.contains(&key) {
            continue;
        }
        if let Some(k) = NOT_RENDERED.iter().find(|k| **k == key) {
            if !warned.contains(k) {
                warned.push(k);
                warnings.push(
                    SceneError::input(
                        key,
                        format!(
                            "`{key}` statements are not rendered (Irradia reads surfaces: faces)"
                        ),
                    )
                    .at(n + 1, col)
                    .with_file(origin),
                );
            }
            continue;
        }
        return Err(
            SceneError::input(key, format!("unknown OBJ statement `{key}`"))
                .at(n + 1, col)
                .with_file(origin),
        );
    }
    Ok(())
}
