//! The `[[lights]]` array: point, directional, spot, rectangle and sphere area lights,
//! and Mitsuba's `constant`, `envmap` and `projector` emitters (read in
//! [`super::emitters`]).

use super::emitters::{read_envmap, read_projector};
use super::reader::{Result, Table, Val};
use super::textures::read_texture_map;
use crate::light::{Light, SpotProfile, SpotTexture};
use glam::Vec3;
use irradia_core::Rgb;
use std::sync::Arc;

pub fn read_lights(v: Option<Val>) -> Result<Vec<Light>> {
    let Some(v) = v else {
        return Ok(Vec::new());
    };
    v.array()?.iter().map(read_light).collect()
}

fn read_light(v: &Val) -> Result<Light> {
    let t = v.table()?;
    let kind = t.req("type")?.choice(&[
        "point",
        "directional",
        "spot",
        "rect",
        "sphere",
        "constant",
        "envmap",
        "projector",
    ])?;
    let light = match kind {
        "point" => Light::Point {
            position: t.req("position")?.vec3()?,
            intensity: t.rgb_or("intensity", Rgb::WHITE)?,
        },
        "directional" => Light::Directional {
            direction: t.req("direction")?.direction()?.normalize(),
            irradiance: t.rgb_or("irradiance", Rgb::WHITE)?,
        },
        "spot" => read_spot(&t)?,
        "rect" => {
            let corner = t.req("corner")?.vec3()?;
            let edge_u = t.req("edge_u")?.vec3()?;
            let edge_v_v = t.req("edge_v")?;
            let edge_v = edge_v_v.vec3()?;
            if edge_u.cross(edge_v).length_squared() == 0.0 {
                return Err(
                    edge_v_v.err("edge_u and edge_v must span a rectangle of non-zero area")
                );
            }
            Light::Rect {
                corner,
                edge_u,
                edge_v,
                radiance: t.rgb_or("radiance", Rgb::WHITE)?,
                samples: t.count_or("samples", 16)?,
            }
        }
        "sphere" => Light::Sphere {
            center: t.req("center")?.vec3()?,
            radius: t.req("radius")?.positive()?,
            radiance: t.rgb_or("radiance", Rgb::WHITE)?,
            samples: t.count_or("samples", 16)?,
        },
        "constant" => Light::Constant {
            radiance: t.rgb_or("radiance", Rgb::WHITE)?,
        },
        "envmap" => read_envmap(&t)?,
        _ => read_projector(&t)?,
    };
    t.finish()?;
    Ok(light)
}

/// The spot's position and axis (`direction` or `look_at`), for spots and projectors.
pub(super) fn position_and_axis(t: &Table) -> Result<(Vec3, Vec3)> {
    let position = t.req("position")?.vec3()?;
    let direction = match (t.get("direction"), t.get("look_at")) {
        (Some(_), Some(l)) => return Err(l.err("give either direction or look_at, not both")),
        (Some(d), None) => d.direction()?,
        (None, Some(l)) => {
            let d = l.vec3()? - position;
            if d.length_squared() == 0.0 {
                return Err(l.err("look_at must differ from position"));
            }
            d
        }
        (None, None) => return Err(t.err(format!("a {} needs direction or look_at", kind(t)))),
    }
    .normalize();
    Ok((position, direction))
}

fn kind(t: &Table) -> &'static str {
    match t.get("type").and_then(|k| k.str().ok()) {
        Some("projector") => "projector",
        _ => "spot light",
    }
}

/// A spot light: the lecture's smooth cone (`outer_angle`, `inner_angle`) or Mitsuba's
/// `spot` (`cutoff_angle`, default 20°, and `beam_width`, default ¾ of the cutoff, with
/// its falloff linear in the angle). All angles are half-angles from the axis. Either
/// may carry a `texture` ([`SpotTexture`]) oriented by `up` (default [0, 1, 0]).
fn read_spot(t: &Table) -> Result<Light> {
    let (position, direction) = position_and_axis(t)?;
    let mitsuba = t.get("cutoff_angle").or(t.get("beam_width"));
    let lecture = t.get("outer_angle").or(t.get("inner_angle"));
    if let (Some(m), Some(l)) = (&mitsuba, &lecture) {
        let names = |v: &Val| v.path.rsplit('.').next().unwrap_or("").to_string();
        return Err(m.err(format!(
            "give either cutoff_angle/beam_width (Mitsuba's falloff) or \
             outer_angle/inner_angle (smooth falloff), not {} with {}",
            names(m),
            names(l)
        )));
    }
    let angle = |v: &Val| -> Result<f32> {
        let x = v.f32()?;
        if !(x > 0.0 && x <= 90.0) {
            return Err(v.err(format!(
                "must be between 0 (exclusive) and 90 degrees (got {x})"
            )));
        }
        Ok(x)
    };
    let (inner, outer, profile) = if lecture.is_some() {
        let outer_v = t.req("outer_angle")?;
        let outer = angle(&outer_v)?;
        let inner = match t.get("inner_angle") {
            Some(i) => {
                let x = i.f32()?;
                if !(0.0..=outer).contains(&x) {
                    return Err(i.err(format!(
                        "must be between 0 and outer_angle ({outer}) degrees (got {x})"
                    )));
                }
                x
            }
            None => outer,
        };
        (inner, outer, SpotProfile::Smooth)
    } else {
        let cutoff = match t.get("cutoff_angle") {
            Some(c) => angle(&c)?,
            None => 20.0,
        };
        let beam = match t.get("beam_width") {
            Some(b) => {
                let x = b.f32()?;
                if !(0.0..=cutoff).contains(&x) {
                    return Err(b.err(format!(
                        "must be between 0 and cutoff_angle ({cutoff}) degrees (got {x})"
                    )));
                }
                x
            }
            None => 0.75 * cutoff,
        };
        (beam, cutoff, SpotProfile::Linear)
    };
    let cos_outer = outer.to_radians().cos();
    // `texture` (Mitsuba's): an image across the cutoff cone, oriented by `up`.
    let up_v = t.get("up");
    let texture = match t.get("texture") {
        Some(tex) => {
            let map = read_texture_map(&tex)?;
            if matches!(map, crate::texture::TextureMap::MeshAttribute(_)) {
                return Err(tex.err("a spot light's texture cannot be a mesh_attribute (it is read across the cone, not on a mesh)"));
            }
            let up = up_v.as_ref().map_or(Ok(Vec3::Y), |u| u.direction())?;
            if direction.cross(up.normalize()).length() < 1e-4 {
                let at = up_v.unwrap_or(tex);
                return Err(
                    at.err("up must not be parallel to the spot's axis (give an `up` across it)")
                );
            }
            Some(Arc::new(SpotTexture::new(map, direction, up, cos_outer)))
        }
        None => {
            if let Some(u) = up_v {
                return Err(u.err("`up` orients a spot light's `texture`; there is none"));
            }
            None
        }
    };
    Ok(Light::Spot {
        position,
        direction,
        intensity: t.rgb_or("intensity", Rgb::WHITE)?,
        cos_inner: inner.to_radians().cos(),
        cos_outer,
        profile,
        texture,
    })
}
