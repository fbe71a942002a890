//! Materials: the lecture's Phong model with mirror reflection and transmission, the
//! POV-Ray finish variant of it, emission, and textures.
//!
//! Conventions (documented in docs/scene-format.md): a point light of intensity `I`
//! at distance `r` gives irradiance `I / r²`; the Phong diffuse term is
//! `diffuse * colour * I * cos θ / r²` (no 1/π), the specular term is
//! `specular * I * (R·V)^shininess / r²`, the ambient term `ambient * colour * ambient_light`.

use glam::Vec2;
use irradia_core::{Image, Rgb};
use std::sync::Arc;

use crate::bsdf::lecture::lecture_fields;
use crate::bsdf::BsdfDesc;
use crate::texture::{TextureMap, TextureQuery};

/// How the local (direct) part of a surface is shaded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ShadingModel {
    /// The lecture's Phong model.
    #[default]
    Phong,
    /// POV-Ray 3.7's `finish`: as Phong, but the local terms of a surface whose pigment
    /// filters light are scaled by `1 - transmission`, and highlights are not.
    PovRay,
}

/// A colour that may vary over the surface.
#[derive(Clone, Debug)]
pub enum Texture {
    Solid(Rgb),
    /// Alternating colours on a 3D grid of cubes of side `scale` (in world space).
    Checker {
        a: Rgb,
        b: Rgb,
        scale: f32,
    },
    /// An image looked up by the surface's (u, v), repeated; `scale` repeats per unit uv.
    Image {
        image: Arc<Image>,
        scale: Vec2,
    },
}

/// `x.floor() as i64` without the call to libm's `floorf` (x86-64's baseline has no
/// rounding instruction): truncate, then step down for negative non-integers. Same
/// result for every input, NaN (0) and the saturated ends included.
#[inline]
fn floor_i64(x: f32) -> i64 {
    let i = x as i64;
    i.saturating_sub((x < i as f32) as i64)
}

impl Texture {
    /// The colour at a world point `p` with surface coordinates `uv`.
    pub fn eval(&self, p: glam::Vec3, uv: Vec2) -> Rgb {
        match self {
            Texture::Solid(c) => *c,
            Texture::Checker { a, b, scale } => {
                let q = p / *scale;
                // A tiny bias keeps points that lie exactly on a cell face (a floor at
                // y = 0) on one side, as POV-Ray does.
                let s = floor_i64(q.x + 1e-4) + floor_i64(q.y + 1e-4) + floor_i64(q.z + 1e-4);
                if s.rem_euclid(2) == 0 {
                    *a
                } else {
                    *b
                }
            }
            Texture::Image { image, scale } => image_texel(image, uv * *scale),
        }
    }
}

/// The texel of `image` at `st` (surface coordinates times the repeat scale): repeated
/// (wrapped to [0, 1)), nearest texel, `v` running up the image. Black for an empty
/// image or a non-finite coordinate. The ray tracer and the rasterizer both look up
/// image textures through it, so they sample the same texel at the same point.
pub fn image_texel(image: &Image, st: Vec2) -> Rgb {
    let (w, h) = (image.width(), image.height());
    if w == 0 || h == 0 || !st.is_finite() {
        return Rgb::BLACK;
    }
    let x = ((st.x - st.x.floor()) * w as f32) as u32;
    let y = ((1.0 - (st.y - st.y.floor())) * h as f32) as u32;
    image.get(x.min(w - 1), y.min(h - 1))
}

#[derive(Clone, Debug)]
pub struct Material {
    pub name: String,
    /// Base colour (POV-Ray's pigment).
    pub color: Texture,
    /// Ambient coefficient k_a, times the scene's ambient light.
    pub ambient: f32,
    /// Diffuse coefficient k_d.
    pub diffuse: f32,
    /// Phong specular coefficient k_s.
    pub specular: f32,
    /// Phong exponent n.
    pub shininess: f32,
    /// Mirror reflectance k_r (the constant reflectance, or the weight of the Fresnel
    /// term when `fresnel` is set).
    pub reflection: Rgb,
    /// Transmitted fraction k_t (POV-Ray's filter): light passes through filtered by
    /// `filter_color`.
    pub transmission: f32,
    /// Colour the transmitted light is filtered by; `None` means the base colour.
    pub filter_color: Option<Rgb>,
    /// Index of refraction of the medium inside the surface.
    pub ior: f32,
    /// Use Fresnel's equations for reflection/transmission of dielectrics instead of the
    /// constant `reflection` (POV-Ray's default is constant).
    pub fresnel: bool,
    /// Emitted radiance, on the side the surface normal points to (out of solids); with
    /// an `emission_texture`, that texture's mean (what integrators that do not read
    /// textures emit).
    pub emission: Rgb,
    /// Emitted radiance that varies over the surface (Mitsuba's `area` emitter with a
    /// textured `radiance`): the texture at the point's uv. The path tracer and
    /// `direct` render it, at hits and at light samples.
    pub emission_texture: Option<TextureMap>,
    /// Emit on both sides of the surface (e.g. a closed room that glows inwards).
    pub emission_two_sided: bool,
    pub model: ShadingModel,
    /// The physically based description, when the scene gave a Mitsuba BSDF `type`; the
    /// lecture fields above are then derived from it ([`crate::bsdf::lecture`]).
    pub bsdf: Option<Arc<BsdfDesc>>,
}

impl Material {
    /// The radiance emitted at a point with surface coordinates `uv` (on the emitting
    /// side): the emission texture there, or the constant `emission`.
    #[inline]
    pub fn emission_at(&self, uv: Vec2) -> Rgb {
        self.emission_query(&TextureQuery::at_uv(uv))
    }

    /// [`Material::emission_at`] with everything a texture lookup may read (the
    /// mesh attributes at the point as well as its uv).
    #[inline]
    pub fn emission_query(&self, q: &TextureQuery) -> Rgb {
        match &self.emission_texture {
            Some(t) => t.eval(q),
            None => self.emission,
        }
    }

    /// A physically based material: `desc`, with the lecture fields that
    /// [`crate::bsdf::lecture::lecture_fields`] derives from it and the lecture's
    /// default ambient coefficient.
    pub fn from_bsdf(name: &str, desc: BsdfDesc) -> Material {
        let f = lecture_fields(&desc);
        Material {
            name: name.to_string(),
            color: f.color,
            diffuse: f.diffuse,
            specular: f.specular,
            shininess: f.shininess,
            reflection: f.reflection,
            transmission: f.transmission,
            filter_color: f.filter_color,
            ior: f.ior,
            fresnel: f.fresnel,
            bsdf: Some(Arc::new(desc)),
            ..Material::default()
        }
    }
}

impl Default for Material {
    fn default() -> Self {
        Self {
            name: "default".into(),
            color: Texture::Solid(Rgb::splat(0.8)),
            ambient: 0.1,
            diffuse: 0.8,
            specular: 0.0,
            shininess: 20.0,
            reflection: Rgb::BLACK,
            transmission: 0.0,
            filter_color: None,
            ior: 1.0,
            fresnel: false,
            emission: Rgb::BLACK,
            emission_texture: None,
            emission_two_sided: false,
            model: ShadingModel::Phong,
            bsdf: None,
        }
    }
}
