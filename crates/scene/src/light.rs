//! Light sources: point, directional, spot, rectangle and sphere area lights, and
//! Mitsuba 3's `constant`, `envmap` and `projector` emitters (emissive surfaces, Mitsuba's
//! `area` emitter, are materials with an `emission`).

use crate::envmap::EnvMap;
use crate::projector::Projector;
use glam::Vec3;
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
