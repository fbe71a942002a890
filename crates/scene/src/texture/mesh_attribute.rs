//! Mitsuba 3's `mesh_attribute` texture: a per-vertex (interpolated) or per-face colour
//! stored on the mesh, times `scale`.
//!
//! The values come from the lookup ([`super::TextureQuery`]): the renderer passes the
//! hit's interpolated vertex colour or its face colour. The data path that would fill
//! them is not built yet: Irradia's mesh readers do not keep colours and a hit carries
//! none, so today every lookup sees `None` and gets black.

use irradia_core::Rgb;

/// Which mesh attribute is read (Mitsuba's `name` parameter).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshAttributeName {
    /// `"vertex_color"`: colours at the vertices, interpolated over each triangle.
    VertexColor,
    /// `"face_color"`: one colour per triangle.
    FaceColor,
}

impl MeshAttributeName {
    pub fn as_str(self) -> &'static str {
        match self {
            MeshAttributeName::VertexColor => "vertex_color",
            MeshAttributeName::FaceColor => "face_color",
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct MeshAttribute {
    pub name: MeshAttributeName,
    /// Multiplies the attribute (Mitsuba's default 1).
    pub scale: f32,
}

impl MeshAttribute {
    /// The attribute's value given the hit's vertex colour and face colour.
    pub fn eval(&self, vertex_color: Option<Rgb>, face_color: Option<Rgb>) -> Rgb {
        let v = match self.name {
            MeshAttributeName::VertexColor => vertex_color,
            MeshAttributeName::FaceColor => face_color,
        };
        v.unwrap_or(Rgb::BLACK) * self.scale
    }
}
