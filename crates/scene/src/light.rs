//! Light sources: point, directional, spot, rectangle and sphere area lights, and
//! Mitsuba 3's `constant`, `envmap` and `projector` emitters (emissive surfaces, Mitsuba's
//! `area` emitter, are materials with an `emission`).

use crate::envmap::EnvMap;
use crate::projector::Projector;
use crate::texture::{TextureMap, TextureQuery};
use glam::{Vec2, Vec3};
use irradia_core::Rgb;
use std::sync::Arc;

#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// Intensity `I` (W/sr in the path tracer); irradiance at distance r is `I / r²`
    /// (Mitsuba's `point`).
    Point { position: Vec3, intensity: Rgb },
    /// Light from direction `-direction` (travelling along `direction`), irradiance `E`
    /// (Mitsuba's `directional`).
    Directional { direction: Vec3, irradiance: Rgb },
    /// A point light limited to a cone: full inside `cos_inner`, falling to zero at
    /// `cos_outer` along `profile`.
    Spot {
        position: Vec3,
        direction: Vec3,
        intensity: Rgb,
        cos_inner: f32,
        cos_outer: f32,
        profile: SpotProfile,
        /// An image over the cone that multiplies the intensity (Mitsuba's spot
        /// `texture`); the path tracer and `direct` render it.
        texture: Option<Arc<SpotTexture>>,
    },
    /// A one-sided rectangle `corner + s*edge_u + t*edge_v`, s,t in [0,1], emitting
    /// `radiance` on the side of `edge_u x edge_v`; sampled with `samples` shadow rays
    /// (stratified) by the Whitted tracer for soft shadows.
    Rect {
        corner: Vec3,
        edge_u: Vec3,
        edge_v: Vec3,
        radiance: Rgb,
        samples: u32,
    },
    /// A sphere emitting `radiance` outwards, sampled with `samples` shadow rays.
    Sphere {
        center: Vec3,
        radius: f32,
        radiance: Rgb,
        samples: u32,
    },
    /// Radiance arriving equally from every direction at infinity (Mitsuba's
    /// `constant`): what rays that leave the scene see, added to the background.
    Constant { radiance: Rgb },
    /// Radiance at infinity from a latitude-longitude image (Mitsuba's `envmap`).
    Envmap(Arc<EnvMap>),
    /// An image projected from a point through a pinhole (Mitsuba's `projector`).
    Projector(Arc<Projector>),
}

/// A spot light's image (Mitsuba's spot `texture`): the direction at local `(x, y, z)`
/// (z along the spot's axis) reads the texture at
/// `uv = 0.5 + 0.5 · (x, y) / (z · tan(cutoff))`, so the image spans the square around
/// the cutoff cone; the intensity is multiplied by the texture's colour there.
#[derive(Clone, Debug, PartialEq)]
pub struct SpotTexture {
    pub map: TextureMap,
    /// The spot's local x and y axes (unit, across its direction): Mitsuba's
    /// `to_world` columns, `x = up × direction` for a `lookat`.
    pub x_axis: Vec3,
    pub y_axis: Vec3,
    /// `tan(cutoff_angle)`.
    pub uv_factor: f32,
}

impl SpotTexture {
    /// The image's frame for a spot along `direction` with `up` (not parallel to it)
    /// and the cutoff half-angle whose cosine is `cos_cutoff`.
    pub fn new(map: TextureMap, direction: Vec3, up: Vec3, cos_cutoff: f32) -> Self {
        let z = direction.normalize();
        let x_axis = up.cross(z).normalize();
        let y_axis = z.cross(x_axis);
        let cos = cos_cutoff.clamp(-1.0, 1.0);
        Self {
            map,
            x_axis,
            y_axis,
            uv_factor: (1.0 - cos * cos).sqrt() / cos,
        }
    }

    /// The texture coordinates of the unit direction `d` leaving the light, whose
    /// component along the axis is `z` (> 0).
    #[inline]
    pub fn uv(&self, d: Vec3, z: f32) -> Vec2 {
        let k = 0.5 / (z * self.uv_factor);
        Vec2::new(0.5 + k * d.dot(self.x_axis), 0.5 + k * d.dot(self.y_axis))
    }

    /// The factor on the intensity sent in the unit direction `d` (axis component `z`).
    #[inline]
    pub fn eval(&self, d: Vec3, z: f32) -> Rgb {
        self.map.eval(&TextureQuery::at_uv(self.uv(d, z)))
    }
}

/// How a spot light's intensity falls from the edge of its beam to its cutoff.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SpotProfile {
    /// A smoothstep in the cosine (the lecture's and OpenGL-like spots; fields
    /// `inner_angle`, `outer_angle`).
    #[default]
    Smooth,
    /// Linear in the angle θ from the axis, Mitsuba's `spot`: 1 up to `beam_width`,
    /// `(cutoff_angle − θ) / (cutoff_angle − beam_width)` beyond, 0 past `cutoff_angle`.
    Linear,
}

impl SpotProfile {
    /// The fraction of the spot's intensity sent at `cos` from its axis.
    #[inline]
    pub fn falloff(self, cos: f32, cos_inner: f32, cos_outer: f32) -> f32 {
        match self {
            SpotProfile::Smooth => spot_falloff(cos, cos_inner, cos_outer),
            SpotProfile::Linear => {
                if cos <= cos_outer {
                    0.0
                } else if cos >= cos_inner {
                    1.0
                } else {
                    let (beam, cutoff) = (cos_inner.acos(), cos_outer.acos());
                    ((cutoff - cos.clamp(-1.0, 1.0).acos()) / (cutoff - beam).max(1e-9))
                        .clamp(0.0, 1.0)
                }
            }
        }
    }
}

/// The spot light's smooth cone falloff: 1 inside `cos_inner`, 0 outside `cos_outer`,
/// and a smoothstep between (shared by every integrator so they light spots alike).
#[inline]
pub fn spot_falloff(cos: f32, cos_inner: f32, cos_outer: f32) -> f32 {
    if cos >= cos_inner {
        1.0
    } else if cos <= cos_outer {
        0.0
    } else {
        let x = (cos - cos_outer) / (cos_inner - cos_outer).max(1e-9);
        x * x * (3.0 - 2.0 * x)
    }
}

impl Light {
    /// Whether the light sits at infinity and is seen by rays that leave the scene.
    pub fn is_environment(&self) -> bool {
        matches!(self, Light::Constant { .. } | Light::Envmap(_))
    }

    /// The radiance this light sends along a ray that leaves the scene in direction
    /// `dir` (black for lights that are not at infinity).
    #[inline]
    pub fn environment_radiance(&self, dir: Vec3) -> Rgb {
        match self {
            Light::Constant { radiance } => *radiance,
            Light::Envmap(map) => map.eval(dir),
            _ => Rgb::BLACK,
        }
    }
}
