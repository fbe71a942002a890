//! glTF cameras and `KHR_lights_punctual` lights.
//!
//! A camera looks down its node's −Z with +Y up. `perspective`: `fov = yfov` (degrees)
//! across the height (`fov_axis = "y"`), `znear` the `near_clip`, and an
//! `aspectRatio` sets the image to 480 pixels high and as wide as the ratio asks.
//! `orthographic`: `height = 2 · ymag`. Only the first camera in the node hierarchy is
//! used (the others are warnings).
//!
//! Lights shine down their node's −Z. glTF's photometric units carry over unchanged,
//! because Irradia's point and spot `intensity` is a radiant intensity (irradiance
//! `I / r²` at distance r) and a directional light's `irradiance` an irradiance: a
//! point or spot of `intensity` candela gives `intensity · color`, a directional light
//! of `intensity` lux gives `irradiance = intensity · color`. A spot's cone is
//! `inner_angle = innerConeAngle`, `outer_angle = outerConeAngle` (degrees; the fall-off
//! between them is smooth in cos θ). `range` is not applied (a warning).

use crate::model::{color, num, vec3};
use glam::{Mat4, Vec3};
use irradia_scene::file::tree::Node;
use irradia_scene::SceneError;
use std::path::Path;

#[derive(Default)]
pub struct View {
    camera: Option<Node>,
    image: Option<Node>,
    pub lights: Vec<Node>,
}

impl View {
    pub fn camera(
        &mut self,
        cam: &gltf::Camera,
        world: &Mat4,
        warnings: &mut Vec<SceneError>,
        origin: &Path,
    ) {
        if self.camera.is_some() {
            warnings.push(
                SceneError::input(
                    format!("camera {}", cam.index()),
                    "only the first camera is used",
                )
                .with_file(origin),
            );
            return;
        }
        let eye = world.transform_point3(Vec3::ZERO);
        let dir = world.transform_vector3(-Vec3::Z).normalize_or_zero();
        let up = world.transform_vector3(Vec3::Y).normalize_or_zero();
        if dir == Vec3::ZERO || up == Vec3::ZERO || dir.cross(up).length() < 1e-6 {
            warnings.push(
                SceneError::input(
                    format!("camera {}", cam.index()),
                    "its node's transform collapses the view: the camera is not used",
                )
                .with_file(origin),
            );
            return;
        }
        let mut c = Node::table(0);
        c.set("eye", vec3(eye))
            .set("look_at", vec3(eye + dir))
            .set("up", vec3(up));
        match cam.projection() {
            gltf::camera::Projection::Perspective(p) => {
                let fov = p.yfov().to_degrees().clamp(1e-3, 179.0);
                c.put("type", "perspective", 0)
                    .put("fov", num(fov), 0)
                    .put("fov_axis", "y", 0);
                if p.znear() > 0.0 && p.znear().is_finite() {
                    c.put("near_clip", num(p.znear()), 0);
                }
                if let Some(a) = p.aspect_ratio().filter(|a| a.is_finite() && *a > 0.0) {
                    let h = 480i64;
                    let w = ((h as f32) * a).round().clamp(1.0, 16384.0) as i64;
                    let mut img = Node::table(0);
                    img.put("width", w, 0).put("height", h, 0);
                    self.image = Some(img);
                }
            }
            gltf::camera::Projection::Orthographic(o) => {
                c.put("type", "orthographic", 0).put(
                    "height",
                    num((2.0 * o.ymag().abs()).max(1e-6)),
                    0,
                );
                if o.znear() > 0.0 && o.znear().is_finite() {
                    c.put("near_clip", num(o.znear()), 0);
                }
            }
        }
        self.camera = Some(c);
    }

    pub fn light(
        &mut self,
        light: &gltf::khr_lights_punctual::Light,
        world: &Mat4,
        warnings: &mut Vec<SceneError>,
        origin: &Path,
    ) {
        use gltf::khr_lights_punctual::Kind;
        let label = format!("light {}", light.index());
        if light.range().is_some() {
            warnings.push(
                SceneError::input(
                    label.as_str(),
                    "range is not applied (the light reaches everywhere)",
                )
                .with_file(origin),
            );
        }
        let c = light.color();
        let i = light.intensity().max(0.0);
        let power = color([c[0] * i, c[1] * i, c[2] * i]);
        let position = world.transform_point3(Vec3::ZERO);
        let dir = world.transform_vector3(-Vec3::Z).normalize_or_zero();
        let dir = if dir == Vec3::ZERO { -Vec3::Z } else { dir };
        let mut l = Node::table(0);
        match light.kind() {
            Kind::Point => {
                l.put("type", "point", 0)
                    .set("position", vec3(position))
                    .set("intensity", power);
            }
            Kind::Directional => {
                l.put("type", "directional", 0)
                    .set("direction", vec3(dir))
                    .set("irradiance", power);
            }
            Kind::Spot {
                inner_cone_angle,
                outer_cone_angle,
            } => {
                let outer = outer_cone_angle.to_degrees().clamp(1e-2, 90.0);
                let inner = inner_cone_angle.to_degrees().clamp(1e-2, outer);
                l.put("type", "spot", 0)
                    .set("position", vec3(position))
                    .set("direction", vec3(dir))
                    .set("intensity", power)
                    .put("outer_angle", num(outer), 0)
                    .put("inner_angle", num(inner), 0);
            }
        }
        self.lights.push(l);
    }

    pub fn write(self, tree: &mut Node) {
        if let Some(c) = self.camera {
            tree.set("camera", c);
        }
        if let Some(i) = self.image {
            tree.set("image", i);
        }
        for l in self.lights {
            tree.push("lights", l);
        }
    }
}
