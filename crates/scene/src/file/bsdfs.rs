//! The physically based `[materials.NAME]` tables: a Mitsuba 3 BSDF `type` with
//! Mitsuba's parameter names (docs/scene-format.md, "Physically based materials").
//! Nested materials (blendbsdf, mask, twosided, bumpmap, normalmap) are inline tables
//! or the names of other physically based materials, in any order; cycles are errors.

use super::reader::{unknown_name_message, Result, Table, Val};
use super::textures::{color_or, float_or, read_color_texture, read_float_texture};
use crate::bsdf::{
    BsdfDesc, Conductor, Dielectric, Diffuse, Distribution, Microfacet, Plastic, PlasticRoughness,
    Principled, PrincipledSpecular, PrincipledThin, Roughness, BSDF_TYPES,
};
use crate::texture::{ColorTexture, TextureMap};
use irradia_core::Rgb;
use irradia_scatter::ior::{conductor_ior, conductor_names, dielectric_ior, dielectric_names};
use std::collections::HashMap;

/// Whether a material table is a physically based one (it has a `type`).
pub fn is_physically_based(v: &Val) -> bool {
    v.table().is_ok_and(|t| t.has("type"))
}

/// A material's `emission`: a colour, or a texture table (`bitmap`, `checkerboard`)
/// read at the surface's uv, whose mean then stands for the constant.
pub fn read_emission(v: Option<Val>) -> Result<(Rgb, Option<TextureMap>)> {
    match v {
        None => Ok((Rgb::BLACK, None)),
        Some(v) if v.is_table() => {
            let map = super::textures::read_texture_map(&v)?;
            Ok((map.mean(), Some(map)))
        }
        Some(v) => Ok((v.rgb()?, None)),
    }
}

/// What a physically based material entry holds besides its BSDF.
pub struct PbrEntry {
    pub bsdf: BsdfDesc,
    pub emission: Rgb,
    pub emission_texture: Option<TextureMap>,
    pub emission_two_sided: bool,
}

/// Reads the physically based entries of the `materials` table, each once, resolving
/// references between them.
pub struct BsdfResolver<'a, 'd> {
    entries: &'a [(&'d str, Val<'d>)],
    done: HashMap<String, BsdfDesc>,
    /// The entries being read, outermost first (to report a cycle).
    reading: Vec<String>,
}

impl<'a, 'd> BsdfResolver<'a, 'd> {
    pub fn new(entries: &'a [(&'d str, Val<'d>)]) -> Self {
        BsdfResolver {
            entries,
            done: HashMap::new(),
            reading: Vec::new(),
        }
    }

    /// The entry `name` (a physically based one), with its emission fields.
    pub fn entry(&mut self, name: &str, v: &Val<'d>) -> Result<PbrEntry> {
        self.reading.push(name.to_string());
        let t = v.table()?;
        let bsdf = self.read_bsdf(&t)?;
        let (emission, emission_texture) = read_emission(t.get("emission"))?;
        let emission_two_sided = t.bool_or("emission_two_sided", false)?;
        t.finish()?;
        self.reading.pop();
        self.done.insert(name.to_string(), bsdf.clone());
        Ok(PbrEntry {
            bsdf,
            emission,
            emission_texture,
            emission_two_sided,
        })
    }

    /// A nested material: an inline table with a `type`, or the name of another
    /// physically based material.
    fn nested(&mut self, v: &Val<'d>) -> Result<BsdfDesc> {
        if v.is_table() {
            let t = v.table()?;
            let b = self.read_bsdf(&t)?;
            t.finish()?;
            return Ok(b);
        }
        let name = v.str().map_err(|_| {
            v.err(format!(
                "expected a material name or an inline material table, found {}",
                v.node.value.type_name()
            ))
        })?;
        if let Some(b) = self.done.get(name) {
            return Ok(b.clone());
        }
        if self.reading.iter().any(|r| r == name) {
            return Err(v.err(format!(
                "the materials refer to each other in a cycle: {} -> {name}",
                self.reading.join(" -> ")
            )));
        }
        let Some((_, entry)) = self.entries.iter().find(|(n, _)| *n == name) else {
            let names: Vec<&str> = self.entries.iter().map(|(n, _)| *n).collect();
            return Err(v.err(unknown_name_message("material", name, &names)));
        };
        if !is_physically_based(entry) {
            return Err(v.err(format!(
                "material `{name}` is a lecture material (it has no `type`); a nested material must be physically based"
            )));
        }
        let entry = entry.clone();
        Ok(self.entry(name, &entry)?.bsdf)
    }

    fn read_bsdf(&mut self, t: &Table<'d>) -> Result<BsdfDesc> {
        let type_v = t.req("type")?;
        let kind = type_v.str()?;
        let Some(kind) = BSDF_TYPES.iter().find(|k| **k == kind) else {
            let mut msg = unknown_name_message("material type", kind, &BSDF_TYPES);
            if kind == "blend" {
                msg = format!(
                    "unknown material type `blend`: Mitsuba calls it `blendbsdf` (valid: {})",
                    BSDF_TYPES.join(", ")
                );
            }
            return Err(type_v.err(msg));
        };
        Ok(match *kind {
            "diffuse" => BsdfDesc::Diffuse(Diffuse {
                reflectance: color_or(t, "reflectance", Rgb::splat(0.5))?,
            }),
            "conductor" => BsdfDesc::Conductor(conductor(t)?),
            "roughconductor" => BsdfDesc::RoughConductor(conductor(t)?, microfacet(t)?),
            "dielectric" => BsdfDesc::Dielectric(dielectric(t)?),
            "roughdielectric" => BsdfDesc::RoughDielectric(dielectric(t)?, microfacet(t)?),
            "thindielectric" => BsdfDesc::ThinDielectric(dielectric(t)?),
            "plastic" => BsdfDesc::Plastic(plastic(t)?),
            "roughplastic" => BsdfDesc::RoughPlastic(
                plastic(t)?,
                PlasticRoughness {
                    distribution: distribution(t)?,
                    alpha: t.non_negative_or("alpha", 0.1)?,
                    sample_visible: t.bool_or("sample_visible", true)?,
                },
            ),
            "principled" => BsdfDesc::Principled(Box::new(principled(t)?)),
            "principledthin" => BsdfDesc::PrincipledThin(Box::new(principled_thin(t)?)),
            "blendbsdf" => {
                let weight = float_or(t, "weight", 0.5)?;
                let [a, b] = self.two_nested(t, "bsdfs")?;
                BsdfDesc::Blend {
                    weight,
                    bsdfs: Box::new([a, b]),
                }
            }
            "mask" => BsdfDesc::Mask {
                opacity: float_or(t, "opacity", 0.5)?,
                bsdf: Box::new(self.nested(&t.req("bsdf")?)?),
            },
            "twosided" => match (t.get("bsdf"), t.get("bsdfs")) {
                (Some(_), Some(both)) => {
                    return Err(both
                        .err("give either bsdf (both sides) or bsdfs = [front, back], not both"))
                }
                (Some(one), None) => BsdfDesc::TwoSided {
                    front: Box::new(self.nested(&one)?),
                    back: None,
                },
                (None, Some(_)) => {
                    let [front, back] = self.two_nested(t, "bsdfs")?;
                    BsdfDesc::TwoSided {
                        front: Box::new(front),
                        back: Some(Box::new(back)),
                    }
                }
                (None, None) => {
                    let missing = t.req("bsdf").err();
                    return Err(missing.unwrap_or_else(|| t.err("missing required field")));
                }
            },
            "bumpmap" => BsdfDesc::BumpMap {
                texture: read_float_texture(&t.req("texture")?)?,
                scale: t.f32_or("scale", 1.0)?,
                bsdf: Box::new(self.nested(&t.req("bsdf")?)?),
            },
            _ => BsdfDesc::NormalMap {
                normalmap: read_color_texture(&t.req("normalmap")?)?,
                bsdf: Box::new(self.nested(&t.req("bsdf")?)?),
            },
        })
    }

    fn two_nested(&mut self, t: &Table<'d>, key: &'static str) -> Result<[BsdfDesc; 2]> {
        let v = t.req(key)?;
        let items = v.array()?;
        let [a, b] = items.as_slice() else {
            return Err(v.err(format!(
                "expected exactly 2 materials, found {}",
                items.len()
            )));
        };
        Ok([self.nested(a)?, self.nested(b)?])
    }
}

fn distribution(t: &Table) -> Result<Distribution> {
    Ok(match t.get("distribution") {
        Some(d) => match d.choice(&["beckmann", "ggx"])? {
            "ggx" => Distribution::Ggx,
            _ => Distribution::Beckmann,
        },
        None => Distribution::Beckmann,
    })
}

/// `alpha`, or `alpha_u` with `alpha_v`; never both forms.
fn microfacet(t: &Table) -> Result<Microfacet> {
    let alpha = match (t.get("alpha"), t.get("alpha_u"), t.get("alpha_v")) {
        (Some(_), Some(u), _) | (Some(_), None, Some(u)) => {
            return Err(u.err("give either alpha or alpha_u and alpha_v, not both"))
        }
        (Some(a), None, None) => Roughness::Isotropic(read_float_texture(&a)?),
        (None, Some(u), Some(v)) => Roughness::Anisotropic {
            alpha_u: read_float_texture(&u)?,
            alpha_v: read_float_texture(&v)?,
        },
        (None, Some(one), None) | (None, None, Some(one)) => {
            return Err(one.err("an anisotropic roughness needs both alpha_u and alpha_v"))
        }
        (None, None, None) => Roughness::default(),
    };
    Ok(Microfacet {
        distribution: distribution(t)?,
        alpha,
        sample_visible: t.bool_or("sample_visible", true)?,
    })
}

/// `material = "Au"` (Mitsuba's conductor names; `"none"` is a perfect mirror), or
/// `eta` and `k`; never both.
fn conductor(t: &Table) -> Result<Conductor> {
    let specular_reflectance = color_or(t, "specular_reflectance", Rgb::WHITE)?;
    let (eta_v, k_v) = (t.get("eta"), t.get("k"));
    let (material, eta, k) = match t.get("material") {
        Some(m) => {
            if let Some(other) = eta_v.or(k_v) {
                return Err(other.err("give either material or eta and k, not both"));
            }
            let name = m.str()?;
            let (eta, k) = conductor_ior(name).ok_or_else(|| {
                m.err(unknown_name_message("conductor", name, &conductor_names()))
            })?;
            (Some(name.to_string()), eta.into(), k.into())
        }
        None => (
            None,
            eta_v.map_or(Ok(ColorTexture::Value(Rgb::BLACK)), |v| {
                read_color_texture(&v)
            })?,
            k_v.map_or(Ok(ColorTexture::Value(Rgb::WHITE)), |v| {
                read_color_texture(&v)
            })?,
        ),
    };
    Ok(Conductor {
        material,
        eta,
        k,
        specular_reflectance,
    })
}

/// Mitsuba's default IORs: "bk7", "air", "polypropylene".
const BK7: f32 = 1.5046;
const AIR: f32 = 1.000277;
const POLYPROPYLENE: f32 = 1.49;

/// An IOR: a positive number or one of Mitsuba's names ("bk7", "water", "air", ...).
fn ior(t: &Table, key: &'static str, default: f32) -> Result<f32> {
    let Some(v) = t.get(key) else {
        return Ok(default);
    };
    if v.is_str() {
        let name = v.str()?;
        return dielectric_ior(name)
            .ok_or_else(|| v.err(unknown_name_message("IOR name", name, &dielectric_names())));
    }
    v.positive()
}

fn dielectric(t: &Table) -> Result<Dielectric> {
    Ok(Dielectric {
        int_ior: ior(t, "int_ior", BK7)?,
        ext_ior: ior(t, "ext_ior", AIR)?,
        specular_reflectance: color_or(t, "specular_reflectance", Rgb::WHITE)?,
        specular_transmittance: color_or(t, "specular_transmittance", Rgb::WHITE)?,
    })
}

fn plastic(t: &Table) -> Result<Plastic> {
    Ok(Plastic {
        diffuse_reflectance: color_or(t, "diffuse_reflectance", Rgb::splat(0.5))?,
        specular_reflectance: color_or(t, "specular_reflectance", Rgb::WHITE)?,
        int_ior: ior(t, "int_ior", POLYPROPYLENE)?,
        ext_ior: ior(t, "ext_ior", AIR)?,
        nonlinear: t.bool_or("nonlinear", false)?,
    })
}

fn principled(t: &Table) -> Result<Principled> {
    let d = Principled::default();
    let specular = match (t.get("eta"), t.get("specular")) {
        (Some(_), Some(s)) => return Err(s.err("give either eta or specular, not both")),
        (Some(e), None) => PrincipledSpecular::Eta(e.positive()?),
        (None, Some(s)) => PrincipledSpecular::Specular(s.non_negative()?),
        (None, None) => d.specular,
    };
    Ok(Principled {
        base_color: color_or(t, "base_color", Rgb::splat(0.5))?,
        roughness: float_or(t, "roughness", 0.5)?,
        anisotropic: float_or(t, "anisotropic", 0.0)?,
        metallic: float_or(t, "metallic", 0.0)?,
        spec_trans: float_or(t, "spec_trans", 0.0)?,
        specular,
        spec_tint: float_or(t, "spec_tint", 0.0)?,
        sheen: float_or(t, "sheen", 0.0)?,
        sheen_tint: float_or(t, "sheen_tint", 0.0)?,
        flatness: float_or(t, "flatness", 0.0)?,
        clearcoat: float_or(t, "clearcoat", 0.0)?,
        clearcoat_gloss: float_or(t, "clearcoat_gloss", 0.0)?,
        main_specular_sampling_rate: t.non_negative_or("main_specular_sampling_rate", 1.0)?,
        clearcoat_sampling_rate: t.non_negative_or("clearcoat_sampling_rate", 1.0)?,
        diffuse_reflectance_sampling_rate: t
            .non_negative_or("diffuse_reflectance_sampling_rate", 1.0)?,
    })
}

fn principled_thin(t: &Table) -> Result<PrincipledThin> {
    Ok(PrincipledThin {
        base_color: color_or(t, "base_color", Rgb::splat(0.5))?,
        roughness: float_or(t, "roughness", 0.5)?,
        anisotropic: float_or(t, "anisotropic", 0.0)?,
        spec_trans: float_or(t, "spec_trans", 0.0)?,
        eta: float_or(t, "eta", 1.5)?,
        spec_tint: float_or(t, "spec_tint", 0.0)?,
        sheen: float_or(t, "sheen", 0.0)?,
        sheen_tint: float_or(t, "sheen_tint", 0.0)?,
        flatness: float_or(t, "flatness", 0.0)?,
        diff_trans: float_or(t, "diff_trans", 0.0)?,
        specular_reflectance_sampling_rate: t
            .non_negative_or("specular_reflectance_sampling_rate", 1.0)?,
        diffuse_reflectance_sampling_rate: t
            .non_negative_or("diffuse_reflectance_sampling_rate", 1.0)?,
        diffuse_transmittance_sampling_rate: t
            .non_negative_or("diffuse_transmittance_sampling_rate", 1.0)?,
        specular_transmittance_sampling_rate: t
            .non_negative_or("specular_transmittance_sampling_rate", 1.0)?,
    })
}
