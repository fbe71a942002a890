//! Scenes for the two-pass image (`crate::two_pass`): the diffuse patches that the
//! radiosity pass solves, plus smooth specular objects (mirrors, glass) that only the
//! second, ray-traced pass sees as such.
//!
//! What the diffuse pass makes of a specular object (the first pass of Wallace, Cohen
//! and Greenberg 1987 without their extra "mirror world" form factors):
//! - a mirror is opaque: its facets enter the radiosity mesh as black patches
//!   (reflectance 0, no emission), so it casts its shadow; the light it would reflect
//!   onto diffuse surfaces is missing;
//! - glass is left out: light passes it unchanged, so it casts no shadow; the caustic
//!   it would focus is missing too.
//!
//! These black stand-ins are hidden from the second pass, which intersects the smooth
//! shape itself.

use crate::mesh::{spec, PatchSpec};
use crate::scenes;
use glam::{DVec3, Vec3};
use irradia_geometry::shapes::Sphere;
use irradia_geometry::Shape;
use std::sync::Arc;

/// How a specular object scatters light in the second pass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpecularMaterial {
    /// A perfect mirror reflecting this fraction per channel.
    Mirror { reflectance: [f64; 3] },
    /// A smooth dielectric: Fresnel reflection and Snell refraction, with `transmittance`
    /// applied to each refracted ray (1 = clear glass).
    Glass { ior: f64, transmittance: [f64; 3] },
}

/// A specular object: a shape in world space and its material.
#[derive(Clone, Debug)]
pub struct SpecularObject {
    pub name: String,
    pub shape: Arc<dyn Shape>,
    pub material: SpecularMaterial,
}

impl SpecularObject {
    /// Whether the diffuse pass sees the object as a black occluder (mirrors) or not at
    /// all (glass).
    pub fn occludes_in_diffuse_pass(&self) -> bool {
        matches!(self.material, SpecularMaterial::Mirror { .. })
    }

    /// The black patches that stand for the object in the diffuse pass: its facets
    /// (`detail` segments around a curved surface), reflecting and emitting nothing.
    pub fn stand_in(&self, detail: u32) -> Vec<PatchSpec> {
        let Some(f) = self.shape.facets(detail) else {
            return Vec::new();
        };
        f.faces
            .iter()
            .enumerate()
            .map(|(k, face)| {
                let corners: Vec<DVec3> = face
                    .iter()
                    .map(|&i| f.vertices[i as usize].as_dvec3())
                    .collect();
                spec(
                    &format!("{} facet {k}", self.name),
                    &corners,
                    [0.0; 3],
                    [0.0; 3],
                )
            })
            .collect()
    }
}

/// Patches for the radiosity pass and the specular objects of the second pass.
#[derive(Clone, Debug)]
pub struct SpecularScene {
    /// The diffuse patches, then the stand-ins of the opaque specular objects.
    pub patches: Vec<PatchSpec>,
    pub objects: Vec<SpecularObject>,
    /// `patches[first_stand_in..]` are stand-ins, hidden in the two-pass image.
    pub first_stand_in: usize,
}

/// Segments around a curved specular object's stand-in.
pub const STAND_IN_DETAIL: u32 = 16;

impl SpecularScene {
    /// Appends the stand-ins of the opaque objects to the diffuse patches.
    pub fn new(diffuse: Vec<PatchSpec>, objects: Vec<SpecularObject>) -> Self {
        let first_stand_in = diffuse.len();
        let mut patches = diffuse;
        for o in objects.iter().filter(|o| o.occludes_in_diffuse_pass()) {
            patches.extend(o.stand_in(STAND_IN_DETAIL));
        }
        Self {
            patches,
            objects,
            first_stand_in,
        }
    }

    /// Whether `PatchSpec` number `source` is a stand-in (hidden in the two-pass image).
    pub fn is_stand_in(&self, source: u32) -> bool {
        source as usize >= self.first_stand_in
    }
}

/// The built-in scenes with specular objects (`irradia radiosity --builtin NAME`).
pub const BUILTINS: &[(&str, &str)] = &[(
    "cornell-specular",
    "the measured Cornell box without blocks, with a mirror sphere and a glass sphere",
)];

pub fn builtin(name: &str) -> Option<SpecularScene> {
    match name {
        "cornell-specular" => Some(cornell_specular()),
        _ => None,
    }
}

/// The measured Cornell box (without its blocks) with a perfect-mirror sphere at the
/// back on the red side and a clear glass sphere (index 1.5) at the front on the green
/// side, both of radius 100 mm resting on the floor (the arrangement of Jensen's
/// photon-mapping Cornell box).
pub fn cornell_specular() -> SpecularScene {
    let sphere = |c: Vec3| -> Arc<dyn Shape> { Arc::new(Sphere::new(c, 100.0)) };
    SpecularScene::new(
        scenes::cornell_empty(),
        vec![
            SpecularObject {
                name: "mirror sphere".into(),
                shape: sphere(Vec3::new(385.0, 100.0, 370.0)),
                material: SpecularMaterial::Mirror {
                    reflectance: [1.0; 3],
                },
            },
            SpecularObject {
                name: "glass sphere".into(),
                shape: sphere(Vec3::new(175.0, 100.0, 190.0)),
                material: SpecularMaterial::Glass {
                    ior: 1.5,
                    transmittance: [1.0; 3],
                },
            },
        ],
    )
}
