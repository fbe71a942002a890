//! Radiosity patches from a ray-tracing `Scene` (a scene file or a built-in of the scene
//! crate): every object's surface as planar polygons (`Shape::facets`, curved surfaces
//! tessellated at `detail` segments per turn), carried to world space by its instance's
//! transform, with the material's diffuse colour as reflectance and its emission
//! (radiance) times π as emitted radiosity.
//!
//! Radiosity handles only the diffuse part: mirror and glass terms are left to the ray
//! tracer (a two-pass image). Input that radiosity cannot solve is reported with the
//! scene file, line, column and field, as the scene loader reports its own errors: a
//! material whose diffuse reflectance (`color` × `diffuse`) reaches 1, a scene where no
//! material emits, and (with [`check_closed`]) an enclosure with an open edge.

use crate::error::{RadiosityError, Result};
use crate::mesh::PatchSpec;
use glam::{DVec3, Vec2, Vec3};
use irradia_scene::{Scene, Texture};
use std::f64::consts::PI;

/// The scene's surfaces as patch specs. Objects that cannot be faceted (unbounded
/// planes, for example) are skipped and listed in the returned warnings.
pub fn patches_from_scene(scene: &Scene, detail: u32) -> Result<(Vec<PatchSpec>, Vec<String>)> {
    let (specs, _, warnings) = patches_with_objects(scene, detail)?;
    Ok((specs, warnings))
}

/// As [`patches_from_scene`], with the index of the object each patch came from.
pub fn patches_with_objects(
    scene: &Scene,
    detail: u32,
) -> Result<(Vec<PatchSpec>, Vec<usize>, Vec<String>)> {
    let mut out = Vec::new();
    let mut objects = Vec::new();
    let mut warnings = Vec::new();
    let src = scene
        .source
        .as_ref()
        .map(|p| p.display().to_string())
        .unwrap_or_else(|| "scene".into());
    for (oi, (obj, inst)) in scene
        .objects
        .iter()
        .zip(scene.accel.instances())
        .enumerate()
    {
        let Some(f) = inst.shape.facets(detail) else {
            warnings.push(format!(
                "{src}: object {oi} ('{}', a {}) cannot be cut into polygons (unbounded?); radiosity ignores it",
                obj.name,
                inst.shape.kind()
            ));
            continue;
        };
        let m = scene.materials.get(obj.material as usize).ok_or_else(|| {
            RadiosityError::Input(format!(
                "{src}: object {oi} ('{}') has no material {}",
                obj.name, obj.material
            ))
        })?;
        let colour = match &m.color {
            Texture::Solid(c) => *c,
            other => other.eval(Vec3::ZERO, Vec2::ZERO),
        };
        let rho = [
            (colour.r * m.diffuse) as f64,
            (colour.g * m.diffuse) as f64,
            (colour.b * m.diffuse) as f64,
        ];
        if let Some(c) = rho.iter().position(|&r| r >= 1.0) {
            let field = if matches!(m.color, Texture::Solid(_))
                && colour.r.max(colour.g).max(colour.b) < 1.0
            {
                "diffuse"
            } else {
                "color"
            };
            return Err(input(
                scene,
                &["materials", &m.name, field],
                format!(
                    "the {} diffuse reflectance (color × diffuse = {}) of material '{}' (object {oi}, '{}') \
                     is at or above 1: such a surface reflects at least all the light it receives and \
                     the radiosity equation has no finite solution; use a colour or diffuse factor that \
                     gives less than 1 (real materials stay below about 0.95)",
                    ["red", "green", "blue"][c],
                    rho[c],
                    m.name,
                    obj.name
                ),
            ));
        }
        let e = [
            m.emission.r as f64 * PI,
            m.emission.g as f64 * PI,
            m.emission.b as f64 * PI,
        ];
        let to_world = inst.to_world();
        for (fi, face) in f.faces.iter().enumerate() {
            let corners: Vec<DVec3> = face
                .iter()
                .map(|&k| to_world.transform_point3(f.vertices[k as usize]).as_dvec3())
                .collect();
            out.push(PatchSpec {
                name: format!("{src}: object {oi} ('{}') face {fi}", obj.name),
                corners,
                reflectance: rho,
                emission: e,
            });
            objects.push(oi);
        }
    }
    if out.is_empty() {
        return Err(input(
            scene,
            &["objects"],
            "no object could be cut into polygons for radiosity".into(),
        ));
    }
    if !out.iter().any(|s| s.emission.iter().any(|&e| e > 0.0)) {
        return Err(input(
            scene,
            &["materials"],
            "no object's material emits light, so every radiosity would be 0; give the material of \
             a light-source object an `emission` (radiance, e.g. emission = [10, 10, 10])"
                .into(),
        ));
    }
    Ok((out, objects, warnings))
}

/// An input error at a field of the scene file: `file:line:column: field: message`
/// (the position found by parsing the file again with the scene crate's positioned
/// tree; without a file or position, `scene: field: message`).
fn input(scene: &Scene, path: &[&str], message: String) -> RadiosityError {
    let field = field_name(path);
    let Some(file) = scene.source.as_ref() else {
        return RadiosityError::Input(format!("scene: {field}: {message}"));
    };
    let at = position(file, path)
        .map(|(l, c)| format!(":{l}:{c}"))
        .unwrap_or_default();
    RadiosityError::Input(format!("{}{at}: {field}: {message}", file.display()))
}

/// `["objects", "3"]` → `objects[3]`; `["materials", "white", "color"]` →
/// `materials.white.color`.
fn field_name(path: &[&str]) -> String {
    let mut s = String::new();
    for p in path {
        if p.parse::<usize>().is_ok() {
            s.push_str(&format!("[{p}]"));
        } else {
            if !s.is_empty() {
                s.push('.');
            }
            s.push_str(p);
        }
    }
    s
}

/// Line and column of a field in a scene file (the deepest part of `path` found).
fn position(file: &std::path::Path, path: &[&str]) -> Option<(usize, usize)> {
    use irradia_scene::file::tree::{line_col, parse_toml, Value};
    let text = std::fs::read_to_string(file).ok()?;
    let root = match irradia_scene::SceneSyntax::from_path(file).ok()? {
        irradia_scene::SceneSyntax::Toml => parse_toml(&text).ok()?,
        irradia_scene::SceneSyntax::Json => {
            irradia_scene::file::json_tree::parse_json(&text).ok()?
        }
    };
    let mut node = &root;
    let mut pos = None;
    for key in path {
        let next = match (&node.value, key.parse::<usize>()) {
            (Value::Array(items), Ok(i)) => items.get(i).map(|n| (n, n.pos)),
            (Value::Table(entries), _) => entries
                .iter()
                .find(|e| e.key == *key)
                .map(|e| (&e.node, e.key_pos)),
            _ => None,
        };
        let Some((n, p)) = next else { break };
        node = n;
        pos = Some(p);
    }
    pos.map(|p| line_col(&text, p))
}

/// Checks that the patches close an enclosure, as the furnace test and the ambient term
/// of progressive refinement assume: every edge of every patch must be covered by edges
/// of other patches (collinear and overlapping; T-junctions allowed). An open edge is
/// an input error naming the patch (for scene files: the object's file, line and field)
/// and the edge's end points.
pub fn check_closed(specs: &[PatchSpec], objects: Option<(&Scene, &[usize])>) -> Result<()> {
    let scale = specs
        .iter()
        .flat_map(|s| s.corners.iter())
        .fold(0.0f64, |m, c| m.max(c.abs().max_element()))
        .max(1e-300);
    let tol = 1e-6 * scale;
    let edges: Vec<(usize, DVec3, DVec3)> = specs
        .iter()
        .enumerate()
        .flat_map(|(i, s)| {
            (0..s.corners.len())
                .map(move |k| (i, s.corners[k], s.corners[(k + 1) % s.corners.len()]))
        })
        .collect();
    for &(i, a, b) in &edges {
        let d = b - a;
        let len2 = d.length_squared();
        if len2 <= tol * tol {
            continue;
        }
        // Parameter intervals of `ab` covered by other patches' collinear edges.
        let mut cover: Vec<(f64, f64)> = Vec::new();
        for &(j, p, q) in &edges {
            if j == i {
                continue;
            }
            let off = |x: DVec3| (x - a).cross(d).length() / len2.sqrt();
            if off(p) > tol || off(q) > tol {
                continue;
            }
            let (tp, tq) = ((p - a).dot(d) / len2, (q - a).dot(d) / len2);
            let (lo, hi) = (tp.min(tq).max(0.0), tp.max(tq).min(1.0));
            if hi > lo {
                cover.push((lo, hi));
            }
        }
        cover.sort_by(|x, y| x.0.total_cmp(&y.0));
        let eps = tol / len2.sqrt();
        let mut reached = 0.0f64;
        for (lo, hi) in cover {
            if lo > reached + eps {
                break;
            }
            reached = reached.max(hi);
        }
        if reached < 1.0 - eps {
            let gap = a + d * reached;
            let what = format!(
                "the enclosure is open: the edge from ({:.4}, {:.4}, {:.4}) to ({:.4}, {:.4}, {:.4}) of \
                 '{}' is shared by no other surface from ({:.4}, {:.4}, {:.4}) on; a closed room is \
                 assumed here (furnace check, ambient term), so close the gap or leave out the check",
                a.x, a.y, a.z, b.x, b.y, b.z, specs[i].name, gap.x, gap.y, gap.z
            );
            return Err(match objects {
                Some((scene, objs)) => input(scene, &["objects", &objs[i].to_string()], what),
                None => RadiosityError::Input(what),
            });
        }
    }
    Ok(())
}
