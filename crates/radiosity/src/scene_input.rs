//! Radiosity patches from a ray-tracing `Scene` (a scene file or a built-in of the scene
//! crate): every object's surface as planar polygons (`Shape::facets`, curved surfaces
//! tessellated at `detail` segments per turn), carried to world space by its instance's
//! transform, with the material's diffuse colour as reflectance and its emission
//! (radiance) times π as emitted radiosity.
//!
//! Radiosity handles only the diffuse part: mirror and glass terms are left to the ray
//! tracer (a two-pass image), and a material whose diffuse reflectance reaches 1 is
//! reported by `mesh::validate` with the object's name.

use crate::error::{RadiosityError, Result};
use crate::mesh::PatchSpec;
use glam::{DVec3, Vec2, Vec3};
use irradia_scene::{Scene, Texture};
use std::f64::consts::PI;

/// The scene's surfaces as patch specs. Objects that cannot be faceted (unbounded
/// planes, for example) are skipped and listed in the returned warnings.
pub fn patches_from_scene(scene: &Scene, detail: u32) -> Result<(Vec<PatchSpec>, Vec<String>)> {
    let mut out = Vec::new();
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
        }
    }
    if out.is_empty() {
        return Err(RadiosityError::Input(format!(
            "{src}: no object could be cut into polygons for radiosity"
        )));
    }
    Ok((out, warnings))
}
