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

/// How the highlight is computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Highlight {
    /// Blinn-Phong: `(n·h)^s` with `h` halfway between the light and the eye (OpenGL's
    /// fixed-function model).
    #[default]
    BlinnPhong,
    /// Phong (1975), the lecture's and the Whitted tracer's: `(r·v)^s` with `r` the
    /// light direction mirrored about the normal.
    Phong,
}

/// Surface reflectance for the pipeline's lighting model. A pipeline holds a table of
/// them (`Pipeline::materials`) and every triangle names its entry by index
/// (`Triangle::material`).
///
/// The colour of a point with vertex colour `C`:
/// `emission + C*ambient*A + Σ E (C*diffuse*cos + specular*highlight^shininess)`, with
/// `A` the lights' ambient term and `E` each light's irradiance (no 1/π).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Multiplies the vertex colour for the diffuse term.
    pub diffuse: Rgb,
    pub specular: Rgb,
    /// Blinn-Phong or Phong exponent.
    pub shininess: f32,
    /// Light the side facing the eye (normals flipped towards the eye), for open
    /// surfaces such as isosurfaces.
    pub two_sided: bool,
    /// Multiplies the vertex colour for the ambient term; `None` (the default) uses
    /// `diffuse`, as the fixed-function pipeline's usual ambient = diffuse.
    pub ambient: Option<Rgb>,
    /// Added to the reflected colour (an emitting surface).
    pub emission: Rgb,
    pub highlight: Highlight,
    /// Point and spot lights fade as 1/r² (off for POV-Ray's finish model, whose
    /// lights do not fade by default, as in the Whitted tracer).
    pub distance_falloff: bool,
    /// Entry of the pipeline's texture table (`Pipeline::textures`) that multiplies
    /// the base colour at every fragment, or `None`.
    pub texture: Option<u32>,
    /// Fraction of the light behind the surface that passes through it (0: opaque).
    /// A transparent surface is drawn after the opaque ones, back to front, as
    /// `dst = colour + transmission * filter * dst` (see [`crate::transparency`]).
    pub transmission: f32,
    /// The colour the light passing through is filtered by; `None` means the
    /// fragment's base colour (the Whitted tracer's default).
    pub filter: Option<Rgb>,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            diffuse: Rgb::splat(1.0),
            specular: Rgb::splat(0.0),
            shininess: 32.0,
            two_sided: true,
            ambient: None,
            emission: Rgb::BLACK,
            highlight: Highlight::BlinnPhong,
            distance_falloff: true,
            texture: None,
            transmission: 0.0,
            filter: None,
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

/// The frame's lights in eye space and its material table, ready to shade points.
#[derive(Clone, Debug)]
pub struct EyeLights {
    ambient: Vec3,
    lights: Vec<EyeLight>,
    /// Material `i` for index `i`; indices past the end use `fallback`.
    materials: Vec<Material>,
    fallback: Material,
    orthographic: bool,
}

fn v3(c: Rgb) -> Vec3 {
    Vec3::new(c.r, c.g, c.b)
}

impl EyeLights {
    /// One material for every triangle.
    pub fn new(lights: &Lights, material: &Material, view: Mat4, orthographic: bool) -> Self {
        Self::with_materials(lights, &[], material, view, orthographic)
    }

    /// A material table: index `i` shades with `materials[i]`, indices past its end
    /// with `fallback`.
    pub fn with_materials(
        lights: &Lights,
        materials: &[Material],
        fallback: &Material,
        view: Mat4,
        orthographic: bool,
    ) -> Self {
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
            materials: materials.to_vec(),
            fallback: *fallback,
            orthographic,
        }
    }

    /// The material of index `i`.
    #[inline(always)]
    pub fn material(&self, i: u32) -> &Material {
        self.materials.get(i as usize).unwrap_or(&self.fallback)
    }

    /// Whether any material (the table's or the fallback) has a texture or lets
    /// light through: the fragment stage then needs the per-material shaders.
    pub fn needs_material_fragments(&self) -> bool {
        self.materials
            .iter()
            .chain(std::iter::once(&self.fallback))
            .any(|m| m.texture.is_some() || m.is_transparent())
    }

    /// [`EyeLights::shade_with`] material index 0.
    #[inline]
    pub fn shade(&self, p: Vec3, n: Vec3, base: Vec3) -> Vec3 {
        self.shade_with(0, p, n, base)
    }

    /// Colour at eye-space point `p` with unit normal `n` and base colour `base` (the
    /// vertex colour), shaded with material `material`:
    /// `em + base*ka*ambient + sum E (base*kd*cos + ks*highlight^s)`
    /// (`base*kd*(ambient + sum E cos) + ...` when `ka` is `None`).
    #[inline]
    pub fn shade_with(&self, material: u32, p: Vec3, n: Vec3, base: Vec3) -> Vec3 {
        let m = self.material(material);
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
        let fade = m.distance_falloff;
        let (mut diffuse_sum, ambient) = match m.ambient {
            None => (self.ambient, Vec3::ZERO),
            Some(ka) => (Vec3::ZERO, base * v3(ka) * self.ambient),
        };
        let mut specular_sum = Vec3::ZERO;
        for l in &self.lights {
            let (to_light, e) = match *l {
                EyeLight::Directional { to_light, color } => (to_light, color),
                EyeLight::Point { position, color } => {
                    let d = position - p;
                    let r2 = d.length_squared().max(1e-20);
                    (d / r2.sqrt(), if fade { color / r2 } else { color })
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
                    (to_light, color * if fade { f / r2 } else { f })
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
                    let v = eye_dir.normalize_or_zero();
                    match m.highlight {
                        Highlight::BlinnPhong => {
                            let h = (to_light + v).normalize_or_zero();
                            specular_sum += e * n.dot(h).max(0.0).powf(m.shininess);
                        }
                        Highlight::Phong => {
                            let rv = (2.0 * cos * n - to_light).dot(v);
                            if rv > 0.0 {
                                specular_sum += e * power(rv, m.shininess);
                            }
                        }
                    }
                }
            }
        }
        m.emission_v3() + ambient + kd * diffuse_sum + ks * specular_sum
    }
}

impl Material {
    #[inline(always)]
    fn emission_v3(&self) -> Vec3 {
        v3(self.emission)
    }

    /// Whether the material lets light through (drawn in the transparent pass).
    #[inline]
    pub fn is_transparent(&self) -> bool {
        self.transmission > 0.0
    }

    /// Per channel, the fraction of the colour behind that shows through a fragment
    /// of base colour `base`: `transmission * filter` (clamped to [0, 1]).
    #[inline]
    pub fn transmittance(&self, base: Vec3) -> Vec3 {
        let f = self.filter.map(v3).unwrap_or(base);
        (f * self.transmission).clamp(Vec3::ZERO, Vec3::ONE)
    }
}

/// `x^s` for a highlight: by repeated squaring for whole exponents (as the Whitted
/// tracer does, so both give the same highlights), `powf` otherwise.
#[inline]
fn power(x: f32, s: f32) -> f32 {
    if s.fract() == 0.0 && (0.0..=4096.0).contains(&s) {
        x.powi(s as i32)
    } else {
        x.powf(s)
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

    #[test]
    fn material_table_phong_ambient_emission_and_falloff() {
        // Eye at the origin, a surface facing up at (0, 0, -2), a light 2 up and 2 back.
        let light = Vec3::new(0.0, 2.0, -4.0);
        let lights = Lights {
            ambient: Rgb::splat(0.5),
            lights: vec![RasterLight::Point {
                position: light,
                color: Rgb::splat(8.0),
            }],
        };
        let shiny = Material {
            diffuse: Rgb::splat(0.6),
            specular: Rgb::splat(0.8),
            shininess: 10.0,
            ambient: Some(Rgb::splat(0.2)),
            emission: Rgb::new(0.1, 0.0, 0.0),
            highlight: Highlight::Phong,
            ..Material::default()
        };
        let no_fade = Material {
            distance_falloff: false,
            ..shiny
        };
        let e = EyeLights::with_materials(
            &lights,
            &[Material::default(), shiny, no_fade],
            &Material::default(),
            Mat4::IDENTITY,
            false,
        );
        let (p, n, base) = (Vec3::new(0.0, 0.0, -2.0), Vec3::Y, Vec3::splat(0.5));
        let l = (light - p).normalize();
        let cos = n.dot(l);
        let rv = (2.0 * cos * n - l).dot(Vec3::Z);
        assert!(rv > 0.7);
        // em + C k_a A + E (C k_d cos + k_s (r.v)^n), green channel (no emission).
        let expect = |e: f32| 0.5 * 0.2 * 0.5 + e * (0.5 * 0.6 * cos + 0.8 * rv.powi(10));
        let got = e.shade_with(1, p, n, base);
        assert!(
            (got.y - expect(1.0)).abs() < 1e-5,
            "{got} vs {}",
            expect(1.0)
        );
        assert!((got.x - got.y - 0.1).abs() < 1e-5, "emission: {got}");
        let got = e.shade_with(2, p, n, base);
        assert!((got.y - expect(8.0)).abs() < 1e-4, "no falloff: {got}");
        // Index 0 and any index past the table: the default material (no specular):
        // C (A + E cos).
        for i in [0, 7] {
            let got = e.shade_with(i, p, n, base);
            assert!((got.y - 0.5 * (0.5 + cos)).abs() < 1e-5, "{i}: {got}");
        }
    }
}
