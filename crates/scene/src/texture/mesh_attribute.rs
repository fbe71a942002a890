//! Mitsuba 3's `mesh_attribute` texture (its plugin documentation, "Mesh attribute
//! texture"): the value of a named attribute of the mesh that was hit, times `scale`.
//!
//! `name` starts with `vertex_` (values at the vertices, interpolated over each
//! triangle with the hit's barycentric coordinates) or `face_` (one value per
//! triangle). The attributes are the mesh's ([`irradia_geometry::mesh::attributes`]):
//! PLY properties named as Mitsuba's `ply` plugin names them (`color_0..2` per vertex
//! is `vertex_color`, `weight_0` per face `face_weight`), vertex colours of OBJ and
//! glTF files as `vertex_color`. Values are used as they are stored (linear RGB, as in
//! Mitsuba's RGB variants).
//!
//! Evaluated as a colour (Mitsuba's `eval`), a 3-channel attribute is that colour and a
//! 1-channel one a grey; as a number (`eval_1`, a blend weight or a roughness) only a
//! 1-channel attribute is meaningful. The scene reader checks, for every object a
//! material is given to, that the shape has each attribute the material's textures
//! read with fitting channels ([`crate::file::attributes`]); a lookup without
//! the attribute (no mesh at the point) reads black.

use super::TextureQuery;
use irradia_core::Rgb;
use irradia_geometry::mesh::AttributeValue;

#[derive(Clone, Debug, PartialEq)]
pub struct MeshAttribute {
    /// The attribute's name (`vertex_...` or `face_...`).
    pub name: String,
    /// Multiplies the attribute (Mitsuba's default 1).
    pub scale: f32,
}

impl MeshAttribute {
    /// The attribute at the query's mesh point, `None` without one.
    fn value(&self, q: &TextureQuery) -> Option<AttributeValue> {
        q.attributes?.eval(&self.name)
    }

    /// As a colour: a 3-channel value, or a 1-channel one as a grey; times `scale`,
    /// negative values read as 0; black where the hit has no such attribute.
    pub fn eval(&self, q: &TextureQuery) -> Rgb {
        let c = match self.value(q) {
            Some(AttributeValue::Three(c)) => Rgb::new(c.x, c.y, c.z),
            Some(AttributeValue::One(v)) => Rgb::splat(v),
            None => return Rgb::BLACK,
        };
        let s = self.scale;
        Rgb::new((c.r * s).max(0.0), (c.g * s).max(0.0), (c.b * s).max(0.0))
    }

    /// As a number: a 1-channel value times `scale`, not below 0; 0 for a 3-channel
    /// attribute (Mitsuba's `eval_attribute_1` reads a mismatched attribute as zero;
    /// the scene reader refuses that use) and where the hit has no such attribute.
    pub fn eval_1(&self, q: &TextureQuery) -> f32 {
        match self.value(q) {
            Some(AttributeValue::One(v)) => (v * self.scale).max(0.0),
            _ => 0.0,
        }
    }
}
