//! The one rule that gives a physically based material the lecture's fields (colour,
//! k_d, k_s, Phong exponent, mirror reflection, transmission, IOR, Fresnel), so the
//! Whitted tracer, the rasterizer and radiosity render it without knowing about BSDFs.
//! docs/scene-format.md ("The lecture fields of a physically based material") states the
//! same rule as a table.
//!
//! - Textured parameters count by their mean ([`crate::texture::ColorTexture::mean`]),
//!   except a colour `bitmap` with `wrap_mode = "repeat"` whose `to_uv` is a pure scale:
//!   it becomes the lecture's image texture (rows flipped, as the lecture's v runs up).
//! - Smooth lobes are mirrors (`reflection`) or refraction (`transmission`, `ior`,
//!   `fresnel`); rough lobes are Phong highlights (`specular`) with the exponent of the
//!   same width, `n = 2/α² - 2` (Walter et al. 2007, "Microfacet models for refraction
//!   through rough surfaces", section 5.2), α floored at 0.01.
//! - Layered materials (blend, mask, twosided, bumpmap, normalmap) take their nested
//!   materials' fields: blend mixes them by its mean weight, mask adds `1 - opacity`
//!   of straight transmission, the others pass the (front) nested material through.

use super::{conductor_f0, dielectric_f0, BsdfDesc, Conductor, Dielectric, Plastic};
use crate::material::Texture;
use crate::texture::{ColorTexture, TextureMap, WrapMode};
use irradia_core::{Image, Rgb};
use std::sync::Arc;

/// The lecture fields of [`crate::Material`] that a BSDF description sets.
#[derive(Clone, Debug)]
pub struct LectureFields {
    pub color: Texture,
    pub diffuse: f32,
    pub specular: f32,
    pub shininess: f32,
    pub reflection: Rgb,
    pub transmission: f32,
    pub filter_color: Option<Rgb>,
    pub ior: f32,
    pub fresnel: bool,
}

impl Default for LectureFields {
    fn default() -> Self {
        LectureFields {
            color: Texture::Solid(Rgb::BLACK),
            diffuse: 0.0,
            specular: 0.0,
            shininess: 20.0,
            reflection: Rgb::BLACK,
            transmission: 0.0,
            filter_color: None,
            ior: 1.0,
            fresnel: false,
        }
    }
}

/// The Phong exponent whose lobe is as wide as a microfacet lobe of roughness `alpha`.
pub fn phong_exponent(alpha: f32) -> f32 {
    let a = alpha.max(0.01);
    2.0 / (a * a) - 2.0
}

/// A colour parameter as a lecture texture (module doc).
pub fn lecture_texture(c: &ColorTexture) -> Texture {
    if let ColorTexture::Map(TextureMap::Bitmap(b)) = c {
        if let (WrapMode::Repeat, Some(scale)) = (b.wrap_mode, b.to_uv.as_scale()) {
            if scale.x > 0.0 && scale.y > 0.0 {
                let t = &b.texels;
                let pixels = (0..t.height)
                    .rev()
                    .flat_map(|y| (0..t.width).map(move |x| t.get(x, y)))
                    .collect();
                let image = Image::from_pixels(t.width, t.height, pixels);
                return Texture::Image {
                    image: Arc::new(image),
                    scale,
                };
            }
        }
    }
    Texture::Solid(c.mean())
}

fn conductor(c: &Conductor) -> Rgb {
    conductor_f0(c.eta.mean(), c.k.mean()) * c.specular_reflectance.mean()
}

fn smooth_dielectric(d: &Dielectric) -> LectureFields {
    LectureFields {
        color: lecture_texture(&d.specular_transmittance),
        reflection: d.specular_reflectance.mean(),
        transmission: 1.0,
        filter_color: Some(d.specular_transmittance.mean()),
        ior: d.eta(),
        fresnel: true,
        ..Default::default()
    }
}

fn plastic_base(p: &Plastic) -> LectureFields {
    LectureFields {
        color: lecture_texture(&p.diffuse_reflectance),
        diffuse: 1.0,
        ior: p.int_ior / p.ext_ior,
        ..Default::default()
    }
}

/// A weighted mix of two lecture materials: numbers and colours mix linearly; the
/// colour texture, filter colour and Fresnel switch come from the heavier side.
fn mix(a: LectureFields, b: LectureFields, w: f32) -> LectureFields {
    let lerp = |x: f32, y: f32| x * (1.0 - w) + y * w;
    let heavy = if w > 0.5 { &b } else { &a };
    let color = match (&a.color, &b.color) {
        (Texture::Solid(x), Texture::Solid(y)) => Texture::Solid(*x * (1.0 - w) + *y * w),
        _ => heavy.color.clone(),
    };
    LectureFields {
        color,
        diffuse: lerp(a.diffuse, b.diffuse),
        specular: lerp(a.specular, b.specular),
        shininess: lerp(a.shininess, b.shininess),
        reflection: a.reflection * (1.0 - w) + b.reflection * w,
        transmission: lerp(a.transmission, b.transmission),
        filter_color: heavy.filter_color,
        ior: lerp(a.ior, b.ior),
        fresnel: heavy.fresnel,
    }
}

/// The lecture fields of `desc` (module doc; docs/scene-format.md has the table).
pub fn lecture_fields(desc: &BsdfDesc) -> LectureFields {
    match desc {
        BsdfDesc::Diffuse(d) => LectureFields {
            color: lecture_texture(&d.reflectance),
            diffuse: 1.0,
            ..Default::default()
        },
        BsdfDesc::Conductor(c) => {
            let f = conductor(c);
            LectureFields {
                color: Texture::Solid(f),
                reflection: f,
                ..Default::default()
            }
        }
        BsdfDesc::RoughConductor(c, m) => {
            let f = conductor(c);
            LectureFields {
                color: Texture::Solid(f),
                specular: f.mean(),
                shininess: phong_exponent(m.alpha.mean_alpha()),
                ..Default::default()
            }
        }
        BsdfDesc::Dielectric(d) => smooth_dielectric(d),
        BsdfDesc::RoughDielectric(d, m) => LectureFields {
            specular: dielectric_f0(d.eta()) * d.specular_reflectance.mean().mean(),
            shininess: phong_exponent(m.alpha.mean_alpha()),
            reflection: Rgb::BLACK,
            ..smooth_dielectric(d)
        },
        BsdfDesc::ThinDielectric(d) => {
            // A slab's reflectance at normal incidence, with every internal bounce.
            let r = dielectric_f0(d.eta());
            let slab = 2.0 * r / (1.0 + r);
            LectureFields {
                color: lecture_texture(&d.specular_transmittance),
                reflection: d.specular_reflectance.mean() * slab,
                transmission: 1.0 - slab,
                filter_color: Some(d.specular_transmittance.mean()),
                ..Default::default()
            }
        }
        BsdfDesc::Plastic(p) => LectureFields {
            reflection: p.specular_reflectance.mean(),
            fresnel: true,
            ..plastic_base(p)
        },
        BsdfDesc::RoughPlastic(p, r) => LectureFields {
            specular: dielectric_f0(p.int_ior / p.ext_ior) * p.specular_reflectance.mean().mean(),
            shininess: phong_exponent(r.alpha),
            ..plastic_base(p)
        },
        BsdfDesc::Principled(p) => {
            let metallic = p.metallic.mean().clamp(0.0, 1.0);
            let trans = p.spec_trans.mean().clamp(0.0, 1.0);
            let eta = p.specular.eta();
            let rough = p.roughness.mean();
            LectureFields {
                color: lecture_texture(&p.base_color),
                diffuse: (1.0 - metallic) * (1.0 - trans),
                specular: dielectric_f0(eta) * (1.0 - metallic) + metallic,
                shininess: phong_exponent(rough * rough),
                transmission: (1.0 - metallic) * trans,
                filter_color: (trans > 0.0).then(|| p.base_color.mean()),
                ior: eta,
                fresnel: trans > 0.0,
                ..Default::default()
            }
        }
        BsdfDesc::PrincipledThin(p) => {
            let trans = p.spec_trans.mean().clamp(0.0, 1.0);
            let rough = p.roughness.mean();
            LectureFields {
                color: lecture_texture(&p.base_color),
                diffuse: 1.0 - trans,
                specular: dielectric_f0(p.eta.mean()),
                shininess: phong_exponent(rough * rough),
                transmission: trans,
                filter_color: (trans > 0.0).then(|| p.base_color.mean()),
                ..Default::default()
            }
        }
        BsdfDesc::Blend { weight, bsdfs } => mix(
            lecture_fields(&bsdfs[0]),
            lecture_fields(&bsdfs[1]),
            weight.mean().clamp(0.0, 1.0),
        ),
        BsdfDesc::Mask { opacity, bsdf } => {
            let inner = lecture_fields(bsdf);
            let o = opacity.mean().clamp(0.0, 1.0);
            LectureFields {
                diffuse: inner.diffuse * o,
                specular: inner.specular * o,
                reflection: inner.reflection * o,
                transmission: 1.0 - o * (1.0 - inner.transmission),
                filter_color: Some(inner.filter_color.unwrap_or(Rgb::WHITE)),
                ..inner
            }
        }
        BsdfDesc::TwoSided { front, .. } => lecture_fields(front),
        BsdfDesc::BumpMap { bsdf, .. } | BsdfDesc::NormalMap { bsdf, .. } => lecture_fields(bsdf),
    }
}
