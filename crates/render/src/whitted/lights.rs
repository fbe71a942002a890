//! Light sources prepared for the Whitted tracer: per-light constants computed once
//! (unit directions, cone cosines, rectangle normal and area), and the sampling of area
//! lights with stratified shadow rays for soft shadows.
//!
//! Every light is turned into one or more "light samples": a unit direction towards the
//! light, the distance a shadow ray must clear, and the irradiance the sample brings to a
//! surface facing it (before the cosine). The Phong terms then treat each sample like a
//! point light.

use glam::{Vec2, Vec3};
use irradia_core::{Frame, Rgb, Rng};
use irradia_scene::{Light, Projector, SpotProfile};
use std::f32::consts::PI;
use std::sync::Arc;

/// One light with its constants precomputed.
#[derive(Clone, Debug)]
pub(crate) enum PreparedLight {
    Point {
        position: Vec3,
        intensity: Rgb,
    },
    Directional {
        /// Unit vector towards the light.
        to_light: Vec3,
        irradiance: Rgb,
    },
    Spot {
        position: Vec3,
        /// Unit axis of the cone (direction the light shines).
        axis: Vec3,
        intensity: Rgb,
        cos_inner: f32,
        cos_outer: f32,
        profile: SpotProfile,
    },
    /// Mitsuba's `projector`: a point light whose intensity is an image.
    Projector(Arc<Projector>),
    Rect {
        corner: Vec3,
        edge_u: Vec3,
        edge_v: Vec3,
        /// Unit normal of the emitting side.
        normal: Vec3,
        /// radiance * area / samples: the intensity of one sample along the normal.
        sample_power: Rgb,
        strata_u: u32,
        strata_v: u32,
        samples: u32,
    },
    Sphere {
        center: Vec3,
        radius: f32,
        radiance: Rgb,
        strata_u: u32,
        strata_v: u32,
        samples: u32,
    },
}

/// A direction towards a light and what arrives along it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LightSample {
    /// Unit direction from the shaded point towards the light.
    pub dir: Vec3,
    /// Distance to the light along `dir` (infinite for directional lights).
    pub dist: f32,
    /// Irradiance on a surface facing the light, before the cosine factor.
    pub irradiance: Rgb,
}

/// Splits `n` samples into a `u x v` grid with `u * v >= n`, as square as possible.
fn strata(n: u32) -> (u32, u32) {
    let n = n.max(1);
    let u = (n as f32).sqrt().ceil() as u32;
    let v = n.div_ceil(u);
    (u, v)
}

/// A jittered point in stratum `i` of a `su x sv` grid over the unit square.
#[inline]
fn stratum_point(i: u32, su: u32, sv: u32, rng: &mut Rng) -> Vec2 {
    let (iu, iv) = (i % su, (i / su) % sv);
    Vec2::new(
        (iu as f32 + rng.next_f32()) / su as f32,
        (iv as f32 + rng.next_f32()) / sv as f32,
    )
}

impl PreparedLight {
    /// The light prepared, or `None` for lights at infinity (`constant`, `envmap`),
    /// which the Whitted tracer sees only along rays that leave the scene.
    pub fn new(light: &Light) -> Option<Self> {
        Some(match *light {
            Light::Point {
                position,
                intensity,
            } => PreparedLight::Point {
                position,
                intensity,
            },
            Light::Directional {
                direction,
                irradiance,
            } => PreparedLight::Directional {
                to_light: -direction.normalize(),
                irradiance,
            },
            Light::Spot {
                position,
                direction,
                intensity,
                cos_inner,
                cos_outer,
                profile,
                ..
            } => PreparedLight::Spot {
                position,
                axis: direction.normalize(),
                intensity,
                cos_inner,
                cos_outer,
                profile,
            },
            Light::Projector(ref p) => PreparedLight::Projector(p.clone()),
            Light::Constant { .. } | Light::Envmap(_) => return None,
            Light::Rect {
                corner,
                edge_u,
                edge_v,
                radiance,
                samples,
            } => {
                let c = edge_u.cross(edge_v);
                let area = c.length();
                let samples = samples.max(1);
                let (su, sv) = strata(samples);
                PreparedLight::Rect {
                    corner,
                    edge_u,
                    edge_v,
                    normal: c / area,
                    sample_power: radiance * (area / samples as f32),
                    strata_u: su,
                    strata_v: sv,
                    samples,
                }
            }
            Light::Sphere {
                center,
                radius,
                radiance,
                samples,
            } => {
                let samples = samples.max(1);
                let (su, sv) = strata(samples);
                PreparedLight::Sphere {
                    center,
                    radius,
                    radiance,
                    strata_u: su,
                    strata_v: sv,
                    samples,
                }
            }
        })
    }

    /// How many shadow rays the light takes per shaded point.
    #[inline]
    pub fn samples(&self) -> u32 {
        match self {
            PreparedLight::Rect { samples, .. } | PreparedLight::Sphere { samples, .. } => *samples,
            _ => 1,
        }
    }

    /// Sample `i` of the light seen from point `p`. `falloff` applies the inverse-square
    /// law to point and spot lights (off for POV-Ray's finish model, whose lights do not
    /// fade by default). `None` when the light sends nothing towards `p`.
    ///
    /// Point lights (the usual case, and the only lights of the `whitted` and `csg`
    /// scenes) are answered here, inline in the shading loop, with the sample in
    /// registers; the other kinds out of line ([`Self::sample_other`], the same
    /// arithmetic for a point light). Measured: the out-of-line call returned the
    /// sample through memory and the tracer stalled reloading it.
    #[inline(always)]
    pub fn sample(&self, p: Vec3, i: u32, falloff: bool, rng: &mut Rng) -> Option<LightSample> {
        if let PreparedLight::Point {
            position,
            intensity,
        } = *self
        {
            let d = position - p;
            let d2 = d.length_squared();
            let dist = d2.sqrt();
            let irradiance = if falloff { intensity / d2 } else { intensity };
            return Some(LightSample {
                dir: d / dist,
                dist,
                irradiance,
            });
        }
        self.sample_other(p, i, falloff, rng)
    }

    /// [`Self::sample`] for every kind of light, out of line.
    #[inline(never)]
    fn sample_other(&self, p: Vec3, i: u32, falloff: bool, rng: &mut Rng) -> Option<LightSample> {
        match *self {
            PreparedLight::Point {
                position,
                intensity,
            } => {
                let d = position - p;
                let d2 = d.length_squared();
                let dist = d2.sqrt();
                let irradiance = if falloff { intensity / d2 } else { intensity };
                Some(LightSample {
                    dir: d / dist,
                    dist,
                    irradiance,
                })
            }
            PreparedLight::Directional {
                to_light,
                irradiance,
            } => Some(LightSample {
                dir: to_light,
                dist: f32::INFINITY,
                irradiance,
            }),
            PreparedLight::Spot {
                position,
                axis,
                intensity,
                cos_inner,
                cos_outer,
                profile,
            } => {
                let d = position - p;
                let d2 = d.length_squared();
                let dist = d2.sqrt();
                let dir = d / dist;
                let cos = -dir.dot(axis);
                if cos <= cos_outer {
                    return None;
                }
                let fall = profile.falloff(cos, cos_inner, cos_outer);
                let e = intensity * fall;
                Some(LightSample {
                    dir,
                    dist,
                    irradiance: if falloff { e / d2 } else { e },
                })
            }
            PreparedLight::Projector(ref proj) => {
                let s = proj.illuminate(p)?;
                // `li` is I / r²; without falloff (POV-Ray's model) the intensity.
                let irradiance = if falloff {
                    s.li
                } else {
                    s.li * (s.dist * s.dist)
                };
                Some(LightSample {
                    dir: s.wi,
                    dist: s.dist,
                    irradiance,
                })
            }
            PreparedLight::Rect {
                corner,
                edge_u,
                edge_v,
                normal,
                sample_power,
                strata_u,
                strata_v,
                ..
            } => {
                let uv = stratum_point(i, strata_u, strata_v, rng);
                let q = corner + edge_u * uv.x + edge_v * uv.y;
                let d = q - p;
                let d2 = d.length_squared();
                let dist = d2.sqrt();
                let dir = d / dist;
                let cos_l = -dir.dot(normal);
                if cos_l <= 0.0 {
                    return None;
                }
                Some(LightSample {
                    dir,
                    dist,
                    irradiance: sample_power * (cos_l / d2),
                })
            }
            PreparedLight::Sphere {
                center,
                radius,
                radiance,
                strata_u,
                strata_v,
                samples,
            } => {
                // Uniform sampling of the cone the sphere subtends (solid angle Ω), so
                // each of the n samples carries L Ω / n.
                let to_c = center - p;
                let dc2 = to_c.length_squared();
                let r2 = radius * radius;
                if dc2 <= r2 {
                    return None;
                }
                let dc = dc2.sqrt();
                let cos_max = (1.0 - r2 / dc2).max(0.0).sqrt();
                let uv = stratum_point(i, strata_u, strata_v, rng);
                let cos_t = 1.0 - uv.x * (1.0 - cos_max);
                let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
                let phi = 2.0 * PI * uv.y;
                let frame = Frame::from_normal(to_c / dc);
                let dir = frame
                    .to_world(Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t))
                    .normalize();
                // Distance to the near side of the sphere along dir.
                let b = dc * cos_t;
                let dist = b - (r2 - dc2 * sin_t * sin_t).max(0.0).sqrt();
                let omega = 2.0 * PI * (1.0 - cos_max);
                Some(LightSample {
                    dir,
                    dist,
                    irradiance: radiance * (omega / samples as f32),
                })
            }
        }
    }
}
