//! The `[[lights]]` array: point, directional, spot, and rectangle and sphere area
//! lights.

use super::reader::{Result, Val};
use crate::light::Light;
use irradia_core::Rgb;

pub fn read_lights(v: Option<Val>) -> Result<Vec<Light>> {
    let Some(v) = v else {
        return Ok(Vec::new());
    };
    v.array()?.iter().map(read_light).collect()
}

fn read_light(v: &Val) -> Result<Light> {
    let t = v.table()?;
    let kind = t
        .req("type")?
        .choice(&["point", "directional", "spot", "rect", "sphere"])?;
    let light = match kind {
        "point" => Light::Point {
            position: t.req("position")?.vec3()?,
            intensity: t.rgb_or("intensity", Rgb::WHITE)?,
        },
        "directional" => Light::Directional {
            direction: t.req("direction")?.direction()?.normalize(),
            irradiance: t.rgb_or("irradiance", Rgb::WHITE)?,
        },
        "spot" => {
            let position = t.req("position")?.vec3()?;
            let direction = match (t.get("direction"), t.get("look_at")) {
                (Some(_), Some(l)) => {
                    return Err(l.err("give either direction or look_at, not both"))
                }
                (Some(d), None) => d.direction()?,
                (None, Some(l)) => {
                    let d = l.vec3()? - position;
                    if d.length_squared() == 0.0 {
                        return Err(l.err("look_at must differ from position"));
                    }
                    d
                }
                (None, None) => return Err(t.err("a spot light needs direction or look_at")),
            }
            .normalize();
            let outer_v = t.req("outer_angle")?;
            let outer = outer_v.f32()?;
            if !(outer > 0.0 && outer <= 90.0) {
                return Err(outer_v.err(format!(
                    "must be between 0 (exclusive) and 90 degrees (got {outer})"
                )));
            }
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
            Light::Spot {
                position,
                direction,
                intensity: t.rgb_or("intensity", Rgb::WHITE)?,
                cos_inner: inner.to_radians().cos(),
                cos_outer: outer.to_radians().cos(),
            }
        }
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
        _ => Light::Sphere {
            center: t.req("center")?.vec3()?,
            radius: t.req("radius")?.positive()?,
            radiance: t.rgb_or("radiance", Rgb::WHITE)?,
            samples: t.count_or("samples", 16)?,
        },
    };
    t.finish()?;
    Ok(light)
}
