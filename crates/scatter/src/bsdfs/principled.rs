//! Mitsuba 3's `principled`: the Disney principled BSDF (Burley 2012, "Physically Based
//! Shading at Disney"; Burley 2015, "Extending the Disney BRDF to a BSDF with Integrated
//! Subsurface Scattering"), as Mitsuba's plugin defines it:
//!
//! - a diffuse lobe with Burley's retro-reflection (and, with `flatness`, the
//!   Hanrahan-Krueger "fake subsurface" blend), weighted by `(1 - metallic)(1 -
//!   spec_trans)`, plus `sheen` (Schlick weight of the half angle, tinted towards the
//!   base colour by `sheen_tint`);
//! - the main specular reflection: GGX (`roughness²`, stretched by `anisotropic`) with
//!   a Fresnel term blending the exact dielectric Fresnel, Schlick with the base colour
//!   for `metallic` and a tinted Schlick for `spec_tint`;
//! - rough transmission by `spec_trans` through the dielectric of index `eta`, tinted by
//!   `√base_color` (Walter et al. 2007);
//! - a clearcoat: Burley's GTR1 normals (roughness `lerp(0.1, 0.001, clearcoat_gloss)`),
//!   Schlick Fresnel with R0 = 0.04 and GGX masking with α = 0.25, weighted by
//!   `clearcoat / 4`, without the `1 / (4 cos θo cos θi)` factor, as Mitsuba writes it.
//!
//! Light arriving from inside (`wo.z < 0`) sees only the dielectric's reflection and
//! transmission. A lobe Mitsuba turns on because its parameter is given is on here
//! when the parameter is non-zero (the same for untextured values). Mitsuba's
//! sampling picks a lobe with probabilities that depend on the Fresnel term of the
//! sampled normal when `spec_trans > 0` and reports the pdf with the Fresnel term of the
//! half vector; this is kept as it is.

use crate::bsdf::{BsdfSample, LobeFlags, Scatter};
use crate::microfacet::{Microfacet, MicrofacetType};
use crate::optics::{fresnel_dielectric, reflect_about, refract_about};
use glam::{Vec2, Vec3};
use irradia_core::sampling::cosine_hemisphere;
use irradia_core::Rgb;
use std::f32::consts::{FRAC_1_PI, PI};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Principled {
    /// Mitsuba's `base_color` (default 0.5).
    pub base_color: Rgb,
    /// Mitsuba's `roughness` (default 0.5).
    pub roughness: f32,
    /// Mitsuba's `metallic`, `specular` (as `eta`, see [`Principled::eta_from_specular`]),
    /// `spec_tint`, `anisotropic`, `sheen`, `sheen_tint`, `clearcoat`,
    /// `clearcoat_gloss`, `spec_trans` and `flatness` (all default 0).
    pub metallic: f32,
    pub spec_tint: f32,
    pub anisotropic: f32,
    pub sheen: f32,
    pub sheen_tint: f32,
    pub clearcoat: f32,
    pub clearcoat_gloss: f32,
    pub spec_trans: f32,
    pub flatness: f32,
    /// Mitsuba's `eta`, interior over exterior (default 1.5, from `specular` 0.5).
    pub eta: f32,
    /// Mitsuba's `main_specular_sampling_rate`, `clearcoat_sampling_rate` and
    /// `diffuse_reflectance_sampling_rate` (default 1).
    pub main_specular_sampling_rate: f32,
    pub clearcoat_sampling_rate: f32,
    pub diffuse_reflectance_sampling_rate: f32,
}

impl Default for Principled {
    fn default() -> Self {
        Self {
            base_color: Rgb::splat(0.5),
            roughness: 0.5,
            metallic: 0.0,
            spec_tint: 0.0,
            anisotropic: 0.0,
            sheen: 0.0,
            sheen_tint: 0.0,
            clearcoat: 0.0,
            clearcoat_gloss: 0.0,
            spec_trans: 0.0,
            flatness: 0.0,
            eta: Self::eta_from_specular(0.5),
            main_specular_sampling_rate: 1.0,
            clearcoat_sampling_rate: 1.0,
            diffuse_reflectance_sampling_rate: 1.0,
        }
    }
}

/// Burley's diffuse lobe without the albedo and 1/π: the Fresnel-shaped diffuse term
/// times retro-reflection, blended with Hanrahan-Krueger's fake subsurface (flattened
/// by Fss90 = Rr / 2) by `flatness` (Burley 2015; Mitsuba's `principled` and
/// `principledthin`). `cos_d` is the cosine between the half vector and `wi`.
pub(crate) fn burley_diffuse(
    cos_o: f32,
    cos_i: f32,
    cos_d: f32,
    roughness: f32,
    flatness: f32,
) -> f32 {
    let (fo, fi) = (schlick_weight(cos_o), schlick_weight(cos_i));
    let f_diff = (1.0 - 0.5 * fi) * (1.0 - 0.5 * fo);
    let rr = 2.0 * roughness * cos_d * cos_d;
    let f_retro = rr * (fo + fi + fo * fi * (rr - 1.0));
    if flatness != 0.0 {
        let fss90 = rr / 2.0;
        let fss = (1.0 + (fss90 - 1.0) * fo) * (1.0 + (fss90 - 1.0) * fi);
        let f_ss = 1.25 * (fss * (1.0 / (cos_o + cos_i) - 0.5) + 0.5);
        f_diff + f_retro + (f_ss - f_diff - f_retro) * flatness
    } else {
        f_diff + f_retro
    }
}

/// Schlick's weight `(1 - cos)⁵`, the argument clamped to [0, 1].
pub(crate) fn schlick_weight(cos: f32) -> f32 {
    let m = (1.0 - cos).clamp(0.0, 1.0);
    m * m * m * m * m
}

/// Schlick's Fresnel approximation `R0 + (1 - R0)(1 - cos)⁵` with the cosine taken on
/// the denser side (the refracted one when light comes from the denser medium), as
/// Mitsuba's `calc_schlick`.
pub(crate) fn calc_schlick(r0: Rgb, cos_theta_i: f32, eta: f32) -> Rgb {
    let outside = cos_theta_i >= 0.0;
    let (eta_it, eta_ti) = if outside {
        (eta, 1.0 / eta)
    } else {
        (1.0 / eta, eta)
    };
    let cos_t2 = 1.0 - (1.0 - cos_theta_i * cos_theta_i) * eta_ti * eta_ti;
    let w = if eta_it > 1.0 {
        schlick_weight(cos_theta_i.abs())
    } else {
        schlick_weight(cos_t2.max(0.0).sqrt())
    };
    r0 + (Rgb::WHITE - r0) * w
}

/// The normal-incidence reflectance `((η - 1) / (η + 1))²`.
pub(crate) fn schlick_r0_eta(eta: f32) -> f32 {
    ((eta - 1.0) / (eta + 1.0)).powi(2)
}

/// Luminance of a linear sRGB colour (Mitsuba's `luminance` in RGB mode).
pub(crate) fn luminance(c: Rgb) -> f32 {
    0.212671 * c.r + 0.715160 * c.g + 0.072169 * c.b
}

/// `c / luminance(c)`, white for black (the tint colour of `spec_tint`, `sheen_tint`).
pub(crate) fn tint_color(c: Rgb) -> Rgb {
    let lum = luminance(c);
    if lum > 0.0 {
        c / lum
    } else {
        Rgb::WHITE
    }
}

/// Whether `wo` and `wi` both see the front of microfacet `m` on the side `cos θo`
/// chose (reflection), or `wi` its back (refraction): Mitsuba's `mac_mic_compatibility`.
pub(crate) fn mac_mic_compatible(m: Vec3, wo: Vec3, wi: Vec3, reflection: bool) -> bool {
    let m = if wo.z < 0.0 { -m } else { m };
    let wi_m = if reflection { wi.dot(m) } else { -wi.dot(m) };
    wo.dot(m) > 0.0 && wi_m > 0.0
}

/// The visible-normal GGX distribution of Burley's `roughness` (α = roughness²),
/// stretched along x and squeezed along y by `anisotropic` with the aspect
/// `√(1 - 0.9 anisotropic)`, both α at least 0.001: Mitsuba's `calc_dist_params`.
pub(crate) fn ggx_distribution(roughness: f32, anisotropic: f32) -> Microfacet {
    let r2 = roughness * roughness;
    let aspect = (1.0 - 0.9 * anisotropic).sqrt();
    Microfacet::new(
        MicrofacetType::Ggx,
        (r2 / aspect).max(0.001),
        (r2 * aspect).max(0.001),
        true,
    )
}

/// Burley's GTR1 distribution ("generalised Trowbridge-Reitz", γ = 1) of the clearcoat.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Gtr1 {
    pub alpha: f32,
}

impl Gtr1 {
    pub fn d(&self, m: Vec3) -> f32 {
        let a2 = self.alpha * self.alpha;
        let r = (a2 - 1.0) / (PI * a2.ln() * (1.0 + (a2 - 1.0) * m.z * m.z));
        if r * m.z > 1e-20 {
            r
        } else {
            0.0
        }
    }

    pub fn pdf(&self, m: Vec3) -> f32 {
        if m.z < 0.0 {
            0.0
        } else {
            m.z * self.d(m)
        }
    }

    pub fn sample(&self, u: Vec2) -> Vec3 {
        let (sin_phi, cos_phi) = (2.0 * PI * u.x).sin_cos();
        let a2 = self.alpha * self.alpha;
        let cos2 = (1.0 - a2.powf(1.0 - u.y)) / (1.0 - a2);
        let sin_t = (1.0 - cos2).max(0.0).sqrt();
        Vec3::new(cos_phi * sin_t, sin_phi * sin_t, cos2.max(0.0).sqrt())
    }
}

/// Smith's separable GGX masking of one direction with roughness `alpha` (Mitsuba's
/// `smith_ggx1`, used by the clearcoat).
pub(crate) fn smith_ggx1(v: Vec3, m: Vec3, alpha: f32) -> f32 {
    if v.dot(m) * v.z <= 0.0 {
        return 0.0;
    }
    if v.z == 1.0 {
        return 1.0;
    }
    let c2 = v.z * v.z;
    let tan2 = (1.0 - c2) / c2;
    2.0 / (1.0 + (1.0 + alpha * alpha * tan2).sqrt())
}

/// The lobes of one evaluation, for `eval` and `pdf`.
struct Geometry {
    /// The generalised half vector, pointing outwards.
    wh: Vec3,
    reflect: bool,
    refract: bool,
    front: bool,
    /// The index ratio along the light's path (`eta` from outside, `1 / eta` inside).
    eta_path: f32,
}

impl Principled {
    /// Mitsuba's `specular` (0 to 1, default 0.5) as the index of refraction:
    /// `2 / (1 - √(0.08 specular)) - 1`.
    pub fn eta_from_specular(specular: f32) -> f32 {
        2.0 / (1.0 - (0.08 * specular).sqrt()) - 1.0
    }

    /// The main specular GGX distribution.
    fn spec_distribution(&self) -> Microfacet {
        ggx_distribution(self.roughness, self.anisotropic)
    }

    fn clearcoat_distribution(&self) -> Gtr1 {
        Gtr1 {
            alpha: 0.1 + (0.001 - 0.1) * self.clearcoat_gloss,
        }
    }

    /// Weights of the reflecting (diffuse) and transmitting parts.
    fn weights(&self) -> (f32, f32) {
        let brdf = (1.0 - self.metallic) * (1.0 - self.spec_trans);
        let bsdf = (1.0 - self.metallic) * self.spec_trans;
        (brdf, bsdf)
    }

    fn geometry(&self, wo: Vec3, wi: Vec3) -> Geometry {
        let reflect = wo.z * wi.z > 0.0;
        let front = wo.z > 0.0;
        let eta_path = if front { self.eta } else { 1.0 / self.eta };
        let wh = (wo + wi * if reflect { 1.0 } else { eta_path }).normalize();
        Geometry {
            wh: if wh.z < 0.0 { -wh } else { wh },
            reflect,
            refract: wo.z * wi.z < 0.0,
            front,
            eta_path,
        }
    }

    /// The lobe selection probabilities (diffuse, clearcoat, transmission, main
    /// specular reflection) for Fresnel reflectance `f`, normalised.
    fn lobe_probabilities(&self, front: bool, f: f32) -> [f32; 4] {
        let (brdf, bsdf) = self.weights();
        let srate = self.main_specular_sampling_rate;
        let (spec, trans, cc, diff) = if front {
            (
                srate * (1.0 - bsdf * (1.0 - f)),
                if self.spec_trans != 0.0 {
                    srate * bsdf * (1.0 - f)
                } else {
                    0.0
                },
                0.25 * self.clearcoat * self.clearcoat_sampling_rate,
                brdf * self.diffuse_reflectance_sampling_rate,
            )
        } else {
            let trans = if self.spec_trans != 0.0 { 1.0 - f } else { 0.0 };
            (f, trans, 0.0, 0.0)
        };
        let inv = 1.0 / (spec + trans + cc + diff);
        [diff * inv, cc * inv, trans * inv, spec * inv]
    }
}

impl Scatter for Principled {
    fn flags(&self) -> LobeFlags {
        let aniso = if self.anisotropic != 0.0 {
            LobeFlags::ANISOTROPIC
        } else {
            LobeFlags::NONE
        };
        let mut f = LobeFlags::DIFFUSE_REFLECTION
            | LobeFlags::GLOSSY_REFLECTION
            | LobeFlags::FRONT_SIDE
            | LobeFlags::BACK_SIDE
            | aniso;
        if self.spec_trans != 0.0 {
            f = f | LobeFlags::GLOSSY_TRANSMISSION;
        }
        f
    }

    fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if wo.z == 0.0 || wi.z == 0.0 {
            return Rgb::BLACK;
        }
        let (brdf, bsdf) = self.weights();
        let g = self.geometry(wo, wi);
        let wh = g.wh;
        let distr = self.spec_distribution();
        let fr = fresnel_dielectric(wo.dot(wh), self.eta).reflectance;
        let refl_ok = mac_mic_compatible(wh, wo, wi, true);
        let refr_ok = mac_mic_compatible(wh, wo, wi, false);
        let d = distr.d(wh);
        let gg = distr.g(wo, wi, wh);
        let (cos_o, cos_i) = (wo.z.abs(), wi.z.abs());
        // Mitsuba's value carries |cos θi|; this sum is that value, divided at the end.
        let mut value = Rgb::BLACK;
        if g.reflect && refl_ok && fr > 0.0 {
            let f = if g.front {
                let mut schlick = Rgb::BLACK;
                let cos = wo.dot(wh);
                if self.metallic != 0.0 {
                    schlick += calc_schlick(self.base_color, cos, self.eta) * self.metallic;
                }
                if self.spec_tint != 0.0 {
                    let eta_it = if cos >= 0.0 { self.eta } else { 1.0 / self.eta };
                    let f0 = tint_color(self.base_color) * schlick_r0_eta(eta_it);
                    schlick +=
                        calc_schlick(f0, cos, self.eta) * ((1.0 - self.metallic) * self.spec_tint);
                }
                Rgb::splat((1.0 - self.metallic) * (1.0 - self.spec_tint) * fr) + schlick
            } else {
                Rgb::splat(bsdf * fr)
            };
            value += f * (d * gg / (4.0 * cos_o));
        }
        if self.spec_trans != 0.0 && bsdf > 0.0 && g.refract && refr_ok && fr < 1.0 {
            let ep = g.eta_path;
            // The radiance compression (1/η_path)² of refraction.
            let scale = 1.0 / (ep * ep);
            let (wo_h, wi_h) = (wo.dot(wh), wi.dot(wh));
            let t = (scale * (1.0 - fr) * d * gg * ep * ep * wo_h * wi_h
                / (wo.z * (wo_h + ep * wi_h).powi(2)))
            .abs();
            let sqrt_base = Rgb::new(
                self.base_color.r.sqrt(),
                self.base_color.g.sqrt(),
                self.base_color.b.sqrt(),
            );
            value += sqrt_base * (bsdf * t);
        }
        if self.clearcoat > 0.0 && g.reflect && refl_ok && g.front {
            let fcc = calc_schlick(Rgb::splat(0.04), wo.dot(wh), self.eta).r;
            let dcc = self.clearcoat_distribution().d(wh);
            let gcc = smith_ggx1(wo, wh, 0.25) * smith_ggx1(wi, wh, 0.25);
            value += Rgb::splat(self.clearcoat * 0.25 * fcc * dcc * gcc * cos_i);
        }
        if brdf > 0.0 && g.reflect && g.front {
            let cos_d = wh.dot(wi);
            let lobe = burley_diffuse(cos_o, cos_i, cos_d, self.roughness, self.flatness);
            value += self.base_color * (brdf * cos_i * FRAC_1_PI * lobe);
            if self.sheen > 0.0 && 1.0 - self.metallic > 0.0 {
                let fd = schlick_weight(cos_d.abs());
                let tint =
                    Rgb::WHITE + (tint_color(self.base_color) - Rgb::WHITE) * self.sheen_tint;
                value += tint * (self.sheen * (1.0 - self.metallic) * fd * cos_i);
            }
        }
        value / cos_i
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z == 0.0 {
            return 0.0;
        }
        let g = self.geometry(wo, wi);
        let wh = g.wh;
        let distr = self.spec_distribution();
        let fr = fresnel_dielectric(wo.dot(wh), self.eta).reflectance;
        let [p_diff, p_cc, p_trans, p_spec] = self.lobe_probabilities(g.front, fr);
        let wi_h = wi.dot(wh);
        let dwh_dwi = if g.reflect || self.spec_trans == 0.0 {
            (1.0 / (4.0 * wi_h)).abs()
        } else {
            let ep = g.eta_path;
            (ep * ep * wi_h / (wo.dot(wh) + ep * wi_h).powi(2)).abs()
        };
        let wo_up = if wo.z < 0.0 { -wo } else { wo };
        let mut pdf = 0.0;
        let refl_ok = g.reflect && mac_mic_compatible(wh, wo, wi, true);
        if refl_ok {
            pdf += p_spec * distr.pdf(wo_up, wh) * dwh_dwi;
        }
        if g.reflect {
            pdf += p_diff * wi.z * FRAC_1_PI;
        }
        if self.spec_trans != 0.0 && g.refract && mac_mic_compatible(wh, wo, wi, false) {
            pdf += p_trans * distr.pdf(wo_up, wh) * dwh_dwi;
        }
        if self.clearcoat != 0.0 && refl_ok {
            pdf += p_cc * self.clearcoat_distribution().pdf(wh) * dwh_dwi;
        }
        pdf
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let (_, bsdf) = self.weights();
        let front = wo.z > 0.0;
        if !front && !(self.spec_trans != 0.0 && bsdf > 0.0) {
            return None;
        }
        let wo_up = if front { wo } else { -wo };
        let (m_spec, _) = self.spec_distribution().sample(wo_up, u);
        let fres = fresnel_dielectric(wo.dot(m_spec), self.eta);
        let [p_diff, p_cc, p_trans, _] = self.lobe_probabilities(front, fres.reflectance);
        let (wi, lobe, eta) = if u_lobe < p_diff {
            let wi = cosine_hemisphere(u);
            if wo.z * wi.z <= 0.0 {
                return None;
            }
            (wi, LobeFlags::DIFFUSE_REFLECTION, 1.0)
        } else if u_lobe < p_diff + p_cc {
            let m = self.clearcoat_distribution().sample(u);
            let wi = reflect_about(wo, m);
            if wo.z * wi.z <= 0.0 || !mac_mic_compatible(m, wo, wi, true) {
                return None;
            }
            (wi, LobeFlags::GLOSSY_REFLECTION, 1.0)
        } else if u_lobe < p_diff + p_cc + p_trans {
            let wi = refract_about(wo, m_spec, fres.cos_theta_t, fres.eta_ti);
            if wo.z * wi.z >= 0.0 || !mac_mic_compatible(m_spec, wo, wi, false) {
                return None;
            }
            (wi, LobeFlags::GLOSSY_TRANSMISSION, fres.eta_it)
        } else {
            let wi = reflect_about(wo, m_spec);
            if wo.z * wi.z <= 0.0 || !mac_mic_compatible(m_spec, wo, wi, true) {
                return None;
            }
            (wi, LobeFlags::GLOSSY_REFLECTION, 1.0)
        };
        let wi = wi.normalize();
        let pdf = self.pdf(wo, wi);
        if pdf <= 0.0 || !pdf.is_finite() {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: self.eval(wo, wi) * (wi.z.abs() / pdf),
            pdf,
            lobe,
            eta,
        })
    }
}
