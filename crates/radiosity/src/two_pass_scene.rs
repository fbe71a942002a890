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
//!
//! Scene files ([`from_scene`]) declare specular objects through their materials; the
//! rule that decides which objects are mirrors, which are glass and which stay diffuse
//! is [`specular_material`]'s.

use crate::error::{RadiosityError, Result};
use crate::mesh::{spec, PatchSpec};
use crate::scene_input;
use crate::scenes;
use glam::{Affine3A, DVec3, Vec2, Vec3};
use irradia_core::{Aabb, Ray};
use irradia_geometry::shapes::Sphere;
use irradia_geometry::{Facets, Hit, Instance, Shape, Span};
use irradia_scene::{Material, Scene, Texture};
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

/// What the two-pass display makes of a scene-file material: `Some` for a mirror or
/// glass (traced in pass two), `None` for a diffuse surface (solved by radiosity with
/// `color × diffuse`), with notes on the parts of the material that are left out.
///
/// The rule, with `ρ_d` the largest channel of the diffuse reflectance `color ×
/// diffuse`, `k_r` the largest channel of `reflection` and `k_t = transmission`:
/// - a material that emits light is diffuse (radiosity needs its lights as patches);
/// - a material with `max(k_r, k_t) = 0`, or whose diffuse part is the larger
///   (`ρ_d > max(k_r, k_t)`), is diffuse; its mirror and transmitted parts are left
///   out (noted);
/// - otherwise, with `k_t > 0`, it is glass: a smooth dielectric of index `ior` whose
///   reflection follows Fresnel's equations (whatever `reflection` and `fresnel` say)
///   and whose refracted rays are multiplied by `transmission × filter` (`filter`
///   defaults to the base colour, as for the ray tracer);
/// - otherwise it is a mirror reflecting `reflection` (per channel) at every angle
///   (`fresnel` is ignored, noted).
///
/// A specular material's diffuse part, if any, is left out (noted): pass two has no
/// surface that is both traced and solved.
pub fn specular_material(m: &Material) -> (Option<SpecularMaterial>, Vec<String>) {
    let colour = match &m.color {
        Texture::Solid(c) => *c,
        other => other.eval(Vec3::ZERO, Vec2::ZERO),
    };
    let rho_d = (colour.r.max(colour.g).max(colour.b) * m.diffuse) as f64;
    let k_r = m.reflection.r.max(m.reflection.g).max(m.reflection.b) as f64;
    let k_t = m.transmission as f64;
    let specular = k_r.max(k_t);
    let mut notes = Vec::new();
    let emits = m.emission.r.max(m.emission.g).max(m.emission.b) > 0.0;
    if specular <= 0.0 {
        return (None, notes);
    }
    if emits || rho_d > specular {
        notes.push(format!(
            "solved as a diffuse surface ({}); its {} left out of the two-pass image",
            if emits {
                "it emits light".to_string()
            } else {
                format!("diffuse reflectance {rho_d:.3} > specular {specular:.3}")
            },
            match (k_r > 0.0, k_t > 0.0) {
                (true, true) => "mirror reflection and transmission are",
                (true, false) => "mirror reflection is",
                _ => "transmission is",
            }
        ));
        return (None, notes);
    }
    if rho_d > 0.0 {
        notes.push(format!(
            "traced as {} in pass two; its diffuse part (reflectance {rho_d:.3}) is left out",
            if k_t > 0.0 { "glass" } else { "a mirror" }
        ));
    }
    let material = if k_t > 0.0 {
        let f = m.filter_color.unwrap_or(colour);
        SpecularMaterial::Glass {
            ior: m.ior as f64,
            transmittance: [f.r, f.g, f.b].map(|c| k_t * c as f64),
        }
    } else {
        if m.fresnel {
            notes.push(
                "fresnel = true is ignored: the two-pass mirror reflects `reflection` at every angle"
                    .into(),
            );
        }
        SpecularMaterial::Mirror {
            reflectance: [m.reflection.r, m.reflection.g, m.reflection.b].map(|c| c as f64),
        }
    };
    (Some(material), notes)
}

/// A scene file (or ray-tracer built-in) as a two-pass scene: objects whose material
/// [`specular_material`] calls a mirror or glass become [`SpecularObject`]s (their shape
/// carried to world space by the object's transform), everything else becomes
/// radiosity patches as [`scene_input::patches_with_objects`] makes them (`detail`
/// segments around curved surfaces). Mirrors also enter the radiosity pass as black
/// stand-ins (their facets), glass does not, as for the built-in scenes.
///
/// Returns the scene, the object index of each patch (for [`scene_input::check_closed`])
/// and warnings. A CSG object whose leaves have their own materials stays diffuse (with
/// a warning if any of them is specular). An unbounded specular object (a mirror plane)
/// is traced in pass two but has no stand-in.
pub fn from_scene(scene: &Scene, detail: u32) -> Result<(SpecularScene, Vec<usize>, Vec<String>)> {
    let (specs, owners, mut warnings) = scene_input::patches_with_objects(scene, detail)?;
    let src = scene
        .source
        .as_ref()
        .map(|p| p.display().to_string())
        .unwrap_or_else(|| "scene".into());
    let mut kinds: Vec<Option<SpecularMaterial>> = Vec::with_capacity(scene.objects.len());
    for (oi, obj) in scene.objects.iter().enumerate() {
        let Some(m) = scene.materials.get(obj.material as usize) else {
            kinds.push(None);
            continue;
        };
        let (mut kind, notes) = specular_material(m);
        let at = format!("{src}: object {oi} ('{}'), material '{}'", obj.name, m.name);
        if !obj.leaf_materials.is_empty() {
            let leaf_specular = obj.leaf_materials.iter().any(|&l| {
                scene
                    .materials
                    .get(l as usize)
                    .is_some_and(|lm| specular_material(lm).0.is_some())
            });
            if kind.is_some() || leaf_specular {
                warnings.push(format!(
                    "{at}: a CSG object with several materials is solved as diffuse; its mirror or \
                     glass parts are left out of the two-pass image"
                ));
            }
            kind = None;
        } else {
            warnings.extend(notes.into_iter().map(|n| format!("{at}: {n}")));
        }
        kinds.push(kind);
    }
    let mut patches = Vec::new();
    let mut patch_owners = Vec::new();
    let mut stand_ins = Vec::new();
    let mut stand_in_owners = Vec::new();
    for (s, &oi) in specs.into_iter().zip(&owners) {
        match kinds[oi] {
            None => {
                patches.push(s);
                patch_owners.push(oi);
            }
            Some(SpecularMaterial::Mirror { .. }) => {
                stand_ins.push(PatchSpec {
                    name: format!("{} (black stand-in of a mirror)", s.name),
                    reflectance: [0.0; 3],
                    emission: [0.0; 3],
                    ..s
                });
                stand_in_owners.push(oi);
            }
            Some(SpecularMaterial::Glass { .. }) => {}
        }
    }
    if patches.is_empty() {
        return Err(RadiosityError::Input(format!(
            "{src}: every object is a mirror or glass; the radiosity pass needs diffuse surfaces"
        )));
    }
    let first_stand_in = patches.len();
    patches.extend(stand_ins);
    patch_owners.extend(stand_in_owners);
    let objects = scene
        .objects
        .iter()
        .zip(scene.accel.instances())
        .zip(&kinds)
        .filter_map(|((obj, inst), kind)| {
            kind.map(|material| SpecularObject {
                name: obj.name.clone(),
                shape: world_shape(inst),
                material,
            })
        })
        .collect();
    Ok((
        SpecularScene {
            patches,
            objects,
            first_stand_in,
        },
        patch_owners,
        warnings,
    ))
}

/// The instance's shape in world space: the shape itself when the transform is the
/// identity, else the shape behind its transform.
pub fn world_shape(inst: &Instance) -> Arc<dyn Shape> {
    if *inst.to_world() == Affine3A::IDENTITY {
        inst.shape.clone()
    } else {
        Arc::new(Placed(inst.clone()))
    }
}

/// A shape placed in the world by an instance transform, itself a shape in world
/// coordinates (pass two builds its own acceleration structure over untransformed
/// shapes).
#[derive(Debug)]
struct Placed(Instance);

impl Shape for Placed {
    fn kind(&self) -> &'static str {
        self.0.shape.kind()
    }
    fn bounds(&self) -> Aabb {
        self.0.bounds()
    }
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        self.0.intersect(ray, t_max)
    }
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.0.occluded(ray, t_max)
    }
    fn is_solid(&self) -> bool {
        self.0.shape.is_solid()
    }
    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        self.0.spans(ray, out)
    }
    fn facets(&self, detail: u32) -> Option<Facets> {
        let mut f = self.0.shape.facets(detail)?;
        let m = self.0.to_world();
        for v in &mut f.vertices {
            *v = m.transform_point3(*v);
        }
        let normal_to_world = self.0.to_object().matrix3.transpose();
        for n in &mut f.normals {
            *n = Vec3::from(normal_to_world.mul_vec3a((*n).into())).normalize();
        }
        // A mirroring transform turns counter-clockwise loops clockwise.
        if m.matrix3.determinant() < 0.0 {
            for face in &mut f.faces {
                face.reverse();
            }
        }
        Some(f)
    }
    fn take_warnings(&self) -> Vec<String> {
        self.0.shape.take_warnings()
    }
}
