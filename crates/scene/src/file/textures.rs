//! Reading the physically based materials' parameters: colours (a number, `[r, g, b]`,
//! or a "wavelength:value, ..." spectrum), numbers, and Mitsuba texture tables
//! (`bitmap`, `checkerboard`, `mesh_attribute`) with their `to_uv` transform
//! (docs/scene-format.md, "Textures").

use super::reader::{Result, Table, Val};
use crate::texture::bitmap::read_texels_selected;
use crate::texture::spectrum::{parse_spectrum, spectrum_to_rgb};
use crate::texture::{
    Bitmap, Checkerboard, ColorTexture, FilterType, FloatTexture, MeshAttribute, TextureMap,
    UvTransform, WrapMode,
};
use glam::{Affine2, Mat2, Vec2};
use irradia_core::Rgb;
use std::sync::Arc;

/// A constant colour: a number (grey), `[r, g, b]`, or a "wavelength:value, ..."
/// reflectance spectrum reduced to RGB as Mitsuba's rgb variants do.
pub fn read_rgb(v: &Val) -> Result<Rgb> {
    if v.is_str() {
        let (w, values) = parse_spectrum(v.str()?).map_err(|e| v.err(e.to_string()))?;
        return Ok(spectrum_to_rgb(&w, &values));
    }
    v.rgb()
}

/// A colour parameter: a constant ([`read_rgb`]) or a texture table.
pub fn read_color_texture(v: &Val) -> Result<ColorTexture> {
    if v.is_table() {
        return Ok(ColorTexture::Map(read_texture_map(v)?));
    }
    Ok(ColorTexture::Value(read_rgb(v).map_err(|e| {
        if v.is_number() || v.is_array() || v.is_str() {
            e
        } else {
            v.err(format!(
                "expected a colour (a number, [r, g, b] or \"wavelength:value, ...\") or a texture table, found {}",
                v.node.value.type_name()
            ))
        }
    })?))
}

/// A colour parameter of `t`, or `default`.
pub fn color_or(t: &Table, key: &'static str, default: Rgb) -> Result<ColorTexture> {
    t.get(key)
        .map_or(Ok(ColorTexture::Value(default)), |v| read_color_texture(&v))
}

/// A number parameter that must not be negative: a number or a texture table.
pub fn read_float_texture(v: &Val) -> Result<FloatTexture> {
    if v.is_table() {
        return Ok(FloatTexture::Map(read_texture_map(v)?));
    }
    if !v.is_number() {
        return Err(v.err(format!(
            "expected a number or a texture table, found {}",
            v.node.value.type_name()
        )));
    }
    Ok(FloatTexture::Value(v.non_negative()?))
}

/// A number parameter of `t`, or `default`.
pub fn float_or(t: &Table, key: &'static str, default: f32) -> Result<FloatTexture> {
    t.get(key)
        .map_or(Ok(FloatTexture::Value(default)), |v| read_float_texture(&v))
}

/// `{ type = "bitmap" | "checkerboard" | "mesh_attribute", ... }`.
pub fn read_texture_map(v: &Val) -> Result<TextureMap> {
    let t = v.table()?;
    let kind = t
        .req("type")?
        .choice(&["bitmap", "checkerboard", "mesh_attribute"])?;
    let map = match kind {
        "bitmap" => TextureMap::Bitmap(Arc::new(read_bitmap(&t)?)),
        "checkerboard" => {
            let d = Checkerboard::default();
            TextureMap::Checkerboard(Checkerboard {
                color0: t.get("color0").map_or(Ok(d.color0), |c| read_rgb(&c))?,
                color1: t.get("color1").map_or(Ok(d.color1), |c| read_rgb(&c))?,
                to_uv: read_to_uv(t.get("to_uv"))?,
            })
        }
        _ => {
            // Mitsuba's rule: the name says where the values are.
            let name_v = t.req("name")?;
            let name = name_v.str()?;
            if irradia_geometry::mesh::AttributeDomain::of(name).is_none() {
                return Err(name_v.err(format!(
                    "a mesh attribute's name starts with `vertex_` or `face_` (got \"{name}\")"
                )));
            }
            TextureMap::MeshAttribute(MeshAttribute {
                name: name.to_string(),
                scale: t.non_negative_or("scale", 1.0)?,
            })
        }
    };
    t.finish()?;
    Ok(map)
}

fn read_bitmap(t: &Table) -> Result<Bitmap> {
    let file_v = t.req("filename")?;
    let filename = file_v.doc.resolve(file_v.str()?);
    let filter_type = match t.get("filter_type") {
        Some(f) => match f.choice(&["bilinear", "nearest"])? {
            "nearest" => FilterType::Nearest,
            _ => FilterType::Bilinear,
        },
        None => FilterType::Bilinear,
    };
    let wrap_mode = match t.get("wrap_mode") {
        Some(w) => match w.choice(&["repeat", "mirror", "clamp"])? {
            "mirror" => WrapMode::Mirror,
            "clamp" => WrapMode::Clamp,
            _ => WrapMode::Repeat,
        },
        None => WrapMode::Repeat,
    };
    let raw = t.bool_or("raw", false)?;
    let to_uv = read_to_uv(t.get("to_uv"))?;
    // `image = N`: the file is a glTF/GLB and the bitmap its image N.
    let image = match t.get("image") {
        Some(i) => {
            let ext = filename
                .extension()
                .and_then(|e| e.to_str())
                .map(str::to_ascii_lowercase);
            if !matches!(ext.as_deref(), Some("gltf" | "glb")) {
                return Err(i.err("`image` selects an image of a .gltf or .glb file"));
            }
            Some(i.u32()? as usize)
        }
        None => None,
    };
    let channel = match t.get("channel") {
        Some(c) => Some(match c.choice(&["r", "g", "b", "a"])? {
            "r" => 0,
            "g" => 1,
            "b" => 2,
            _ => 3,
        }),
        None => None,
    };
    let mut texels = read_texels_selected(&filename, raw, image, channel)
        .map_err(|e| file_v.err(format!("cannot load the bitmap: {e}")))?;
    if let Some(k) = t.get("scale") {
        let c = read_rgb(&k)?;
        if ![c.r, c.g, c.b].iter().all(|x| x.is_finite() && *x >= 0.0) {
            return Err(k.err("scale must be finite and not negative"));
        }
        texels.scale(c);
    }
    Ok(Bitmap {
        filename,
        texels,
        filter_type,
        wrap_mode,
        raw,
        to_uv,
    })
}

/// `to_uv = [{ scale = [2, 2] }, { translate = [0.5, 0] }, { rotate = 30 }]`: steps
/// applied in the order written (as object transforms are), or one
/// `{ matrix = [[a, b, tx], [c, d, ty]] }`; the identity when absent.
pub fn read_to_uv(v: Option<Val>) -> Result<UvTransform> {
    let Some(v) = v else {
        return Ok(UvTransform::default());
    };
    let mut m = Affine2::IDENTITY;
    for step in v.array()? {
        m = read_uv_step(&step)? * m;
    }
    let det = m.matrix2.determinant();
    if !(det.is_finite() && det != 0.0) {
        return Err(v.err("the uv transform is not invertible"));
    }
    Ok(UvTransform(m))
}

fn read_uv_step(step: &Val) -> Result<Affine2> {
    let t = step.table()?;
    let kinds = ["translate", "rotate", "scale", "matrix"];
    let present: Vec<Val> = kinds.iter().filter_map(|k| t.get(k)).collect();
    t.finish()?;
    let [v] = present.as_slice() else {
        return Err(
            step.err("each to_uv step must have exactly one of translate, rotate, scale, matrix")
        );
    };
    let key = v.path.rsplit('.').next().unwrap_or("");
    Ok(match key {
        "translate" => {
            let n = v.numbers(2)?;
            Affine2::from_translation(Vec2::new(n[0], n[1]))
        }
        "rotate" => Affine2::from_angle(v.f32()?.to_radians()),
        "scale" => {
            let s = if v.is_number() {
                Vec2::splat(v.f32()?)
            } else {
                let n = v.numbers(2)?;
                Vec2::new(n[0], n[1])
            };
            if s.x == 0.0 || s.y == 0.0 {
                return Err(v.err("scale factors must not be zero"));
            }
            Affine2::from_scale(s)
        }
        _ => {
            let rows = v.array()?;
            if rows.len() != 2 && rows.len() != 3 {
                return Err(v.err(format!(
                    "expected 2 or 3 rows of 3 numbers, found {} rows",
                    rows.len()
                )));
            }
            let r: Vec<Vec<f32>> = rows.iter().map(|r| r.numbers(3)).collect::<Result<_>>()?;
            if rows.len() == 3 && r[2] != [0.0, 0.0, 1.0] {
                return Err(rows[2].err("the last row of an affine uv matrix must be [0, 0, 1]"));
            }
            Affine2::from_mat2_translation(
                Mat2::from_cols(Vec2::new(r[0][0], r[1][0]), Vec2::new(r[0][1], r[1][1])),
                Vec2::new(r[0][2], r[1][2]),
            )
        }
    })
}
