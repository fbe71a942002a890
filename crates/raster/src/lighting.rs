//! Local illumination for the pipeline: ambient + Lambert diffuse + Blinn-Phong
//! specular, evaluated per vertex (Gouraud, 1971) or per pixel (Phong, 1975), as in the
//! OpenGL fixed-function pipeline (no 1/pi, no shadows).
//!
//! Lights are given in world space and moved to eye space once per frame
//! ([`EyeLights`]); all shading happens in eye space, where the eye is at the origin.
//!
//! The lights follow the Whitted tracer's conventions (`irradia_render`'s shading):
//! point and spot lights give `I / r²`, spot cones use the one falloff of every
//! integrator ([`irradia_scene::spot_falloff`]), and area lights are replaced by sample
//! points ([`crate::area_lights`]), so a shadow-free scene rasterizes to what the ray
//! tracer draws.

use glam::{Mat4, Vec3};
use irradia_core::Rgb;
use irradia_scene::Light;

/// How colour is computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Shading {
    /// Vertex colours as given, no lighting.
    Unlit,
    /// Lighting evaluated at the vertices, colours interpolated (Gouraud).
    #[default]
    Gouraud,
    /// Normals and positions interpolated, lighting evaluated at every pixel (Phong).
    Phong,
}

/// One light of the pipeline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RasterLight {
    /// Light travelling along `direction` with irradiance `color`.
    Directional { direction: Vec3, color: Rgb },
    /// A point light of intensity `color`; irradiance falls off as 1 / r².
    Point { position: Vec3, color: Rgb },
    /// A point light limited to a cone around unit `direction`: intensity `color` times
    /// [`irradia_scene::spot_falloff`] of the angle from the axis.
    Spot {
        position: Vec3,
        direction: Vec3,
        color: Rgb,
        cos_inner: f32,
        cos_outer: f32,
    },
    /// A small one-sided Lambertian emitter (a sample point of an area light): intensity
    /// `color * cos θ` at angle θ from the unit `normal`, nothing behind it.
    Emitter {
        position: Vec3,
        normal: Vec3,
        color: Rgb,
    },
}

/// The lights of a frame, in world space.
#[derive(Clone, Debug, PartialEq)]
pub struct Lights {
    pub ambient: Rgb,
    pub lights: Vec<RasterLight>,
}

impl Default for Lights {
    /// A dim ambient term and one white light shining down the view axis from behind
    /// the default camera.
    fn default() -> Self {
        Self {
            ambient: Rgb::splat(0.1),
            lights: vec![RasterLight::Directional {
                direction: Vec3::new(-0.3, -0.5, -1.0).normalize(),
                color: Rgb::splat(1.0),
            }],
        }
    }
}

impl Lights {
    /// The scene's lights: point, directional and spot lights as they are; rectangle
    /// and sphere lights as sample points ([`crate::area_lights`]), as many as the
    /// light's `samples` (at most [`crate::area_lights::MAX_POINTS`]).
    pub fn from_scene(lights: &[Light], ambient: Rgb) -> Self {
        Self {
            ambient,
            lights: lights
                .iter()
                .flat_map(|l| crate::area_lights::scene_light(l, None))
                .collect(),
        }
    }

    /// [`Lights::from_scene`] with every area light cut into about `points` sample
    /// points whatever its `samples`.
    pub fn from_scene_with_points(lights: &[Light], ambient: Rgb, points: u32) -> Self {
        Self {
            ambient,
            lights: lights
                .iter()
                .flat_map(|l| crate::area_lights::scene_light(l, Some(points)))
                .collect(),
        }
    }
}

/// Surface reflectance for the pipeline's lighting model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Multiplies the vertex colour for the diffuse and ambient terms.
    pub diffuse: Rgb,
    pub specular: Rgb,
    /// Blinn-Phong exponent.
    pub shininess: f32,
    /// Light the side facing the eye (normals flipped towards the eye), for open
    /// surfaces such as isosurfaces.
    pub two_sided: bool,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            diffuse: Rgb::splat(1.0),
            specular: Rgb::splat(0.0),
            shininess: 32.0,
            two_sided: true,
        }
    }
}

/// A light moved to eye space.
#[derive(Clone, Copy, Debug)]
enum EyeLight {
    /// Unit vector towards the light.
    Directional {
        to_light: Vec3,
        color: Vec3,
    },
    Point {
        position: Vec3,
        color: Vec3,
    },
    Spot {
        position: Vec3,
        /// Unit axis of the cone.
        axis: Vec3,
        color: Vec3,
        cos_inner: f32,
        cos_outer: f32,
    },
    Emitter {
        position: Vec3,
        normal: Vec3,
        color: Vec3,
    },
}

/// The frame's lights and material in eye space, ready to shade points.
#[derive(Clone, Debug)]
pub struct EyeLights {
    ambient: Vec3,
    lights: Vec<EyeLight>,
    material: Material,
    orthographic: bool,
}

fn v3(c: Rgb) -> Vec3 {
    Vec3::new(c.r, c.g, c.b)
}

impl EyeLights {
    pub fn new(lights: &Lights, material: &Material, view: Mat4, orthographic: bool) -> Self {
        let eye_lights = lights
            .lights
            .iter()
            .map(|l| match *l {
                RasterLight::Directional { direction, color } => EyeLight::Directional {
                    to_light: -view.transform_vector3(direction).normalize_or_zero(),
                    color: v3(color),
                },
                RasterLight::Point { position, color } => EyeLight::Point {
                    position: view.transform_point3(position),
                    color: v3(color),
                },
                RasterLight::Spot {
                    position,
                    direction,
                    color,
                    cos_inner,
                    cos_outer,
                } => EyeLight::Spot {
                    position: view.transform_point3(position),
                    axis: view.transform_vector3(direction).normalize_or_zero(),
                    color: v3(color),
                    cos_inner,
                    cos_outer,
                },
                RasterLight::Emitter {
                    position,
                    normal,
                    color,
                } => EyeLight::Emitter {
                    position: view.transform_point3(position),
                    normal: view.transform_vector3(normal).normalize_or_zero(),
                    color: v3(color),
                },
            })
            .collect();
        Self {
            ambient: v3(lights.ambient),
            lights: eye_lights,
            material: *material,
            orthographic,
        }
    }

    /// Reflected colour at eye-space point `p` with unit normal `n` and base colour
    /// `base` (the vertex colour): `base*kd*(ambient + sum E cos) + ks * sum E (n.h)^s`.
    #[inline]
    pub fn shade(&self, p: Vec3, n: Vec3, base: Vec3) -> Vec3 {
        let m = &self.material;
        // The eye direction, unnormalised: only its sign matters unless there is a
        // specular term.
        let eye_dir = if self.orthographic { Vec3::Z } else { -p };
        let mut n = n;
        if m.two_sided && n.dot(eye_dir) < 0.0 {
            n = -n;
        }
        let kd = base * v3(m.diffuse);
        let ks = v3(m.specular);
        let specular = ks != Vec3::ZERO;
        let mut diffuse_sum = self.ambient;
        let mut specular_sum = Vec3::ZERO;
        for l in &self.lights {
            let (to_light, e) = match *l {
                EyeLight::Directional { to_light, color } => (to_light, color),
                EyeLight::Point { position, color } => {
                    let d = position - p;
                    let r2 = d.length_squared().max(1e-20);
                    (d / r2.sqrt(), color / r2)
                }
                EyeLight::Spot {
                    position,
                    axis,
                    color,
                    cos_inner,
                    cos_outer,
                } => {
                    let d = position - p;
                    let r2 = d.length_squared().max(1e-20);
                    let to_light = d / r2.sqrt();
                    let cos = -to_light.dot(axis);
                    if cos <= cos_outer {
                        continue;
                    }
                    let f = irradia_scene::spot_falloff(cos, cos_inner, cos_outer);
                    (to_light, color * (f / r2))
                }
                EyeLight::Emitter {
                    position,
                    normal,
                    color,
                } => {
                    let d = position - p;
                    let r2 = d.length_squared().max(1e-20);
                    let to_light = d / r2.sqrt();
                    let cos_l = -to_light.dot(normal);
                    if cos_l <= 0.0 {
                        continue;
                    }
                    (to_light, color * (cos_l / r2))
                }
            };
            let cos = n.dot(to_light);
            if cos > 0.0 {
                diffuse_sum += e * cos;
                if specular {
                    let h = (to_light + eye_dir.normalize_or_zero()).normalize_or_zero();
                    specular_sum += e * n.dot(h).max(0.0).powf(m.shininess);
                }
            }
        }
        kd * diffuse_sum + ks * specular_sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lambert_and_two_sided() {
        let lights = Lights {
            ambient: Rgb::splat(0.0),
            lights: vec![RasterLight::Directional {
                direction: -Vec3::Z,
                color: Rgb::splat(1.0),
            }],
        };
        let e = EyeLights::new(&lights, &Material::default(), Mat4::IDENTITY, false);
        let p = Vec3::new(0.0, 0.0, -2.0);
        let n = Vec3::new(0.6, 0.0, 0.8);
        assert!((e.shade(p, n, Vec3::ONE).x - 0.8).abs() < 1e-6);
        // Seen from behind, a two-sided surface is lit as if facing the eye.
        assert!((e.shade(p, -n, Vec3::ONE).x - 0.8).abs() < 1e-6);
        let one_sided = Material {
            two_sided: false,
            ..Material::default()
        };
        let e = EyeLights::new(&lights, &one_sided, Mat4::IDENTITY, false);
        assert_eq!(e.shade(p, -n, Vec3::ONE).x, 0.0);
    }
}
