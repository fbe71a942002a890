//! The `[materials.NAME]` tables: the lecture's Phong coefficients, reflection,
//! transmission, emission and textures, or (with a `type`) a physically based material
//! read by [`super::bsdfs`] (see docs/scene-format.md for every field).

use super::bsdfs::{is_physically_based, BsdfResolver};
use super::reader::{unknown_name_message, Result, Val};
use crate::material::{Material, ShadingModel, Texture};
use glam::Vec2;

use std::sync::Arc;

/// Reads all named materials, in the order written.
pub fn read_materials(v: Option<Val>) -> Result<Vec<Material>> {
    let Some(v) = v else {
        return Ok(Vec::new());
    };
    let t = v.table()?;
    let entries = t.entries();
    let mut resolver = BsdfResolver::new(&entries);
    let mut out = Vec::new();
    for (name, m) in &entries {
        if is_physically_based(m) {
            let e = resolver.entry(name, m)?;
            out.push(Material {
                emission: e.emission,
                emission_texture: e.emission_texture,
                emission_two_sided: e.emission_two_sided,
                ..Material::from_bsdf(name, e.bsdf)
            });
        } else {
            out.push(read_material(name, m)?);
        }
    }
    Ok(out)
}

fn read_material(name: &str, v: &Val) -> Result<Material> {
    let t = v.table()?;
    let d = Material::default();
    let color = match (t.get("color"), t.get("pigment")) {
        (Some(_), Some(p)) => return Err(p.err("give either color or pigment, not both")),
        (Some(c), None) | (None, Some(c)) => read_texture(&c)?,
        (None, None) => d.color.clone(),
    };
    let filter = match (t.get("filter"), t.get("filter_color")) {
        (Some(_), Some(p)) => return Err(p.err("give either filter or filter_color, not both")),
        (Some(c), None) | (None, Some(c)) => Some(c.rgb()?),
        (None, None) => None,
    };
    let model = match t.get("model") {
        Some(m) => match m.choice(&["phong", "povray"])? {
            "povray" => ShadingModel::PovRay,
            _ => ShadingModel::Phong,
        },
        None => ShadingModel::Phong,
    };
    let (emission, emission_texture) = super::bsdfs::read_emission(t.get("emission"))?;
    let m = Material {
        name: name.to_string(),
        color,
        ambient: t.non_negative_or("ambient", d.ambient)?,
        diffuse: t.non_negative_or("diffuse", d.diffuse)?,
        specular: t.non_negative_or("specular", d.specular)?,
        shininess: t.non_negative_or("shininess", d.shininess)?,
        reflection: t.rgb_or("reflection", d.reflection)?,
        transmission: t
            .get("transmission")
            .map_or(Ok(d.transmission), |x| x.in_range(0.0, 1.0))?,
        filter_color: filter,
        ior: t.positive_or("ior", d.ior)?,
        fresnel: t.bool_or("fresnel", d.fresnel)?,
        emission,
        emission_texture,
        emission_two_sided: t.bool_or("emission_two_sided", d.emission_two_sided)?,
        model,
        bsdf: None,
    };
    t.finish()?;
    Ok(m)
}

/// A colour, or a texture table `{ type = "checker", colors = [a, b], scale = 1 }` /
/// `{ type = "image", path = "wood.png", scale = [1, 1] }`.
fn read_texture(v: &Val) -> Result<Texture> {
    if !v.is_table() {
        return Ok(Texture::Solid(v.rgb()?));
    }
    let t = v.table()?;
    let kind = t.req("type")?.choice(&["checker", "image"])?;
    let tex = match kind {
        "checker" => {
            let colors_v = t.req("colors")?;
            let colors = colors_v.array()?;
            if colors.len() != 2 {
                return Err(colors_v.err(format!(
                    "a checker needs exactly 2 colours, found {}",
                    colors.len()
                )));
            }
            Texture::Checker {
                a: colors[0].rgb()?,
                b: colors[1].rgb()?,
                scale: t.positive_or("scale", 1.0)?,
            }
        }
        _ => {
            let path_v = t.req("path")?;
            let path = path_v.doc.resolve(path_v.str()?);
            let image = irradia_core::io::load(&path)
                .map_err(|e| path_v.err(format!("cannot load the image texture: {e}")))?;
            let scale = match t.get("scale") {
                None => Vec2::ONE,
                Some(s) if s.is_number() => Vec2::splat(s.positive()?),
                Some(s) => {
                    let n = s.numbers(2)?;
                    if n[0] <= 0.0 || n[1] <= 0.0 {
                        return Err(s.err("scale factors must be positive"));
                    }
                    Vec2::new(n[0], n[1])
                }
            };
            Texture::Image {
                image: Arc::new(image),
                scale,
            }
        }
    };
    t.finish()?;
    Ok(tex)
}

/// Index of the material called `name`, or an error listing the defined ones.
pub fn material_index(materials: &[crate::Material], v: &Val) -> Result<u32> {
    let name = v.str()?;
    match materials.iter().position(|m| m.name == name) {
        Some(i) => Ok(i as u32),
        None => {
            let names: Vec<&str> = materials.iter().map(|m| m.name.as_str()).collect();
            Err(v.err(unknown_name_message("material", name, &names)))
        }
    }
}
