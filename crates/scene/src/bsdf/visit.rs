//! Every texture parameter of a BSDF description, nested ones included: what the scene
//! reader checks mesh attributes against ([`crate::file::attributes`]).

use super::{BsdfDesc, Roughness};
use crate::texture::{ColorTexture, FloatTexture};

/// A texture parameter: read as a colour (Mitsuba's `eval`) or as a number (`eval_1`).
#[derive(Clone, Copy, Debug)]
pub enum TextureParam<'a> {
    Color(&'a ColorTexture),
    Number(&'a FloatTexture),
}

impl BsdfDesc {
    /// Calls `f` with each texture parameter of the description and of the ones nested
    /// in it, named `"plugin.parameter"` (`"blendbsdf.weight"`).
    pub fn visit_textures(&self, f: &mut dyn FnMut(String, TextureParam<'_>)) {
        let ty = self.type_name();
        let color = |p: &str, c: &ColorTexture, f: &mut dyn FnMut(String, TextureParam<'_>)| {
            f(format!("{ty}.{p}"), TextureParam::Color(c))
        };
        let number = |p: &str, x: &FloatTexture, f: &mut dyn FnMut(String, TextureParam<'_>)| {
            f(format!("{ty}.{p}"), TextureParam::Number(x))
        };
        let rough = |r: &Roughness, f: &mut dyn FnMut(String, TextureParam<'_>)| match r {
            Roughness::Isotropic(a) => number("alpha", a, f),
            Roughness::Anisotropic { alpha_u, alpha_v } => {
                number("alpha_u", alpha_u, f);
                number("alpha_v", alpha_v, f);
            }
        };
        match self {
            BsdfDesc::Diffuse(d) => color("reflectance", &d.reflectance, f),
            BsdfDesc::Conductor(c) | BsdfDesc::RoughConductor(c, _) => {
                color("eta", &c.eta, f);
                color("k", &c.k, f);
                color("specular_reflectance", &c.specular_reflectance, f);
                if let BsdfDesc::RoughConductor(_, m) = self {
                    rough(&m.alpha, f);
                }
            }
            BsdfDesc::Dielectric(d)
            | BsdfDesc::RoughDielectric(d, _)
            | BsdfDesc::ThinDielectric(d) => {
                color("specular_reflectance", &d.specular_reflectance, f);
                color("specular_transmittance", &d.specular_transmittance, f);
                if let BsdfDesc::RoughDielectric(_, m) = self {
                    rough(&m.alpha, f);
                }
            }
            BsdfDesc::Plastic(p) | BsdfDesc::RoughPlastic(p, _) => {
                color("diffuse_reflectance", &p.diffuse_reflectance, f);
                color("specular_reflectance", &p.specular_reflectance, f);
            }
            BsdfDesc::Principled(p) => {
                color("base_color", &p.base_color, f);
                for (n, x) in [
                    ("roughness", &p.roughness),
                    ("anisotropic", &p.anisotropic),
                    ("metallic", &p.metallic),
                    ("spec_trans", &p.spec_trans),
                    ("spec_tint", &p.spec_tint),
                    ("sheen", &p.sheen),
                    ("sheen_tint", &p.sheen_tint),
                    ("flatness", &p.flatness),
                    ("clearcoat", &p.clearcoat),
                    ("clearcoat_gloss", &p.clearcoat_gloss),
                ] {
                    number(n, x, f);
                }
            }
            BsdfDesc::PrincipledThin(p) => {
                color("base_color", &p.base_color, f);
                for (n, x) in [
                    ("roughness", &p.roughness),
                    ("anisotropic", &p.anisotropic),
                    ("spec_trans", &p.spec_trans),
                    ("eta", &p.eta),
                    ("spec_tint", &p.spec_tint),
                    ("sheen", &p.sheen),
                    ("sheen_tint", &p.sheen_tint),
                    ("flatness", &p.flatness),
                    ("diff_trans", &p.diff_trans),
                ] {
                    number(n, x, f);
                }
            }
            BsdfDesc::Blend { weight, bsdfs } => {
                number("weight", weight, f);
                bsdfs[0].visit_textures(f);
                bsdfs[1].visit_textures(f);
            }
            BsdfDesc::Mask { opacity, bsdf } => {
                number("opacity", opacity, f);
                bsdf.visit_textures(f);
            }
            BsdfDesc::TwoSided { front, back } => {
                front.visit_textures(f);
                if let Some(b) = back {
                    b.visit_textures(f);
                }
            }
            BsdfDesc::BumpMap { texture, bsdf, .. } => {
                number("texture", texture, f);
                bsdf.visit_textures(f);
            }
            BsdfDesc::NormalMap { normalmap, bsdf } => {
                color("normalmap", normalmap, f);
                bsdf.visit_textures(f);
            }
        }
    }
}
