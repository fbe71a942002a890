//! Mitsuba 3's `principledthin`: the thin-surface variant of the Disney principled BSDF
//! (Burley 2012, "Physically Based Shading at Disney"; Burley 2015, "Extending the
//! Disney BRDF to a BSDF with Integrated Subsurface Scattering", §5.2 on thin
//! surfaces), as Mitsuba's plugin defines it. A thin sheet (a leaf, paper, a curtain)
//! has no inside: light leaves on the side it arrived on or on the other, unbent, and
//! the sheet scatters the same seen from either side. Its lobes:
//!
//! - specular reflection, weighted by `spec_trans`: GGX (`roughness²`, stretched by
//!   `anisotropic`) with the exact dielectric Fresnel of `eta`, blended towards a
//!   Schlick Fresnel tinted by the base colour by `spec_tint`;
//! - specular transmission, weighted by `spec_trans`: the same microfacet reflection
//!   mirrored to the other side (no refraction through a thin sheet), with the
//!   roughness scaled by `0.65 eta - 0.35` (Burley 2015, Figure 15), `1 - F` of the
//!   dielectric and tinted by the base colour;
//! - diffuse reflection, weighted by `(1 - spec_trans)(1 - diff_trans / 2)`: Burley's
//!   diffuse with retro-reflection, blended by `flatness` towards the Hanrahan-Krueger
//!   "fake subsurface", plus `sheen` (tinted by `sheen_tint`);
//! - Lambertian diffuse transmission, weighted by `(1 - spec_trans) diff_trans / 2`
//!   (`diff_trans` runs from 0 to 2).
//!
//! Light from the back side is evaluated by turning both directions over (`-wo`,
//! `-wi`). Sampling picks a lobe with probabilities proportional to the four
//! `*_sampling_rate`s times the lobes' weights (`spec_trans / 2` for each specular
//! lobe); the diffuse lobes are sampled by the cosine, the specular ones by GGX's
//! visible normals; the pdf Mitsuba reports is the density its sampling has. A lobe
//! Mitsuba turns on because its parameter is given is on here when the parameter is
//! non-zero (the same for untextured values).
//!
//! As in Mitsuba, the glossy transmission is not reciprocal: the half vector comes from
//! `wi` mirrored up, but the microfacet's sidedness is tested with `wi` itself
//! (`wi·h < 0`), which cuts the lobe off from a steep `wo` towards a shallow `wi` and
//! not the other way round. This is kept.

use crate::bsdf::{BsdfSample, LobeFlags, Scatter};
use crate::bsdfs::principled::{
    burley_diffuse, calc_schlick, ggx_distribution, mac_mic_compatible, schlick_r0_eta,
    schlick_weight, tint_color,
};
use crate::microfacet::Microfacet;
use crate::optics::{fresnel_dielectric, reflect_about};
use glam::{Vec2, Vec3};
use irradia_core::sampling::cosine_hemisphere;
use irradia_core::Rgb;
use std::f32::consts::FRAC_1_PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrincipledThin {
    /// Mitsuba's `base_color` (default 0.5).
    pub base_color: Rgb,
    /// Mitsuba's `roughness` (default 0.5).
    pub roughness: f32,
    /// Mitsuba's `anisotropic`, `spec_trans`, `spec_tint`, `sheen`, `sheen_tint` and
    /// `flatness` (0 to 1, default 0).
    pub anisotropic: f32,
    pub spec_trans: f32,
    pub spec_tint: f32,
    pub sheen: f32,
    pub sheen_tint: f32,
    pub flatness: f32,
    /// Mitsuba's `diff_trans`, 0 (diffuse reflection only) to 2 (diffuse transmission
    /// only), default 0.
    pub diff_trans: f32,
    /// Mitsuba's `eta`, the sheet's index over its surroundings' (default 1.5).
    pub eta: f32,
    /// Mitsuba's `specular_reflectance_sampling_rate`,
    /// `specular_transmittance_sampling_rate`, `diffuse_reflectance_sampling_rate` and
    /// `diffuse_transmittance_sampling_rate` (default 1).
    pub specular_reflectance_sampling_rate: f32,
    pub specular_transmittance_sampling_rate: f32,
    pub diffuse_reflectance_sampling_rate: f32,
    pub diffuse_transmittance_sampling_rate: f32,
}

impl Default for PrincipledThin {
    fn default() -> Self {
        Self {
            base_color: Rgb::splat(0.5),
            roughness: 0.5,
            anisotropic: 0.0,
            spec_trans: 0.0,
            spec_tint: 0.0,
            sheen: 0.0,
            sheen_tint: 0.0,
            flatness: 0.0,
            diff_trans: 0.0,
            eta: 1.5,
            specular_reflectance_sampling_rate: 1.0,
            specular_transmittance_sampling_rate: 1.0,
            diffuse_reflectance_sampling_rate: 1.0,
            diffuse_transmittance_sampling_rate: 1.0,
        }
    }
}

/// The two directions turned over together when light arrives from the back (`wo.z <
/// 0`), so that `wo` is always on the front: the sheet is symmetric. Returns the sign
/// applied.
fn to_front(wo: Vec3, wi: Vec3) -> (Vec3, Vec3, f32) {
    if wo.z < 0.0 {
        (-wo, -wi, -1.0)
    } else {
        (wo, wi, 1.0)
    }
}

/// `w` mirrored to the upper hemisphere (`|z|`): a transmitted direction as the
/// reflected one it mirrors.
fn upper(w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, w.z.abs())
}

impl PrincipledThin {
    /// `diff_trans` on 0 to 1: the diffuse part's transmitted fraction.
    fn diff_trans_fraction(&self) -> f32 {
        self.diff_trans / 2.0
    }

    /// The specular reflection's GGX distribution.
    fn reflect_distribution(&self) -> Microfacet {
        ggx_distribution(self.roughness, self.anisotropic)
    }

    /// The specular transmission's GGX distribution: the roughness scaled by
    /// `0.65 eta - 0.35` (Burley 2015, Figure 15).
    fn transmit_distribution(&self) -> Microfacet {
        ggx_distribution((0.65 * self.eta - 0.35) * self.roughness, self.anisotropic)
    }

    /// The lobe selection probabilities (specular reflection, specular transmission,
    /// diffuse reflection, diffuse transmission), normalised.
    fn lobe_probabilities(&self) -> [f32; 4] {
        let (st, dt) = (self.spec_trans, self.diff_trans_fraction());
        let p = [
            st * self.specular_reflectance_sampling_rate / 2.0,
            st * self.specular_transmittance_sampling_rate / 2.0,
            self.diffuse_reflectance_sampling_rate * (1.0 - st) * (1.0 - dt),
            if dt != 0.0 {
                self.diffuse_transmittance_sampling_rate * (1.0 - st) * dt
            } else {
                0.0
            },
        ];
        let total: f32 = p.iter().sum();
        if total > 0.0 {
            p.map(|x| x / total)
        } else {
            [0.0; 4]
        }
    }

    /// The specular reflection's Fresnel term at `cos` (between `wo` and the half
    /// vector): the dielectric's `f_dielectric` blended by `spec_tint` towards Schlick's
    /// approximation with the tinted R0 (Mitsuba's `thin_fresnel`).
    fn thin_fresnel(&self, f_dielectric: f32, cos: f32) -> Rgb {
        if self.spec_tint == 0.0 {
            return Rgb::splat(f_dielectric);
        }
        let f0 = tint_color(self.base_color) * schlick_r0_eta(self.eta);
        let schlick = calc_schlick(f0, cos, self.eta);
        Rgb::splat(f_dielectric * (1.0 - self.spec_tint)) + schlick * self.spec_tint
    }
}

impl Scatter for PrincipledThin {
    fn flags(&self) -> LobeFlags {
        let mut f = LobeFlags::DIFFUSE_REFLECTION | LobeFlags::FRONT_SIDE | LobeFlags::BACK_SIDE;
        if self.diff_trans != 0.0 {
            f = f | LobeFlags::DIFFUSE_TRANSMISSION;
        }
        if self.spec_trans != 0.0 {
            f = f | LobeFlags::GLOSSY_REFLECTION | LobeFlags::GLOSSY_TRANSMISSION;
        }
        if self.anisotropic != 0.0 {
            f = f | LobeFlags::ANISOTROPIC;
        }
        f
    }

    fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if wo.z == 0.0 || wi.z == 0.0 {
            return Rgb::BLACK;
        }
        let (wo, wi, _) = to_front(wo, wi);
        let (st, dt) = (self.spec_trans, self.diff_trans_fraction());
        let reflect = wi.z > 0.0;
        let (cos_o, cos_i) = (wo.z, wi.z.abs());
        // The half vector of `wo` and `wi` mirrored up: transmission is a mirrored
        // microfacet reflection.
        let wh = (wo + upper(wi)).normalize();
        // Mitsuba's value carries |cos θi|; this sum is that value, divided at the end.
        let mut value = Rgb::BLACK;
        if st > 0.0 && mac_mic_compatible(wh, wo, wi, reflect) {
            let cos_h = wo.dot(wh);
            let fr = fresnel_dielectric(cos_h, self.eta).reflectance;
            if reflect {
                let d = self.reflect_distribution();
                let dg = d.d(wh) * d.g(wo, wi, wh);
                value += self.thin_fresnel(fr, cos_h) * (st * dg / (4.0 * cos_o));
            } else {
                let d = self.transmit_distribution();
                let dg = d.d(wh) * d.g(wo, wi, wh);
                value += self.base_color * (st * (1.0 - fr) * dg / (4.0 * cos_o));
            }
        }
        if reflect && st < 1.0 && dt < 1.0 {
            let cos_d = wh.dot(wi);
            let lobe = burley_diffuse(cos_o, cos_i, cos_d, self.roughness, self.flatness);
            let weight = (1.0 - st) * (1.0 - dt);
            value += self.base_color * (weight * cos_i * FRAC_1_PI * lobe);
            if self.sheen > 0.0 {
                let fd = schlick_weight(cos_d.abs());
                let tint =
                    Rgb::WHITE + (tint_color(self.base_color) - Rgb::WHITE) * self.sheen_tint;
                value += tint * (self.sheen * weight * fd * cos_i);
            }
        }
        if !reflect && st < 1.0 && dt > 0.0 {
            value += self.base_color * ((1.0 - st) * dt * FRAC_1_PI * cos_i);
        }
        value / cos_i
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z == 0.0 {
            return 0.0;
        }
        let (wo, wi, _) = to_front(wo, wi);
        let [p_sr, p_st, p_dr, p_dt] = self.lobe_probabilities();
        let (reflect, refract) = (wi.z > 0.0, wi.z < 0.0);
        let mut pdf = 0.0;
        if self.spec_trans != 0.0 && (reflect || refract) {
            let wi_up = upper(wi);
            let wh = (wo + wi_up).normalize();
            // d(wh)/d(wi) of a reflection, about the mirrored `wi` for transmission.
            let dwh_dwi = (1.0 / (4.0 * wi_up.dot(wh))).abs();
            if mac_mic_compatible(wh, wo, wi, reflect) {
                pdf += if reflect {
                    p_sr * self.reflect_distribution().pdf(wo, wh)
                } else {
                    p_st * self.transmit_distribution().pdf(wo, wh)
                } * dwh_dwi;
            }
        }
        if reflect {
            pdf += p_dr * wi.z * FRAC_1_PI;
        }
        if refract {
            pdf += p_dt * -wi.z * FRAC_1_PI;
        }
        pdf
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let (wo_f, _, sign) = to_front(wo, Vec3::ZERO);
        let [p_sr, p_st, p_dr, _] = self.lobe_probabilities();
        let (wi_f, lobe) = if u_lobe < p_sr {
            let (m, _) = self.reflect_distribution().sample(wo_f, u);
            let wi = reflect_about(wo_f, m);
            if wi.z <= 0.0 || !mac_mic_compatible(m, wo_f, wi, true) {
                return None;
            }
            (wi, LobeFlags::GLOSSY_REFLECTION)
        } else if u_lobe < p_sr + p_st {
            let (m, _) = self.transmit_distribution().sample(wo_f, u);
            let r = reflect_about(wo_f, m);
            // Through the sheet without bending: the reflection, mirrored below.
            let wi = Vec3::new(r.x, r.y, -r.z);
            if wi.z >= 0.0 || !mac_mic_compatible(m, wo_f, wi, false) {
                return None;
            }
            (wi, LobeFlags::GLOSSY_TRANSMISSION)
        } else if u_lobe < p_sr + p_st + p_dr {
            (cosine_hemisphere(u), LobeFlags::DIFFUSE_REFLECTION)
        } else if self.diff_trans != 0.0 {
            (-cosine_hemisphere(u), LobeFlags::DIFFUSE_TRANSMISSION)
        } else {
            return None;
        };
        let wi = (wi_f * sign).normalize();
        let pdf = self.pdf(wo, wi);
        if pdf <= 0.0 || !pdf.is_finite() {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: self.eval(wo, wi) * (wi.z.abs() / pdf),
            pdf,
            lobe,
            eta: 1.0,
        })
    }
}
