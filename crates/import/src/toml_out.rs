//! `irradia convert`: a document tree written as Irradia's TOML scene file.
//!
//! Tables become `[section]`s and arrays of tables `[[section]]`s (as docs/
//! scene-format.md writes them); tables inside arrays are inline. File names (the
//! schema's `path`, `filename` and a projector's `irradiance` image) are rewritten
//! relative to the output's folder, so the converted file finds the same meshes and
//! textures from wherever it is written.

use irradia_scene::file::tree::{Node, Value};
use std::path::{Component, Path, PathBuf};

/// The keys whose string values name files, relative to the scene file's folder.
pub const FILE_KEYS: &[&str] = &["path", "filename", "irradiance"];

/// `tree` as TOML text. `from` is the folder its relative file names are relative to,
/// `to` the folder the TOML file will be written in.
pub fn to_toml(tree: &Node, from: &Path, to: &Path) -> String {
    let mut tree = tree.clone();
    rebase_paths(&mut tree, from, to);
    let mut doc = toml_edit::DocumentMut::new();
    if let Value::Table(entries) = &tree.value {
        for e in entries {
            doc.insert(&e.key, item(&e.node));
        }
    }
    doc.to_string()
}

fn item(node: &Node) -> toml_edit::Item {
    match &node.value {
        Value::Table(entries) => {
            let mut t = toml_edit::Table::new();
            for e in entries {
                t.insert(&e.key, item(&e.node));
            }
            // A table of tables only (`[materials]`) needs no header of its own.
            t.set_implicit(
                !entries.is_empty()
                    && entries
                        .iter()
                        .all(|e| matches!(e.node.value, Value::Table(_))),
            );
            toml_edit::Item::Table(t)
        }
        Value::Array(items)
            if !items.is_empty() && items.iter().all(|i| matches!(i.value, Value::Table(_))) =>
        {
            let mut a = toml_edit::ArrayOfTables::new();
            for i in items {
                if let toml_edit::Item::Table(t) = item(i) {
                    a.push(t);
                }
            }
            toml_edit::Item::ArrayOfTables(a)
        }
        _ => toml_edit::Item::Value(value(node)),
    }
}

fn value(node: &Node) -> toml_edit::Value {
    match &node.value {
        Value::Bool(b) => (*b).into(),
        Value::Int(i) => (*i).into(),
        Value::Float(f) => float(*f),
        Value::Str(s) => s.as_str().into(),
        Value::Array(items) => {
            let mut a = toml_edit::Array::new();
            for i in items {
                a.push(value(i));
            }
            toml_edit::Value::Array(a)
        }
        Value::Table(entries) => {
            let mut t = toml_edit::InlineTable::new();
            for e in entries {
                t.insert(&e.key, value(&e.node));
            }
            toml_edit::Value::InlineTable(t)
        }
    }
}

/// A float that reads back as the same `f64` (TOML has no NaN-free guarantee in the
/// schema, but the reader refuses non-finite values with a message).
fn float(f: f64) -> toml_edit::Value {
    f.into()
}

/// Rewrites every relative file name under [`FILE_KEYS`] from folder `from` to `to`.
pub fn rebase_paths(node: &mut Node, from: &Path, to: &Path) {
    match &mut node.value {
        Value::Table(entries) => {
            for e in entries.iter_mut() {
                if FILE_KEYS.contains(&e.key.as_str()) {
                    if let Value::Str(s) = &mut e.node.value {
                        *s = rebase(s, from, to);
                        continue;
                    }
                }
                rebase_paths(&mut e.node, from, to);
            }
        }
        Value::Array(items) => items.iter_mut().for_each(|i| rebase_paths(i, from, to)),
        _ => {}
    }
}

/// `p` (relative to `from`, or absolute) as seen from `to`: relative when both folders
/// can be made absolute, else absolute.
pub(crate) fn rebase(p: &str, from: &Path, to: &Path) -> String {
    let path = Path::new(p);
    if path.is_absolute() {
        return p.to_string();
    }
    let target = normalize(&absolute(from).join(path));
    let base = normalize(&absolute(to));
    relative_to(&target, &base)
        .unwrap_or(target)
        .to_string_lossy()
        .replace('\\', "/")
}

fn absolute(p: &Path) -> PathBuf {
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        std::env::current_dir().unwrap_or_default().join(p)
    }
}

/// Removes `.` and resolves `..` lexically.
fn normalize(p: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            c => out.push(c),
        }
    }
    out
}

fn relative_to(target: &Path, base: &Path) -> Option<PathBuf> {
    let t: Vec<_> = target.components().collect();
    let b: Vec<_> = base.components().collect();
    if t.first() != b.first() {
        return None;
    }
    let common = t.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut out = PathBuf::new();
    for _ in common..b.len() {
        out.push("..");
    }
    for c in &t[common..] {
        out.push(c);
    }
    Some(out)
}
