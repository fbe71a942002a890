//! `<emitter>` into `[[lights]]` (Irradia's lights are Mitsuba's, with Mitsuba's
//! parameter names); a position and direction given by `to_world` are taken from
//! it. An `area` emitter belongs to a shape: its radiance becomes the material's
//! `emission` ([`area_radiance`]).

use super::bsdfs::value;
use super::props::Obj;
use super::xml::Elem;
use super::Builder;
use glam::DVec3;
use irradia_scene::file::tree::Node;
use irradia_scene::SceneError;

const EMITTERS: &[&str] = &[
    "point",
    "spot",
    "directional",
    "constant",
    "envmap",
    "projector",
    "area",
];

const UNRENDERED: &[&str] = &["directionalarea", "sunsky", "sky", "sun"];

/// Mitsuba's `sampling_weight` (how often the emitter is picked for a light sample,
/// relative to the others). Irradia's imported scenes pick every emitter equally often
/// (Mitsuba's default of 1 everywhere), which changes the noise but not the image in
/// expectation: a weight other than 1 is accepted with a note saying so.
fn sampling_weight(b: &mut Builder<'_>, o: &Obj<'_>) -> Result<(), SceneError> {
    if let Some(p) = o.get("sampling_weight") {
        let w = p.f64()?;
        if !(w.is_finite() && w >= 0.0) {
            return Err(p.err("sampling_weight must be a finite number >= 0"));
        }
        if w != 1.0 {
            b.notes.push(format!(
                "emitter sampling_weight {w}: Irradia samples every emitter equally often \
                 (the same image in expectation, different noise)"
            ));
        }
    }
    Ok(())
}

fn v3(v: DVec3, pos: usize) -> Node {
    Node::new([v.x, v.y, v.z], pos)
}

/// The radiance of a shape's `area` emitter, as an emission colour or texture.
pub fn area_radiance<'e>(b: &mut Builder<'e>, e: &'e Elem) -> Result<Option<Node>, SceneError> {
    let o = Obj::read(e)?;
    if o.plugin != "area" {
        if EMITTERS.contains(&o.plugin.as_str()) || UNRENDERED.contains(&o.plugin.as_str()) {
            return Err(e.err_at(
                "type",
                "type",
                format!("a shape's emitter must be `area`, not `{}`", o.plugin),
            ));
        }
        return Err(e.err_at("type", "type", format!("unknown emitter `{}`", o.plugin)));
    }
    // A texture (`bitmap`, `checkerboard`) becomes a textured emission, read at the
    // surface's uv.
    let r = match o.get("radiance") {
        None => Node::new(1.0, e.main_pos),
        Some(p) => value(b, p, true)?,
    };
    if let Some(n) = o.nested.first() {
        return Err(n.err(
            &n.tag,
            format!("<{}> does not belong in an area emitter", n.tag),
        ));
    }
    sampling_weight(b, &o)?;
    o.finish(&["radiance", "sampling_weight"])?;
    Ok(Some(r))
}

pub fn emitter<'e>(b: &mut Builder<'e>, e: &'e Elem) -> Result<(), SceneError> {
    let o = Obj::read(e)?;
    let pos = e.main_pos;
    let kind = o.plugin.as_str();
    if !EMITTERS.contains(&kind) {
        if UNRENDERED.contains(&kind) {
            b.warn(
                e,
                "type",
                format!("the `{kind}` emitter is not rendered: left out"),
            );
            return Ok(());
        }
        let valid: Vec<&str> = EMITTERS.iter().chain(UNRENDERED).copied().collect();
        return Err(e.err_at(
            "type",
            "type",
            format!("unknown emitter `{kind}` (valid: {})", valid.join(", ")),
        ));
    }
    if kind == "area" {
        return Err(e.err("type", "an `area` emitter belongs inside a <shape>"));
    }
    if let Some(n) = o.nested.first() {
        return Err(n.err(&n.tag, format!("<{}> does not belong in an emitter", n.tag)));
    }
    let xf = match o.get("to_world") {
        Some(p) => Some(p.transform()?.clone()),
        None => None,
    };
    let mut l = Node::table(pos);
    l.put("type", kind, pos);
    let params: &[&str] = match kind {
        "point" => {
            let p = match (o.get("position"), &xf) {
                (Some(p), None) => p.vec3()?,
                (None, Some(x)) => x.point(DVec3::ZERO),
                (None, None) => DVec3::ZERO,
                (Some(p), Some(_)) => {
                    return Err(p.err("give either position or to_world, not both"))
                }
            };
            l.set("position", v3(p, pos));
            copy(b, &o, &mut l, &["intensity"])?;
            &["position", "to_world", "intensity"]
        }
        "spot" => {
            let x = xf.clone().unwrap_or_else(super::transform::Xform::identity);
            l.set("position", v3(x.point(DVec3::ZERO), pos));
            l.set("direction", v3(x.vector(DVec3::Z).normalize(), pos));
            copy(b, &o, &mut l, &["intensity", "cutoff_angle", "beam_width"])?;
            if let Some(p) = o.get("texture") {
                // Mitsuba's image across the cone, in the frame of `to_world`.
                let v = value(b, p, true)?;
                if v.get("type").is_some() {
                    l.set("texture", v);
                    l.set("up", v3(x.vector(DVec3::Y).normalize(), pos));
                } else {
                    b.warn(
                        p.elem,
                        "texture",
                        "a spot light's texture must be a bitmap Irradia reads: it shines its intensity uniformly",
                    );
                }
            }
            &[
                "to_world",
                "intensity",
                "cutoff_angle",
                "beam_width",
                "texture",
            ]
        }
        "directional" => {
            let d = match (o.get("direction"), &xf) {
                (Some(p), None) => p.vec3()?,
                (None, Some(x)) => x.vector(DVec3::Z),
                (None, None) => DVec3::Z,
                (Some(p), Some(_)) => {
                    return Err(p.err("give either direction or to_world, not both"))
                }
            };
            l.set("direction", v3(d, pos));
            copy(b, &o, &mut l, &["irradiance"])?;
            &["direction", "to_world", "irradiance"]
        }
        "constant" => {
            copy(b, &o, &mut l, &["radiance"])?;
            &["radiance"]
        }
        "envmap" => {
            let f = o
                .get("filename")
                .ok_or_else(|| e.err("filename", "`envmap` needs `filename`"))?;
            let path = b.file(e, f.elem, f.str()?)?;
            l.put("filename", path, f.elem.main_pos);
            copy(b, &o, &mut l, &["scale"])?;
            if let Some(x) = &xf {
                if !x.steps.is_empty() {
                    l.set("to_world", Node::new(x.steps.clone(), pos));
                }
            }
            if o.get("bitmap").is_some() {
                return Err(e.err(
                    "bitmap",
                    "an envmap from an in-memory bitmap cannot be read from a file",
                ));
            }
            &["filename", "scale", "to_world"]
        }
        "projector" => {
            let x = xf.clone().unwrap_or_else(super::transform::Xform::identity);
            l.set("position", v3(x.point(DVec3::ZERO), pos));
            l.set("direction", v3(x.vector(DVec3::Z).normalize(), pos));
            l.set("up", v3(x.vector(DVec3::Y).normalize(), pos));
            if let Some(p) = o.get("irradiance") {
                let v = value(b, p, true)?;
                // Irradia's projector takes an image file or a colour.
                let v = match v.get("filename") {
                    Some(f) => {
                        let name = match &f.value {
                            irradia_scene::file::tree::Value::Str(s) => s.to_ascii_lowercase(),
                            _ => String::new(),
                        };
                        if [".png", ".exr", ".pfm", ".jpg", ".jpeg", ".bmp"]
                            .iter()
                            .any(|x| name.ends_with(x))
                        {
                            f.clone()
                        } else {
                            b.warn(p.elem, "irradiance", "a projector reads PNG, EXR, PFM, JPEG or BMP images only: irradiance 1 stands in");
                            Node::new(1.0, pos)
                        }
                    }
                    None => v,
                };
                l.set("irradiance", v);
            }
            match (o.get("fov"), o.get("focal_length")) {
                (Some(f), _) => {
                    l.put("fov", f.f64()?, f.elem.main_pos);
                }
                (None, _) => {
                    let diag = (36.0f64 * 36.0 + 24.0 * 24.0).sqrt();
                    l.put("fov", 2.0 * (diag / 100.0).atan().to_degrees(), pos);
                    l.put("fov_axis", "diagonal", pos);
                    if let Some(p) = o.get("focal_length") {
                        b.warn(
                            p.elem,
                            "focal_length",
                            "a projector's focal_length is read as 50mm",
                        );
                    }
                }
            }
            copy(b, &o, &mut l, &["scale", "fov_axis"])?;
            &[
                "to_world",
                "irradiance",
                "fov",
                "fov_axis",
                "focal_length",
                "scale",
            ]
        }
        _ => unreachable!("area is handled above"),
    };
    sampling_weight(b, &o)?;
    o.finish(&[params, &["sampling_weight"]].concat())?;
    b.lights.push(l);
    Ok(())
}

/// Copies parameters of the same name and meaning.
fn copy<'e>(
    b: &mut Builder<'e>,
    o: &Obj<'e>,
    l: &mut Node,
    names: &[&str],
) -> Result<(), SceneError> {
    for n in names {
        if let Some(p) = o.get(n) {
            let v = value(b, p, true)?;
            l.set(n, v);
        }
    }
    Ok(())
}
