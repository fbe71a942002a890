//! Textures of the physically based materials: Mitsuba 3's texture plugins (`bitmap`,
//! `checkerboard`, `mesh_attribute`) wherever a BSDF parameter accepts a texture, as a
//! colour ([`ColorTexture`]) or a number ([`FloatTexture`]: roughness, opacity, blend
//! weight). The lecture materials keep their own [`crate::Texture`].

pub mod bitmap;
pub mod checkerboard;
pub mod cie;
pub mod mesh_attribute;
pub mod spectrum;
pub mod uv_transform;

pub use bitmap::{Bitmap, FilterType, Texels, WrapMode};
pub use checkerboard::Checkerboard;
pub use mesh_attribute::MeshAttribute;
pub use uv_transform::UvTransform;

use glam::Vec2;
use irradia_core::Rgb;
use irradia_geometry::mesh::AttributePoint;
use std::sync::Arc;

/// What a texture lookup knows about the surface point (Mitsuba's
/// `SurfaceInteraction` as far as its textures read it).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TextureQuery<'a> {
    /// Surface coordinates.
    pub uv: Vec2,
    /// Where the point lies on the attributes of the mesh hit (its triangle and
    /// barycentric coordinates), for [`MeshAttribute`]; `None` off meshes with
    /// attributes.
    pub attributes: Option<AttributePoint<'a>>,
}

impl TextureQuery<'_> {
    pub fn at_uv(uv: Vec2) -> Self {
        TextureQuery {
            uv,
            attributes: None,
        }
    }
}

/// A texture plugin (one that varies over the surface).
#[derive(Clone, Debug, PartialEq)]
pub enum TextureMap {
    Bitmap(Arc<Bitmap>),
    Checkerboard(Checkerboard),
    MeshAttribute(MeshAttribute),
}

/// Mitsuba's `luminance()` (Rec. 709 / sRGB primaries), how its textures give one number
/// from a colour.
pub fn mitsuba_luminance(c: Rgb) -> f32 {
    0.212671 * c.r + 0.715160 * c.g + 0.072169 * c.b
}

impl TextureMap {
    /// The colour at the point (Mitsuba's `Texture::eval`).
    pub fn eval(&self, q: &TextureQuery) -> Rgb {
        match self {
            TextureMap::Bitmap(b) => b.eval(q.uv),
            TextureMap::Checkerboard(c) => c.eval(q.uv),
            TextureMap::MeshAttribute(m) => m.eval(q),
        }
    }

    /// The number at the point (Mitsuba's `Texture::eval_1`): a one-channel bitmap's
    /// value, a one-channel mesh attribute, the luminance of a colour.
    pub fn eval_1(&self, q: &TextureQuery) -> f32 {
        match self {
            TextureMap::Bitmap(b) if b.texels.channels == 1 => b.eval(q.uv).r,
            TextureMap::Checkerboard(c) => mitsuba_luminance(c.eval_1_color(q.uv)),
            TextureMap::MeshAttribute(m) => m.eval_1(q),
            _ => mitsuba_luminance(self.eval(q)),
        }
    }

    /// The mean over the texture's domain: a bitmap's mean texel, a checkerboard's mean
    /// of its two colours, a mesh attribute's `scale` × 0.5 (the data is not known
    /// when the scene is read).
    pub fn mean(&self) -> Rgb {
        match self {
            TextureMap::Bitmap(b) => b.texels.mean(),
            TextureMap::Checkerboard(c) => (c.color0 + c.color1) * 0.5,
            TextureMap::MeshAttribute(m) => Rgb::splat(0.5 * m.scale),
        }
    }
}

/// A colour parameter: a constant (a colour or a spectrum reduced to RGB) or a texture.
#[derive(Clone, Debug, PartialEq)]
pub enum ColorTexture {
    Value(Rgb),
    Map(TextureMap),
}

impl ColorTexture {
    pub fn eval(&self, q: &TextureQuery) -> Rgb {
        match self {
            ColorTexture::Value(c) => *c,
            ColorTexture::Map(m) => m.eval(q),
        }
    }

    /// The constant, or the texture's mean ([`TextureMap::mean`]).
    pub fn mean(&self) -> Rgb {
        match self {
            ColorTexture::Value(c) => *c,
            ColorTexture::Map(m) => m.mean(),
        }
    }
}

impl From<Rgb> for ColorTexture {
    fn from(c: Rgb) -> Self {
        ColorTexture::Value(c)
    }
}

/// A number parameter (roughness, opacity, blend weight): a constant or a texture.
#[derive(Clone, Debug, PartialEq)]
pub enum FloatTexture {
    Value(f32),
    Map(TextureMap),
}

impl FloatTexture {
    pub fn eval(&self, q: &TextureQuery) -> f32 {
        match self {
            FloatTexture::Value(v) => *v,
            FloatTexture::Map(m) => m.eval_1(q),
        }
    }

    /// The constant, or the luminance of the texture's mean.
    pub fn mean(&self) -> f32 {
        match self {
            FloatTexture::Value(v) => *v,
            FloatTexture::Map(m) => mitsuba_luminance(m.mean()),
        }
    }
}

impl From<f32> for FloatTexture {
    fn from(v: f32) -> Self {
        FloatTexture::Value(v)
    }
}
