//! glTF 2.0 (`.gltf`, `.glb`) as a scene, read by the `gltf` crate.
//!
//! The default scene's node hierarchy is walked (each node's matrix or TRS composed
//! with its parents'); every triangle primitive of a node's mesh becomes one object
//! `{ type = "mesh", path = "model.glb", mesh = M, primitive = P, transform = [...] }`
//! that the scene reader loads from the file itself, so `irradia convert` writes a
//! small TOML that points at the original. Images embedded in the file are bitmaps
//! `{ filename = "model.glb", image = N }`; external images are referred to by their
//! own file name. Materials ([`materials`]) become `principled` BSDFs; the first
//! camera and the `KHR_lights_punctual` lights are [`view`]'s. glTF is right-handed
//! with +Y up, as Irradia, so nothing is mirrored.
//!
//! Errors name the file and the mesh, primitive or accessor; what Irradia does not
//! render (points and lines, unsupported extensions, a second camera, ...) is a warning.

pub mod materials;
pub mod view;

pub use irradia_geometry::io::gltf::GltfFile;
pub use irradia_geometry::io::MeshFileError;

use crate::model::{self, Bounds};
use crate::Imported;
use glam::{Mat4, Vec3};
use irradia_scene::file::tree::Node;
use irradia_scene::SceneError;
use std::path::Path;

/// Extensions whose meaning Irradia reads.
const READ_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_texture_transform",
    "KHR_materials_emissive_strength",
    "KHR_materials_transmission",
    "KHR_materials_ior",
];

/// Imports `path`.
pub fn import(path: &Path) -> Result<Imported, SceneError> {
    let bytes = crate::read_bytes(path)?;
    parse_bytes(&bytes, path)
}

/// Imports glTF or GLB bytes as if read from `origin` (external buffers and images
/// are resolved relative to `origin`'s folder, and objects refer to `origin`).
pub fn parse_bytes(bytes: &[u8], origin: &Path) -> Result<Imported, SceneError> {
    let file = GltfFile::from_bytes(bytes, origin).map_err(model::mesh_error)?;
    let warn = |field: &str, msg: String| SceneError::input(field, msg).with_file(origin);
    let mut warnings = Vec::new();
    for ext in file.document.extensions_used() {
        if !READ_EXTENSIONS.contains(&ext) {
            warnings.push(warn(
                "extensionsUsed",
                format!("extension {ext} is not read (the scene renders without it)"),
            ));
        }
    }
    let dir = origin.parent().unwrap_or(Path::new(""));
    let name = model::rel_name(origin, dir);
    let mut mats = materials::Materials::new(&file, &name, dir);
    let mut tree = Node::table(0);
    let mut bounds = Bounds::default();
    let mut view = view::View::default();

    // The nodes to draw, with their world matrices: the default scene's, else the
    // first scene's, else every root node.
    let roots: Vec<gltf::Node> = match file
        .document
        .default_scene()
        .or_else(|| file.document.scenes().next())
    {
        Some(s) => s.nodes().collect(),
        None => {
            let mut child = vec![false; file.document.nodes().len()];
            for n in file.document.nodes() {
                for c in n.children() {
                    child[c.index()] = true;
                }
            }
            file.document
                .nodes()
                .filter(|n| !child[n.index()])
                .collect()
        }
    };
    let mut stack: Vec<(gltf::Node, Mat4, usize)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, Mat4::IDENTITY, 0))
        .collect();
    let mut visits = 0usize;
    while let Some((node, parent, depth)) = stack.pop() {
        visits += 1;
        if depth > 256 || visits > 1_000_000 {
            return Err(warn(
                &format!("node {}", node.index()),
                "the node hierarchy is too deep or cyclic".into(),
            ));
        }
        let local = Mat4::from_cols_array_2d(&node.transform().matrix());
        let world = parent * local;
        if !world.is_finite() {
            return Err(warn(
                &format!("node {}", node.index()),
                "its transform is not finite".into(),
            ));
        }
        if let Some(mesh) = node.mesh() {
            for prim in mesh.primitives() {
                let here = format!("mesh {}, primitive {}", mesh.index(), prim.index());
                use gltf::mesh::Mode;
                if !matches!(
                    prim.mode(),
                    Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
                ) {
                    warnings.push(warn(
                        &here,
                        format!(
                            "{:?} primitives are not rendered (only triangles)",
                            prim.mode()
                        ),
                    ));
                    continue;
                }
                let Some(pos) = prim.get(&gltf::Semantic::Positions) else {
                    return Err(warn(
                        &here,
                        "the primitive has no POSITION attribute".into(),
                    ));
                };
                file.check_primitive(&prim, &here)
                    .map_err(model::mesh_error)?;
                add_bounds(&file, &prim, &pos, &world, &mut bounds);
                let colored = prim.get(&gltf::Semantic::Colors(0)).is_some();
                let material = mats.material(&prim.material(), colored, &mut warnings, origin);
                let mut obj = Node::table(0);
                obj.put("type", "mesh", 0)
                    .put("path", name.as_str(), 0)
                    .put("mesh", mesh.index() as i64, 0)
                    .put("primitive", prim.index() as i64, 0)
                    .put("material", material, 0);
                if let Some(n) = mesh.name().or(node.name()) {
                    obj.put("name", n, 0);
                }
                if let Some(t) = model::matrix_transform(&world) {
                    obj.set("transform", t);
                }
                tree.push("objects", obj);
            }
        }
        if let Some(cam) = node.camera() {
            view.camera(&cam, &world, &mut warnings, origin);
        }
        if let Some(light) = node.light() {
            view.light(&light, &world, &mut warnings, origin);
        }
        for c in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((c, world, depth + 1));
        }
    }
    if tree.get("objects").is_none() {
        return Err(warn("", "the scene has no triangle meshes".into()));
    }
    let lit = mats.emissive;
    mats.write(&mut tree);
    view.write(&mut tree);
    let mut notes = Vec::new();
    model::complete_bare_model(&mut tree, bounds, lit, &mut notes);
    Ok(Imported {
        tree,
        text: String::new(),
        origin: origin.to_path_buf(),
        warnings,
        notes,
    })
}

/// Grows `bounds` by the POSITION accessor's box (its `min` and `max`, required by
/// the format; else its values) carried by `world`.
fn add_bounds(
    file: &GltfFile,
    prim: &gltf::Primitive,
    pos: &gltf::Accessor,
    world: &Mat4,
    bounds: &mut Bounds,
) {
    let v3 = |v: Option<gltf::json::Value>| -> Option<Vec3> {
        let a = v?;
        let a = a.as_array()?;
        Some(Vec3::new(
            a.first()?.as_f64()? as f32,
            a.get(1)?.as_f64()? as f32,
            a.get(2)?.as_f64()? as f32,
        ))
    };
    let (lo, hi) = match (v3(pos.min()), v3(pos.max())) {
        (Some(lo), Some(hi)) => (lo, hi),
        _ => {
            let mut b = Bounds::default();
            let reader = prim.reader(|buf| file.buffers.get(buf.index()).map(|d| &d.0[..]));
            for p in reader.read_positions().into_iter().flatten() {
                b.add(Vec3::from(p));
            }
            if b.is_empty() {
                return;
            }
            (b.min, b.max)
        }
    };
    for k in 0..8 {
        let c = Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        );
        bounds.add(world.transform_point3(c));
    }
}
