//! How a scene material becomes the `irradia_scatter` BSDF the path tracer shades with.
//!
//! A material with a physically based description (`material.bsdf`, Mitsuba 3's BSDF
//! plugins) becomes that BSDF: its textures are evaluated at the hit's surface
//! coordinates and the nested descriptions (blend, mask, twosided) become nested BSDFs
//! ([`desc_bsdf`]). Mitsuba's BSDFs are one-sided: the integrators' shading frame keeps
//! +z on the side the geometric normal points to (out of solids), never towards the
//! viewer, so a `diffuse` seen from inside is black, as in Mitsuba.
//!
//! A material without one is the lecture's mixture ([`bsdf_for`]), written for the
//! Whitted tracer, so that every scene renders in the path tracer without edits:
//!
//! | material field | path-tracer lobe |
//! |---|---|
//! | `diffuse * color` | Lambertian, albedo `diffuse * color` |
//! | `specular`, `shininess` | normalised Phong gloss, `ks = specular`, exponent `shininess` |
//! | `reflection` | perfect mirror (only when the surface does not transmit with Fresnel) |
//! | `transmission`, `ior`, `filter_color` | smooth dielectric (always Fresnel-weighted), tinted by the filter colour |
//! | `emission` | emitted radiance, one-sided (the side the surface normal points to) |
//! | `ambient` | ignored: the path tracer computes indirect light instead |
//!
//! If the weights add up to more than one (`max(diffuse*color) + specular +
//! max(reflection) + transmission > 1`), all are scaled down by the sum so that the
//! surface never reflects more energy than it receives.

use glam::{Vec2, Vec3};
use irradia_core::Rgb;
use irradia_scatter::bsdfs::{self, LectureLobe as Lobe, LectureMix, RoughPlasticTables};
use irradia_scatter::microfacet::{Microfacet, MicrofacetType};
use irradia_scatter::Bsdf;
use irradia_scene::bsdf::{self as desc, BsdfDesc, Distribution, Roughness};
use irradia_scene::texture::{ColorTexture, FloatTexture, TextureQuery};
use irradia_scene::{Material, Texture};
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

/// The surface's differential geometry in the local shading frame (+z the shading
/// normal, +x along `dp/du`): what normal and bump maps perturb.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tangents {
    /// `dp/du`, `dp/dv` in the local frame (zero where the shape has no uv
    /// parameterisation: then the frame's own axes stand in, as Mitsuba's
    /// `coordinate_system(n)`).
    pub dpdu: Vec3,
    pub dpdv: Vec3,
    /// The geometric normal in the local frame.
    pub ng: Vec3,
}

impl Default for Tangents {
    fn default() -> Self {
        Self {
            dpdu: Vec3::ZERO,
            dpdv: Vec3::ZERO,
            ng: Vec3::Z,
        }
    }
}

/// The BSDF of `material` at world point `p` with surface coordinates `uv` and local
/// differential geometry `tangents`: its physically based description when it has
/// one, else the lecture mixture.
pub fn material_bsdf(material: &Material, p: Vec3, uv: Vec2, tangents: &Tangents) -> Bsdf {
    material_bsdf_query(material, p, &TextureQuery::at_uv(uv), tangents)
}

/// [`material_bsdf`] with everything a texture lookup may read (a mesh's vertex colour
/// as well as the uv).
pub fn material_bsdf_query(
    material: &Material,
    p: Vec3,
    q: &TextureQuery,
    tangents: &Tangents,
) -> Bsdf {
    match &material.bsdf {
        Some(d) => desc_bsdf(d, q, tangents),
        None => bsdf_for(material, p, q.uv).into(),
    }
}

/// Whether `material`'s BSDF is the same at every surface point (so it is built once
/// per render): a lecture material with a solid colour, or a description without
/// textures.
pub fn is_uniform(material: &Material) -> bool {
    match &material.bsdf {
        Some(d) => desc_uniform(d),
        None => matches!(material.color, Texture::Solid(_)),
    }
}

fn color_uniform(c: &ColorTexture) -> bool {
    matches!(c, ColorTexture::Value(_))
}

fn float_uniform(f: &FloatTexture) -> bool {
    matches!(f, FloatTexture::Value(_))
}

fn roughness_uniform(r: &Roughness) -> bool {
    match r {
        Roughness::Isotropic(a) => float_uniform(a),
        Roughness::Anisotropic { alpha_u, alpha_v } => {
            float_uniform(alpha_u) && float_uniform(alpha_v)
        }
    }
}

/// Whether description `d` is the same at every surface point (no textures, no
/// perturbed normals).
pub fn desc_uniform(d: &BsdfDesc) -> bool {
    let conductor = |c: &desc::Conductor| {
        color_uniform(&c.eta) && color_uniform(&c.k) && color_uniform(&c.specular_reflectance)
    };
    let dielectric = |d: &desc::Dielectric| {
        color_uniform(&d.specular_reflectance) && color_uniform(&d.specular_transmittance)
    };
    let plastic = |p: &desc::Plastic| {
        color_uniform(&p.diffuse_reflectance) && color_uniform(&p.specular_reflectance)
    };
    match d {
        BsdfDesc::Diffuse(d) => color_uniform(&d.reflectance),
        BsdfDesc::Conductor(c) => conductor(c),
        BsdfDesc::RoughConductor(c, m) => conductor(c) && roughness_uniform(&m.alpha),
        BsdfDesc::Dielectric(d) | BsdfDesc::ThinDielectric(d) => dielectric(d),
        BsdfDesc::RoughDielectric(d, m) => dielectric(d) && roughness_uniform(&m.alpha),
        BsdfDesc::Plastic(p) | BsdfDesc::RoughPlastic(p, _) => plastic(p),
        BsdfDesc::Principled(p) => {
            color_uniform(&p.base_color)
                && [
                    &p.roughness,
                    &p.anisotropic,
                    &p.metallic,
                    &p.spec_trans,
                    &p.spec_tint,
                    &p.sheen,
                    &p.sheen_tint,
                    &p.flatness,
                    &p.clearcoat,
                    &p.clearcoat_gloss,
                ]
                .into_iter()
                .all(float_uniform)
        }
        BsdfDesc::PrincipledThin(p) => {
            color_uniform(&p.base_color)
                && [
                    &p.roughness,
                    &p.anisotropic,
                    &p.spec_trans,
                    &p.eta,
                    &p.spec_tint,
                    &p.sheen,
                    &p.sheen_tint,
                    &p.flatness,
                    &p.diff_trans,
                ]
                .into_iter()
                .all(float_uniform)
        }
        BsdfDesc::Blend { weight, bsdfs } => {
            float_uniform(weight) && desc_uniform(&bsdfs[0]) && desc_uniform(&bsdfs[1])
        }
        BsdfDesc::Mask { opacity, bsdf } => float_uniform(opacity) && desc_uniform(bsdf),
        BsdfDesc::TwoSided { front, back } => {
            desc_uniform(front) && back.as_deref().is_none_or(desc_uniform)
        }
        // The perturbed normal varies over the surface.
        BsdfDesc::BumpMap { .. } | BsdfDesc::NormalMap { .. } => false,
    }
}

/// Whether description `d` depends on the surface's tangent direction (anisotropic
/// roughness, which Mitsuba aligns with `dp/du`).
pub fn desc_anisotropic(d: &BsdfDesc) -> bool {
    let rough = |m: &desc::Microfacet| matches!(m.alpha, Roughness::Anisotropic { .. });
    match d {
        BsdfDesc::RoughConductor(_, m) | BsdfDesc::RoughDielectric(_, m) => rough(m),
        BsdfDesc::Principled(p) => !matches!(p.anisotropic, FloatTexture::Value(a) if a == 0.0),
        BsdfDesc::PrincipledThin(p) => !matches!(p.anisotropic, FloatTexture::Value(a) if a == 0.0),
        BsdfDesc::Blend { bsdfs, .. } => desc_anisotropic(&bsdfs[0]) || desc_anisotropic(&bsdfs[1]),
        BsdfDesc::Mask { bsdf, .. } => desc_anisotropic(bsdf),
        BsdfDesc::TwoSided { front, back } => {
            desc_anisotropic(front) || back.as_deref().is_some_and(desc_anisotropic)
        }
        BsdfDesc::BumpMap { .. } | BsdfDesc::NormalMap { .. } => true,
        _ => false,
    }
}

/// Mitsuba's microfacet parameters at a surface point.
fn microfacet(m: &desc::Microfacet, q: &TextureQuery) -> Microfacet {
    let kind = match m.distribution {
        Distribution::Beckmann => MicrofacetType::Beckmann,
        Distribution::Ggx => MicrofacetType::Ggx,
    };
    let (au, av) = match &m.alpha {
        Roughness::Isotropic(a) => {
            let a = a.eval(q);
            (a, a)
        }
        Roughness::Anisotropic { alpha_u, alpha_v } => (alpha_u.eval(q), alpha_v.eval(q)),
    };
    Microfacet::new(kind, au, av, m.sample_visible)
}

/// The scatter BSDF of description `d` with its textures evaluated at `q` and, for
/// normal and bump maps, the local differential geometry `t` (every description has
/// one).
pub fn desc_bsdf(d: &BsdfDesc, q: &TextureQuery, t: &Tangents) -> Bsdf {
    match d {
        BsdfDesc::Diffuse(d) => bsdfs::Diffuse {
            reflectance: d.reflectance.eval(q),
        }
        .into(),
        BsdfDesc::Conductor(c) => bsdfs::Conductor {
            eta: c.eta.eval(q),
            k: c.k.eval(q),
            specular_reflectance: c.specular_reflectance.eval(q),
        }
        .into(),
        BsdfDesc::RoughConductor(c, m) => bsdfs::RoughConductor {
            distribution: microfacet(m, q),
            eta: c.eta.eval(q),
            k: c.k.eval(q),
            specular_reflectance: c.specular_reflectance.eval(q),
        }
        .into(),
        BsdfDesc::Dielectric(d) => bsdfs::Dielectric {
            eta: d.eta(),
            specular_reflectance: d.specular_reflectance.eval(q),
            specular_transmittance: d.specular_transmittance.eval(q),
        }
        .into(),
        BsdfDesc::RoughDielectric(d, m) => bsdfs::RoughDielectric {
            distribution: microfacet(m, q),
            eta: d.eta(),
            specular_reflectance: d.specular_reflectance.eval(q),
            specular_transmittance: d.specular_transmittance.eval(q),
        }
        .into(),
        BsdfDesc::ThinDielectric(d) => bsdfs::ThinDielectric {
            eta: d.eta(),
            specular_reflectance: d.specular_reflectance.eval(q),
            specular_transmittance: d.specular_transmittance.eval(q),
        }
        .into(),
        BsdfDesc::Plastic(p) => bsdfs::Plastic {
            diffuse_reflectance: p.diffuse_reflectance.eval(q),
            specular_reflectance: p.specular_reflectance.eval(q),
            eta: p.int_ior / p.ext_ior,
            nonlinear: p.nonlinear,
        }
        .into(),
        BsdfDesc::RoughPlastic(p, r) => {
            let distribution = Microfacet::new(
                match r.distribution {
                    Distribution::Beckmann => MicrofacetType::Beckmann,
                    Distribution::Ggx => MicrofacetType::Ggx,
                },
                r.alpha,
                r.alpha,
                r.sample_visible,
            );
            let eta = p.int_ior / p.ext_ior;
            bsdfs::RoughPlastic {
                distribution,
                eta,
                diffuse_reflectance: p.diffuse_reflectance.eval(q),
                specular_reflectance: p.specular_reflectance.eval(q),
                nonlinear: p.nonlinear,
                tables: rough_plastic_tables(&distribution, eta),
            }
            .into()
        }
        BsdfDesc::Principled(p) => bsdfs::Principled {
            base_color: p.base_color.eval(q),
            roughness: p.roughness.eval(q),
            metallic: p.metallic.eval(q),
            spec_tint: p.spec_tint.eval(q),
            anisotropic: p.anisotropic.eval(q),
            sheen: p.sheen.eval(q),
            sheen_tint: p.sheen_tint.eval(q),
            clearcoat: p.clearcoat.eval(q),
            clearcoat_gloss: p.clearcoat_gloss.eval(q),
            spec_trans: p.spec_trans.eval(q),
            flatness: p.flatness.eval(q),
            eta: p.specular.eta(),
            main_specular_sampling_rate: p.main_specular_sampling_rate,
            clearcoat_sampling_rate: p.clearcoat_sampling_rate,
            diffuse_reflectance_sampling_rate: p.diffuse_reflectance_sampling_rate,
        }
        .into(),
        // Two-sided by itself: a thin sheet scatters the same seen from either side.
        BsdfDesc::PrincipledThin(p) => bsdfs::PrincipledThin {
            base_color: p.base_color.eval(q),
            roughness: p.roughness.eval(q),
            anisotropic: p.anisotropic.eval(q),
            spec_trans: p.spec_trans.eval(q),
            spec_tint: p.spec_tint.eval(q),
            sheen: p.sheen.eval(q),
            sheen_tint: p.sheen_tint.eval(q),
            flatness: p.flatness.eval(q),
            diff_trans: p.diff_trans.eval(q),
            eta: p.eta.eval(q),
            specular_reflectance_sampling_rate: p.specular_reflectance_sampling_rate,
            specular_transmittance_sampling_rate: p.specular_transmittance_sampling_rate,
            diffuse_reflectance_sampling_rate: p.diffuse_reflectance_sampling_rate,
            diffuse_transmittance_sampling_rate: p.diffuse_transmittance_sampling_rate,
        }
        .into(),
        BsdfDesc::Blend { weight, bsdfs } => bsdfs::Blend {
            weight: weight.eval(q),
            bsdf_0: Box::new(desc_bsdf(&bsdfs[0], q, t)),
            bsdf_1: Box::new(desc_bsdf(&bsdfs[1], q, t)),
        }
        .into(),
        BsdfDesc::Mask { opacity, bsdf } => bsdfs::Mask {
            opacity: opacity.eval(q),
            nested_bsdf: Box::new(desc_bsdf(bsdf, q, t)),
        }
        .into(),
        BsdfDesc::TwoSided { front, back } => bsdfs::TwoSided {
            front: Box::new(desc_bsdf(front, q, t)),
            back: back.as_ref().map(|b| Box::new(desc_bsdf(b, q, t))),
        }
        .into(),
        // Mitsuba's `normalmap`: the texture's colour c is the normal 2c - 1 in the
        // shading frame (+x along dp/du).
        BsdfDesc::NormalMap { normalmap, bsdf } => {
            let c = normalmap.eval(q);
            let n = Vec3::new(c.r, c.g, c.b) * 2.0 - Vec3::ONE;
            bsdfs::NormalMap::new(n, desc_bsdf(bsdf, q, t)).into()
        }
        // Mitsuba's `bumpmap`: the height h = scale · texture moves the surface along
        // its normal; the perturbed tangents are dp/du + n (∂h/∂u − n·dp/du) (and the
        // same in v), the perturbed normal their cross product, turned to the side of
        // the geometric normal. Then as a normal map (its flip of normals facing away and
        // its shadowing term): what pip Mitsuba 3.9.1's `bumpmap` evaluates (measured
        // by bench/pathtrace/envmap_balls.py; without them it was 1-12% brighter).
        BsdfDesc::BumpMap {
            texture,
            scale,
            bsdf,
        } => {
            let (du, dv) = if t.dpdu == Vec3::ZERO || t.dpdv == Vec3::ZERO {
                (Vec3::X, Vec3::Y)
            } else {
                (t.dpdu, t.dpdv)
            };
            let g = height_gradient(texture, q) * *scale;
            let pu = du + Vec3::Z * (g.x - du.z);
            let pv = dv + Vec3::Z * (g.y - dv.z);
            let mut n = pu.cross(pv).normalize_or_zero();
            if n == Vec3::ZERO {
                n = Vec3::Z;
            }
            if n.dot(t.ng) < 0.0 {
                n = -n;
            }
            bsdfs::NormalMap::new(n, desc_bsdf(bsdf, q, t)).into()
        }
    }
}

/// The gradient `(∂h/∂u, ∂h/∂v)` of a height texture at `q`, by central differences
/// over a step far below a texel of any bitmap Irradia reads (the bilinear lookup is
/// linear inside a texel, so the difference is its slope there).
fn height_gradient(texture: &FloatTexture, q: &TextureQuery) -> Vec2 {
    const H: f32 = 2e-5;
    let at = |du: f32, dv: f32| {
        let mut q = *q;
        q.uv += Vec2::new(du, dv);
        texture.eval(&q)
    };
    Vec2::new(
        (at(H, 0.0) - at(-H, 0.0)) / (2.0 * H),
        (at(0.0, H) - at(0.0, -H)) / (2.0 * H),
    )
}

/// The internal-scattering tables of a rough plastic coating, computed once per
/// (distribution, roughness, η) and shared: a textured rough plastic builds its BSDF
/// at every hit, and the tables depend only on the coating (Mitsuba's `roughplastic`
/// precomputes them at load time for the same reason).
fn rough_plastic_tables(distribution: &Microfacet, eta: f32) -> Arc<RoughPlasticTables> {
    type Key = (MicrofacetType, u32, u32, bool, u32);
    static CACHE: OnceLock<Mutex<HashMap<Key, Arc<RoughPlasticTables>>>> = OnceLock::new();
    let key = (
        distribution.kind,
        distribution.alpha_u.to_bits(),
        distribution.alpha_v.to_bits(),
        distribution.sample_visible,
        eta.to_bits(),
    );
    let cache = CACHE.get_or_init(|| Mutex::new(HashMap::new()));
    let mut map = cache.lock().unwrap_or_else(|e| e.into_inner());
    map.entry(key)
        .or_insert_with(|| Arc::new(RoughPlasticTables::new(distribution, eta)))
        .clone()
}

/// The BSDF of `material` at world point `p` with surface coordinates `uv`.
pub fn bsdf_for(material: &Material, p: Vec3, uv: Vec2) -> LectureMix {
    let color = material.color.eval(p, uv);
    let albedo = color * material.diffuse;
    let transmits = material.transmission > 0.0;
    let mirror = if transmits && material.fresnel {
        Rgb::BLACK
    } else {
        material.reflection
    };
    let total =
        albedo.max_component() + material.specular + mirror.max_component() + material.transmission;
    let scale = if total > 1.0 { 1.0 / total } else { 1.0 };
    let mut bsdf = LectureMix::new()
        .with(Lobe::Lambert {
            albedo: albedo * scale,
        })
        .with(Lobe::Phong {
            ks: Rgb::splat(material.specular * scale),
            exponent: material.shininess.max(0.0),
        })
        .with(Lobe::Mirror { r: mirror * scale });
    if transmits {
        let tint = material.filter_color.unwrap_or(color);
        bsdf = bsdf.with(Lobe::Dielectric {
            eta: material.ior,
            tint,
            weight: material.transmission * scale,
        });
    }
    bsdf
}

#[cfg(test)]
mod tests {
    use super::*;
    use irradia_scene::Texture;

    #[test]
    fn over_bright_materials_are_scaled_to_conserve_energy() {
        let m = Material {
            color: Texture::Solid(Rgb::WHITE),
            diffuse: 0.9,
            specular: 0.5,
            reflection: Rgb::splat(0.4),
            ..Material::default()
        };
        let b = bsdf_for(&m, Vec3::ZERO, Vec2::ZERO);
        let wo = Vec3::new(0.3, 0.1, 0.9).normalize();
        let albedo: f32 = b.lobes().map(|l| l.albedo(wo, 4096).max_component()).sum();
        assert!(albedo <= 1.0 + 1e-3, "albedo {albedo}");
    }
}
