//! `<bsdf>` and `<texture>`: Irradia's physically based materials are Mitsuba's
//! BSDFs with Mitsuba's parameter names, so a BSDF becomes a material table of the
//! same `type` with the same parameters; values become numbers, colours, spectra
//! (the wavelength:value text, which Irradia reduces to RGB as Mitsuba does) or
//! texture tables.

use super::props::{Obj, Prop, Val};
use super::xml::Elem;
use super::Builder;
use irradia_scene::file::tree::Node;
use irradia_scene::SceneError;
use std::path::Path;

/// The image files Irradia's `bitmap` reads.
pub const BITMAP_EXTENSIONS: &[&str] = &["png", "jpg", "jpeg", "exr", "hdr", "bmp"];

/// The BSDFs Irradia renders and the parameters each passes on unchanged.
const BSDFS: &[(&str, &[&str])] = &[
    ("diffuse", &["reflectance"]),
    (
        "conductor",
        &["material", "eta", "k", "specular_reflectance"],
    ),
    (
        "roughconductor",
        &[
            "material",
            "eta",
            "k",
            "specular_reflectance",
            "distribution",
            "alpha",
            "alpha_u",
            "alpha_v",
            "sample_visible",
        ],
    ),
    (
        "dielectric",
        &[
            "int_ior",
            "ext_ior",
            "specular_reflectance",
            "specular_transmittance",
        ],
    ),
    (
        "roughdielectric",
        &[
            "int_ior",
            "ext_ior",
            "specular_reflectance",
            "specular_transmittance",
            "distribution",
            "alpha",
            "alpha_u",
            "alpha_v",
            "sample_visible",
        ],
    ),
    (
        "thindielectric",
        &[
            "int_ior",
            "ext_ior",
            "specular_reflectance",
            "specular_transmittance",
        ],
    ),
    (
        "plastic",
        &[
            "diffuse_reflectance",
            "specular_reflectance",
            "int_ior",
            "ext_ior",
            "nonlinear",
        ],
    ),
    (
        "roughplastic",
        &[
            "diffuse_reflectance",
            "specular_reflectance",
            "int_ior",
            "ext_ior",
            "nonlinear",
            "distribution",
            "alpha",
            "sample_visible",
        ],
    ),
    (
        "principled",
        &[
            "base_color",
            "roughness",
            "anisotropic",
            "metallic",
            "spec_trans",
            "spec_tint",
            "sheen",
            "sheen_tint",
            "flatness",
            "clearcoat",
            "clearcoat_gloss",
            "eta",
            "specular",
            "main_specular_sampling_rate",
            "clearcoat_sampling_rate",
            "diffuse_reflectance_sampling_rate",
        ],
    ),
    (
        "principledthin",
        &[
            "base_color",
            "roughness",
            "anisotropic",
            "spec_trans",
            "spec_tint",
            "sheen",
            "sheen_tint",
            "flatness",
            "diff_trans",
            "eta",
            "specular_reflectance_sampling_rate",
            "diffuse_reflectance_sampling_rate",
            "diffuse_transmittance_sampling_rate",
            "specular_transmittance_sampling_rate",
        ],
    ),
    ("blendbsdf", &["weight"]),
    ("mask", &["opacity"]),
    ("twosided", &[]),
    ("bumpmap", &["scale"]),
    ("normalmap", &["normalmap"]),
];

/// Mitsuba's BSDFs that Irradia does not render.
const UNRENDERED: &[&str] = &[
    "hair",
    "measured",
    "measured_polarized",
    "null",
    "polarizer",
    "pplastic",
    "retarder",
    "circular",
];

/// The material name for a `<bsdf>` (or a `<ref>` to one), converting it into
/// `[materials]` the first time.
pub fn material_name<'e>(b: &mut Builder<'e>, e: &'e Elem) -> Result<String, SceneError> {
    let e = if e.tag == "ref" {
        e.check_attrs(&["id", "name"])?;
        let target = b.lookup(e, e.req("id")?)?;
        if target.tag != "bsdf" {
            return Err(e.err_at(
                "id",
                "id",
                format!("`{}` is a <{}>, not a <bsdf>", e.req("id")?, target.tag),
            ));
        }
        target
    } else {
        e
    };
    let key = e as *const Elem;
    if let Some(n) = b.material_names.get(&key) {
        return Ok(n.clone());
    }
    if b.converting.contains(&key) {
        return Err(e.err("bsdf", "BSDFs refer to each other in a cycle"));
    }
    b.converting.push(key);
    let table = bsdf_table(b, e);
    b.converting.pop();
    let table = table?;
    let base = match e.get("id") {
        Some(id) => id.to_string(),
        None => e.get("type").unwrap_or("bsdf").to_string(),
    };
    let name = b.unique(&base);
    b.materials.set(&name, table);
    b.material_names.insert(key, name.clone());
    Ok(name)
}

/// A nested BSDF: a material name when it has an id (or is a reference), else an
/// inline table.
fn nested<'e>(b: &mut Builder<'e>, e: &'e Elem) -> Result<Node, SceneError> {
    if e.tag == "ref" || e.get("id").is_some() {
        let n = material_name(b, e)?;
        return Ok(Node::new(n, e.main_pos));
    }
    bsdf_table(b, e)
}

/// Mitsuba's default BSDF of a shape that names none: diffuse with reflectance 0.5,
/// or 0 when the shape carries an area emitter (Mitsuba 3's `Shape` constructor: an
/// emitter without a BSDF reflects nothing).
pub fn default_material(b: &mut Builder, emitter: bool) -> String {
    let name = if emitter {
        "mitsuba_default_emitter"
    } else {
        "mitsuba_default"
    };
    if !b.used_names.contains(name) {
        b.used_names.insert(name.into());
        let mut t = Node::table(0);
        t.put("type", "diffuse", 0);
        if emitter {
            t.put("reflectance", 0.0, 0);
        }
        b.materials.set(name, t);
    }
    name.into()
}

/// The material table of a `<bsdf>` element.
pub fn bsdf_table<'e>(b: &mut Builder<'e>, e: &'e Elem) -> Result<Node, SceneError> {
    let o = Obj::read(e)?;
    let pos = e.main_pos;
    let kind = o.plugin.as_str();
    let mut t = Node::table(pos);
    let Some(&(_, params)) = BSDFS.iter().find(|(k, _)| *k == kind) else {
        if UNRENDERED.contains(&kind) {
            b.warn(
                e,
                "type",
                format!(
                    "the `{kind}` BSDF is not rendered: a diffuse BSDF (reflectance 0.5) stands in"
                ),
            );
            t.put("type", "diffuse", pos);
            for p in &o.props {
                p.used.set(true);
            }
            return Ok(t);
        }
        let valid: Vec<&str> = BSDFS
            .iter()
            .map(|(k, _)| *k)
            .chain(UNRENDERED.iter().copied())
            .collect();
        return Err(e.err_at(
            "type",
            "type",
            format!("unknown BSDF `{kind}` (valid: {})", valid.join(", ")),
        ));
    };
    t.put("type", kind, pos);
    for &p in params {
        if let Some(prop) = o.get(p) {
            let v = value(b, prop, false)?;
            t.set(p, v);
        }
    }
    let bsdfs: Vec<&'e Elem> = o
        .nested
        .iter()
        .copied()
        .filter(|c| {
            c.tag == "bsdf"
                || (c.tag == "ref"
                    && b.ids
                        .get(c.get("id").unwrap_or(""))
                        .is_some_and(|x| x.tag == "bsdf"))
        })
        .collect();
    let textures: Vec<&'e Elem> = o
        .nested
        .iter()
        .copied()
        .filter(|c| !bsdfs.iter().any(|x| std::ptr::eq(*x, *c)))
        .collect();
    let want = match kind {
        "blendbsdf" => 2..=2,
        "twosided" => 1..=2,
        "mask" | "bumpmap" | "normalmap" => 1..=1,
        _ => 0..=0,
    };
    if !want.contains(&bsdfs.len()) {
        let at = bsdfs.get(*want.end()).copied().unwrap_or(e);
        return Err(at.err(
            "bsdf",
            format!(
                "`{kind}` takes {} nested BSDF{} (got {})",
                if want.start() == want.end() {
                    want.start().to_string()
                } else {
                    format!("{} or {}", want.start(), want.end())
                },
                if *want.end() == 1 { "" } else { "s" },
                bsdfs.len()
            ),
        ));
    }
    let mut inner = Vec::new();
    for c in &bsdfs {
        inner.push(nested(b, c)?);
    }
    match (kind, inner.len()) {
        ("blendbsdf", _) | ("twosided", 2) => {
            t.set("bsdfs", Node::new(inner, pos));
        }
        (_, 1) => {
            t.set("bsdf", inner.pop().unwrap());
        }
        _ => {}
    }
    if kind == "bumpmap" {
        // Mitsuba's bump map takes its one texture whatever its name.
        let named: Vec<&Prop> = o
            .props
            .iter()
            .filter(|p| !p.used.get() && matches!(p.val, Val::Object(_) | Val::Ref(_)))
            .collect();
        let tex = match (named.as_slice(), textures.as_slice()) {
            ([p], []) => {
                p.used.set(true);
                value(b, p, false)?
            }
            ([], [c]) => texture(b, c)?,
            _ => return Err(e.err("texture", "`bumpmap` takes one nested texture (the height)")),
        };
        t.set("texture", tex);
    } else if let Some(c) = textures.first() {
        return Err(c.err(
            &c.tag,
            format!("a nested <{}> needs a name (the parameter it sets)", c.tag),
        ));
    }
    o.finish(params)?;
    Ok(t)
}

/// A property as an Irradia value: a number, colour, spectrum text, string, boolean
/// or texture table. `emitter` spectra are reduced to RGB here (unbounded, without
/// the D65 weighting, as Mitsuba's rgb variants do for emitters).
pub fn value<'e>(b: &mut Builder<'e>, p: &Prop<'e>, emitter: bool) -> Result<Node, SceneError> {
    let pos = p.elem.main_pos;
    Ok(match &p.val {
        Val::Float(x) | Val::SpectrumConst(x) => Node::new(*x, pos),
        Val::Int(i) => Node::new(*i, pos),
        Val::Bool(v) => Node::new(*v, pos),
        Val::Str(s) => Node::new(s.as_str(), pos),
        Val::Rgb(c) => Node::new(*c, pos),
        Val::SpectrumList(text, w, v) => {
            if emitter {
                Node::new(emitter_spectrum_rgb(w, v), pos)
            } else {
                Node::new(text.as_str(), pos)
            }
        }
        Val::Point(v) | Val::Vector(v) => Node::new([v.x, v.y, v.z], pos),
        Val::Transform(_) => return Err(p.err(format!("`{}` does not take a transform", p.name))),
        Val::Object(e) => match e.tag.as_str() {
            "texture" => texture(b, e)?,
            "spectrum" | "rgb" => spectrum_object(b, e)?,
            t => {
                return Err(p.err(format!(
                    "`{}` takes a value or a texture, not a <{t}>",
                    p.name
                )))
            }
        },
        Val::Ref(id) => {
            let target = b.lookup(p.elem, id)?;
            match target.tag.as_str() {
                "texture" => texture(b, target)?,
                "bsdf" => Node::new(material_name(b, target)?, pos),
                t => return Err(p.err(format!("`{id}` is a <{t}>; `{}` takes a texture", p.name))),
            }
        }
    })
}

/// `<spectrum type=...>` plugins: `uniform` and `srgb` hold a constant; others are
/// not rendered.
fn spectrum_object<'e>(b: &mut Builder<'e>, e: &'e Elem) -> Result<Node, SceneError> {
    let o = Obj::read(e)?;
    let pos = e.main_pos;
    let out = match o.plugin.as_str() {
        "uniform" => {
            let v = o.get("value").map_or(Ok(1.0), |p| p.f64())?;
            Node::new(v, pos)
        }
        "srgb" => match o.get("color") {
            Some(p) => value(b, p, false)?,
            None => return Err(e.err("color", "`srgb` needs `color`")),
        },
        k @ ("blackbody" | "d65" | "regular" | "irregular") => {
            b.warn(
                e,
                "type",
                format!("the `{k}` spectrum is not rendered: 1 stands in"),
            );
            for p in &o.props {
                p.used.set(true);
            }
            Node::new(1.0, pos)
        }
        k => {
            return Err(e.err_at(
                "type",
                "type",
                format!(
                "unknown spectrum `{k}` (valid: uniform, srgb, blackbody, d65, regular, irregular)"
            ),
            ))
        }
    };
    o.finish(&["value", "color"])?;
    Ok(out)
}

/// A `<texture>` as Irradia's texture table (or a constant colour for
/// `rawconstant`).
pub fn texture<'e>(b: &mut Builder<'e>, e: &'e Elem) -> Result<Node, SceneError> {
    if e.tag == "ref" {
        let target = b.lookup(e, e.req("id")?)?;
        return texture(b, target);
    }
    if e.tag != "texture" {
        return Err(e.err(&e.tag, format!("expected a <texture>, found <{}>", e.tag)));
    }
    let o = Obj::read(e)?;
    let pos = e.main_pos;
    let mut t = Node::table(pos);
    let kind = o.plugin.as_str();
    let params: &[&str] = match kind {
        "bitmap" => {
            t.put("type", "bitmap", pos);
            let f = o.get("filename").ok_or_else(|| e.err("filename", "`bitmap` needs `filename`"))?;
            let path = b.file(e, f.elem, f.str()?)?;
            let ext = Path::new(&path)
                .extension()
                .and_then(|x| x.to_str())
                .unwrap_or("")
                .to_ascii_lowercase();
            if !BITMAP_EXTENSIONS.contains(&ext.as_str()) {
                b.warn(f.elem, "filename", format!("Irradia does not read .{ext} images (it reads {}): 0.5 stands in for `{path}`", BITMAP_EXTENSIONS.join(", ")));
                for p in &o.props {
                    p.used.set(true);
                }
                return Ok(Node::new(0.5, pos));
            }
            t.put("filename", path, f.elem.main_pos);
            for n in ["filter_type", "wrap_mode", "raw"] {
                if let Some(p) = o.get(n) {
                    let v = value(b, p, false)?;
                    t.set(n, v);
                }
            }
            o.accept(&["format", "accel"]);
            &["filename", "filter_type", "wrap_mode", "raw", "to_uv", "format", "accel"]
        }
        "checkerboard" => {
            t.put("type", "checkerboard", pos);
            for n in ["color0", "color1"] {
                if let Some(p) = o.get(n) {
                    let v = value(b, p, false)?;
                    t.set(n, v);
                }
            }
            &["color0", "color1", "to_uv"]
        }
        "mesh_attribute" => {
            // Mitsuba's plugin: `name` (`vertex_...` or `face_...`, else an error) and
            // `scale`; the scene reader checks the name against each mesh it is used on.
            let p = o.get("name").ok_or_else(|| e.err("name", "`mesh_attribute` needs `name`"))?;
            let name = p.str()?;
            if !name.starts_with("vertex_") && !name.starts_with("face_") {
                return Err(p.err(format!("a mesh attribute's name starts with `vertex_` or `face_` (got `{name}`)")));
            }
            t.put("type", "mesh_attribute", pos);
            for n in ["name", "scale"] {
                if let Some(p) = o.get(n) {
                    let v = value(b, p, false)?;
                    t.set(n, v);
                }
            }
            &["name", "scale"]
        }
        "rawconstant" => {
            let v = o.get("value").ok_or_else(|| e.err("value", "`rawconstant` needs `value`"))?;
            let node = value(b, v, false)?;
            o.finish(&["value"])?;
            return Ok(node);
        }
        "volume" => {
            b.warn(e, "type", "the `volume` texture is not rendered: 0.5 stands in");
            for p in &o.props {
                p.used.set(true);
            }
            return Ok(Node::new(0.5, pos));
        }
        k => {
            return Err(e.err_at("type", "type", format!("unknown texture `{k}` (valid: bitmap, checkerboard, mesh_attribute, rawconstant, volume)")))
        }
    };
    if let Some(p) = o.get("to_uv") {
        let x = p.transform()?;
        if !x.uv_steps.is_empty() {
            t.set("to_uv", Node::new(x.uv_steps.clone(), p.elem.main_pos));
        }
    }
    if let Some(c) = o.nested.first() {
        return Err(c.err(&c.tag, format!("<{}> does not belong in a texture", c.tag)));
    }
    o.finish(params)?;
    Ok(t)
}

/// An emitter's wavelength:value spectrum in linear sRGB: Mitsuba's
/// `spectrum_list_to_srgb(.., bounded = false, d65 = false)`.
pub fn emitter_spectrum_rgb(wavelengths: &[f64], values: &[f64]) -> [f64; 3] {
    // Irradia's colours are not negative; an out-of-gamut emitter is clipped.
    irradia_scene::texture::spectrum::spectrum_to_linear_srgb(wavelengths, values, |_| 1.0)
        .map(|c| c.max(0.0))
}
