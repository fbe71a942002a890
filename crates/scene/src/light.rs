//! Light sources: point, directional, spot, and rectangle and sphere area lights.

use glam::Vec3;
use irradia_core::Rgb;

#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// Intensity `I` (W/sr in the path tracer); irradiance at distance r is `I / r²`.
    Point { position: Vec3, intensity: Rgb },
    /// Light from direction `-direction` (travelling along `direction`), irradiance `E`.
    Directional { direction: Vec3, irradiance: Rgb },
    /// A point light limited to a cone: full inside `cos_inner`, falling smoothly to
    /// zero at `cos_outer`.
    Spot {
        position: Vec3,
        direction: Vec3,
        intensity: Rgb,
        cos_inner: f32,
        cos_outer: f32,
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
}

/// The spot light's cone falloff: 1 inside `cos_inner`, 0 outside `cos_outer`, and a
/// smoothstep between (shared by every integrator so they light spots alike).
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
