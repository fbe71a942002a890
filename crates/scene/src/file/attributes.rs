//! The load-time check of `mesh_attribute` textures (Mitsuba 3's texture plugin of
//! that name): for every object, each attribute its material reads must be one the
//! shape carries, with 1 channel where a number is read (a blend weight, a
//! roughness) and 1 or 3 where a colour is. Mitsuba reads a missing or mismatched
//! attribute as zero; a scene file that names one is a mistake found here instead,
//! an error at the object's `material` (exit 2).

use crate::bsdf::TextureParam;
use crate::material::Material;
use crate::texture::{ColorTexture, FloatTexture, MeshAttribute, TextureMap};
use irradia_geometry::mesh::MeshAttributes;

/// One mesh attribute a material reads.
#[derive(Clone, Debug, PartialEq)]
pub struct AttributeRead {
    /// The attribute's name (`vertex_color`).
    pub name: String,
    /// Where: `"plugin.parameter"` (`"blendbsdf.weight"`), or `"emission"`.
    pub param: String,
    /// Read as a number (Mitsuba's `eval_1`) rather than a colour.
    pub number: bool,
}

/// The mesh attributes `m` reads, in parameter order.
pub fn attribute_reads(m: &Material) -> Vec<AttributeRead> {
    let mut out = Vec::new();
    let mut add = |param: String, a: &MeshAttribute, number: bool| {
        out.push(AttributeRead {
            name: a.name.clone(),
            param,
            number,
        })
    };
    if let Some(d) = &m.bsdf {
        d.visit_textures(&mut |param, t| match t {
            TextureParam::Color(ColorTexture::Map(TextureMap::MeshAttribute(a))) => {
                add(param, a, false)
            }
            TextureParam::Number(FloatTexture::Map(TextureMap::MeshAttribute(a))) => {
                add(param, a, true)
            }
            _ => {}
        });
    }
    if let Some(TextureMap::MeshAttribute(a)) = &m.emission_texture {
        add("emission".into(), a, false);
    }
    out
}

/// Checks the attributes material `m` reads against a shape's (`attrs`, `None` for a
/// shape without any; `shape` names it in the message).
pub fn check_attributes(
    m: &Material,
    attrs: Option<&MeshAttributes>,
    shape: &str,
) -> Result<(), String> {
    for r in attribute_reads(m) {
        let Some(attrs) = attrs else {
            return Err(format!(
                "material '{}' reads the mesh attribute `{}` ({}), but a {shape} has no mesh attributes",
                m.name, r.name, r.param
            ));
        };
        let Some(a) = attrs.get(&r.name) else {
            return Err(format!(
                "material '{}' reads the mesh attribute `{}` ({}), which this {shape} does not have (its attributes: {})",
                m.name,
                r.name,
                r.param,
                attrs.describe()
            ));
        };
        if r.number && a.channels() != 1 {
            return Err(format!(
                "material '{}' reads the mesh attribute `{}` as a number ({}), but it has {} channels: a number needs a 1-channel attribute",
                m.name,
                r.name,
                r.param,
                a.channels()
            ));
        }
    }
    Ok(())
}
