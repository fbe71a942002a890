//! What the model importers (OBJ, glTF, PLY) share: tree-building helpers, and the
//! camera and light a bare model gets.
//!
//! A model file often holds geometry only. When it brings no camera, the importer adds
//! one framing the model: a 3/4 view from the front (+z), right (+x) and above (+y),
//! looking at the centre of the bounding box, far enough that the bounding sphere fits
//! the field of view (40° across the image's shorter side, `fov_axis = "smaller"`).
//! When it brings no light (no light source and no emissive material), the importer
//! adds a studio's two lights and renders with the path tracer: a directional key light
//! from the upper left of the framing view (irradiance [`KEY_IRRADIANCE`]), which gives
//! the surface its shape, and a constant environment ([`FILL_RADIANCE`]) that fills the
//! shadows, so that no side is black and no side is flat. Each addition is one line of
//! [`Imported::notes`].
//!
//! [`Imported::notes`]: crate::Imported::notes

use glam::{Mat4, Vec3};
use irradia_scene::file::tree::{Node, Value};
use irradia_scene::SceneError;
use std::path::Path;

/// The field of view (degrees, across the shorter image side) of a framing camera.
pub const FRAMING_FOV: f32 = 40.0;

/// The irradiance of a bare model's key light (a white Lambert surface facing it
/// reflects radiance 2.5 / π ≈ 0.8).
pub const KEY_IRRADIANCE: f64 = 2.5;

/// The radiance of a bare model's fill (a constant environment, also its background).
pub const FILL_RADIANCE: f64 = 0.3;

/// The direction a bare model's key light travels: from the upper left of the framing
/// camera's view, a little in front of the model (world y up, camera on the +z side).
pub fn key_light_direction() -> Vec3 {
    -Vec3::new(-0.6, 1.0, 0.7).normalize()
}

/// The direction from the model's centre to a framing camera.
pub fn framing_direction() -> Vec3 {
    Vec3::new(0.55, 0.45, 1.0).normalize()
}

/// An `f32` as the `f64` with the same shortest decimal form (0.8, not
/// 0.800000011920929), so that converted files read as the source wrote them.
pub fn num(x: f32) -> f64 {
    if x == 0.0 {
        return 0.0;
    }
    x.to_string().parse().unwrap_or(x as f64)
}

/// `[x, y, z]`.
pub fn vec3(v: Vec3) -> Node {
    Node::new([num(v.x), num(v.y), num(v.z)], 0)
}

/// A colour `[r, g, b]` (or one number when grey).
pub fn color(c: [f32; 3]) -> Node {
    if c[0] == c[1] && c[1] == c[2] {
        Node::new(num(c[0]), 0)
    } else {
        Node::new([num(c[0]), num(c[1]), num(c[2])], 0)
    }
}

/// A transform list of one `{ matrix = [[...], [...], [...]] }` step (rows of the
/// affine part of `m`); `None` for the identity.
pub fn matrix_transform(m: &Mat4) -> Option<Node> {
    if m.abs_diff_eq(Mat4::IDENTITY, 0.0) {
        return None;
    }
    let rows: Vec<Node> = (0..3)
        .map(|r| {
            let row = m.row(r);
            Node::new([num(row.x), num(row.y), num(row.z), num(row.w)], 0)
        })
        .collect();
    let mut step = Node::table(0);
    step.set("matrix", Node::new(rows, 0));
    Some(Node::new(vec![step], 0))
}

/// A file name as the tree writes it: relative to the scene file's folder `dir` when
/// it lies inside it, with `/` separators.
pub fn rel_name(file: &Path, dir: &Path) -> String {
    let rel = file.strip_prefix(dir).unwrap_or(file);
    rel.to_string_lossy().replace('\\', "/")
}

/// Axis-aligned bounds, grown point by point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    pub min: Vec3,
    pub max: Vec3,
}

impl Default for Bounds {
    fn default() -> Self {
        Bounds {
            min: Vec3::splat(f32::INFINITY),
            max: Vec3::splat(f32::NEG_INFINITY),
        }
    }
}

impl Bounds {
    pub fn add(&mut self, p: Vec3) {
        if p.is_finite() {
            self.min = self.min.min(p);
            self.max = self.max.max(p);
        }
    }
    pub fn is_empty(&self) -> bool {
        !matches!(self.min.x.partial_cmp(&self.max.x), Some(o) if o.is_le())
    }
    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }
    /// The radius of the bounding sphere around the box's centre.
    pub fn radius(&self) -> f32 {
        0.5 * (self.max - self.min).length()
    }
}

/// Adds what a bare model lacks: a camera framing `bounds` when `tree` has none; when
/// it has no lights, the path tracer, and a constant environment light unless
/// `emissive` (some material emits). Each addition is a line in `notes`.
pub fn complete_bare_model(
    tree: &mut Node,
    bounds: Bounds,
    emissive: bool,
    notes: &mut Vec<String>,
) {
    if tree.get("camera").is_none() {
        let (center, radius) = if bounds.is_empty() {
            (Vec3::ZERO, 1.0)
        } else {
            (bounds.center(), bounds.radius().max(1e-6))
        };
        // The bounding sphere seen from distance d spans asin(r / d) either side of
        // the axis: d = r / sin(fov / 2), and 5% to spare.
        let half = (FRAMING_FOV.to_radians() * 0.5).sin();
        let d = 1.05 * radius / half;
        let eye = center + d * framing_direction();
        let mut cam = Node::table(0);
        cam.set("eye", vec3(eye))
            .set("look_at", vec3(center))
            .put("fov", FRAMING_FOV as f64, 0)
            .put("fov_axis", "smaller", 0);
        tree.set("camera", cam);
        notes.push(format!(
            "the file has no camera: added one framing the model (bounds {:?} to {:?}), \
             a 3/4 view from the front-right-above at {FRAMING_FOV}° fov",
            bounds.min.to_array(),
            bounds.max.to_array()
        ));
    }
    let has_lights =
        matches!(tree.get("lights").map(|l| &l.value), Some(Value::Array(a)) if !a.is_empty());
    if has_lights {
        return;
    }
    if !emissive {
        let mut key = Node::table(0);
        key.put("type", "directional", 0)
            .set("direction", vec3(key_light_direction()))
            .put("irradiance", KEY_IRRADIANCE, 0);
        tree.push("lights", key);
        let mut fill = Node::table(0);
        fill.put("type", "constant", 0)
            .put("radiance", FILL_RADIANCE, 0);
        tree.push("lights", fill);
    }
    let mut render = match tree.get("render") {
        Some(r) => r.clone(),
        None => Node::table(0),
    };
    render
        .put("integrator", "path", 0)
        .put("spp", 16i64, 0)
        .put("max_depth", 8i64, 0);
    tree.set("render", render);
    notes.push(if emissive {
        "the file has no light sources but emissive materials: rendered with the path tracer (16 spp), which they light".to_string()
    } else {
        format!(
            "the file has no light: added a key light (directional, irradiance {KEY_IRRADIANCE}, \
             from the upper left) and a constant environment fill (radiance {FILL_RADIANCE}), \
             rendered with the path tracer (16 spp)"
        )
    });
}

/// A mesh file's error as the importer reports it: at its line and column when it has
/// them, naming the file.
pub fn mesh_error(e: irradia_geometry::io::MeshFileError) -> SceneError {
    let field = e.field.clone().unwrap_or_default();
    let mut err = SceneError::input(field, e.message.clone()).with_file(&e.path);
    if let Some(line) = e.line {
        err = err.at(line, e.column.unwrap_or(1));
    }
    err
}
