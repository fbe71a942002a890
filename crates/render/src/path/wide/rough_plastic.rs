//! Mitsuba 3's `roughplastic` with the isotropic GGX distribution and visible-normal
//! sampling in every lane of the wide kernel's vector stage (see [`super`]): the
//! scatter crate's `RoughPlastic` (Weidlich and Wilkie 2007, "Arbitrarily layered
//! micro-facet surfaces", as Mitsuba's plugin: a GGX dielectric coating, Walter et al.
//! 2007 eq. 20, over a Lambertian base seen through it,
//! `ρ / (1 − R_int) · T(θo) T(θi) / (η² π)`) with its arithmetic in the same order, in
//! `f32`, on the lane functions of [`super::ggx`] and
//! [`super::rough_dielectric::fresnel_dielectric`].
//!
//! What the scalar BSDF precomputes per material is taken as it is:
//! - the coating's directional transmittance `T(μ)`, Mitsuba's 64-entry table of
//!   `RoughPlasticTables::external_transmittance`, copied into the scene's flat
//!   [`WideScene::transmittance`] table (64 rows per material) and interpolated
//!   linearly in the lanes as `RoughPlasticTables::transmittance` does;
//! - the base seen through the coating, `ρ / (1 − R_int) / η²` (per channel
//!   `ρ / (1 − ρ R_int)` with `nonlinear`), from the internal reflectance `R_int`
//!   (Mitsuba's rectangle-rule mean over the same 64 cosines);
//! - the specular sampling weight `s = mean(specular) / (mean(diffuse) +
//!   mean(specular))`, with which the specular lobe is chosen with probability
//!   `(1 − T(θo)) s / ((1 − T(θo)) s + T(θo) (1 − s))` against the lobe number.
//!
//! One-sided (the kernel stops lanes that see it from behind); a glossy and a diffuse
//! lobe, so light samples are weighted against the mixture's density.

use super::bsdf::cosine_hemisphere;
use super::gather::{checked, field, Table};
use super::ggx::{d, g1, pdf_visible, sample_visible, shading, RoughSample};
use super::rough_dielectric::fresnel_dielectric;
use super::{mat, WideScene};
use irradia_core::Rgb;
use irradia_geometry::packet::lanes::{Fw, Mw, V3, W};
use irradia_scatter::bsdfs::roughplastic::TRANSMITTANCE_RES;
use irradia_scatter::bsdfs::RoughPlastic;
use std::f32::consts::FRAC_1_PI;

/// Rows of [`WideScene::transmittance`] per material.
pub(super) const ROWS: usize = TRANSMITTANCE_RES;

/// The shading-table fields of a rough plastic (`ROUGH`, `KIND`, `ALPHA`, `ETA`,
/// `SPEC_R`, `COAT`, `SPEC_WEIGHT`) and its transmittance table, precomputed as the
/// scalar BSDF computes them.
pub(super) fn record(p: &RoughPlastic, row: &mut [f32; mat::LEN]) -> [f32; ROWS] {
    row[mat::ROUGH] = 1.0;
    row[mat::KIND] = mat::KIND_PLASTIC;
    row[mat::ALPHA] = p.distribution.alpha_u;
    row[mat::ETA] = p.eta;
    let s = p.specular_reflectance;
    row[mat::SPEC_R..mat::SPEC_R + 3].copy_from_slice(&[s.r, s.g, s.b]);
    // `RoughPlastic::diffuse_through_coating`.
    let r_int = p.tables.internal_reflectance;
    let rho = p.diffuse_reflectance;
    let denom = if p.nonlinear {
        Rgb::WHITE - rho * r_int
    } else {
        Rgb::splat(1.0 - r_int)
    };
    let coat = Rgb::new(rho.r / denom.r, rho.g / denom.g, rho.b / denom.b) / (p.eta * p.eta);
    row[mat::COAT..mat::COAT + 3].copy_from_slice(&[coat.r, coat.g, coat.b]);
    // `RoughPlastic::prob_specular`'s weight.
    let s_mean = p.specular_reflectance.mean();
    let total = p.diffuse_reflectance.mean() + s_mean;
    row[mat::SPEC_WEIGHT] = if total > 0.0 { s_mean / total } else { 0.0 };
    p.tables.external_transmittance
}

/// A rough plastic's parameters in every lane.
pub(super) struct PlasticParams<'t> {
    pub alpha: Fw,
    /// `int_ior / ext_ior`.
    pub eta: Fw,
    pub spec_r: V3,
    /// `ρ / (1 − R_int) / η²`.
    pub coat: V3,
    /// The specular sampling weight `s`.
    pub spec_weight: Fw,
    /// The transmittance tables and each lane's first row in them.
    pub table: &'t Table<1>,
    pub first: [u32; W],
}

impl<'t> PlasticParams<'t> {
    /// The materials' parameters from the shading table (α times the test factor) and
    /// their transmittance rows.
    #[inline(always)]
    pub(super) fn gather(ws: &'t WideScene<'_, '_>, material: &[u32; W]) -> Self {
        let rgb = |at: usize| {
            V3::new(
                shading(ws, material, at),
                shading(ws, material, at + 1),
                shading(ws, material, at + 2),
            )
        };
        Self {
            alpha: shading(ws, material, mat::ALPHA) * ws.alpha_scale,
            eta: shading(ws, material, mat::ETA),
            spec_r: rgb(mat::SPEC_R),
            coat: rgb(mat::COAT),
            spec_weight: shading(ws, material, mat::SPEC_WEIGHT),
            table: &ws.transmittance,
            first: material.map(|m| m * ROWS as u32),
        }
    }

    /// `T(cos θ)`, interpolated linearly as `RoughPlasticTables::transmittance`.
    #[inline(always)]
    fn transmittance(&self, cos_theta: Fw) -> Fw {
        let x = cos_theta * (ROWS - 1) as f32;
        // `x.max(0) as usize`, at most the last interval.
        let i = x.max(0.0).map(f32::trunc).min((ROWS - 2) as f32);
        let i0: [u32; W] = std::array::from_fn(|l| self.first[l] + i.0[l] as u32);
        let i1 = i0.map(|k| k + 1);
        checked(self.table, &i1);
        let (v0, v1) = (field(self.table, &i0, 0), field(self.table, &i1, 0));
        v0 + (v1 - v0) * (x - i)
    }

    /// `RoughPlastic::prob_specular` given `T(cos θo)`.
    #[inline(always)]
    fn prob_specular(&self, t_o: Fw) -> Fw {
        let sw = self.spec_weight;
        let (s, d) = ((1.0 - t_o) * sw, t_o * (1.0 - sw));
        (s + d).gt(0.0).keep(s / (s + d))
    }

    /// `RoughPlastic::{eval, pdf}` for `wo`, `wi` (zero unless both are above the
    /// surface); `t_o` is `T(wo.z)`.
    #[inline(always)]
    fn eval_pdf(&self, wo: V3, wi: V3, t_o: Fw) -> (V3, Fw) {
        let alpha = self.alpha;
        let both = wo.z.gt(0.0) & wi.z.gt(0.0);
        let h = wo.add(wi).normalize();
        let dh = d(h, alpha);
        let f = fresnel_dielectric(wo.dot(h), self.eta).r;
        let g = g1(wo, h, alpha) * g1(wi, h, alpha);
        let specular = self
            .spec_r
            .scale(f * dh * g / (4.0 * wo.z * wi.z))
            .keep(dh.gt(0.0));
        let t = t_o * self.transmittance(wi.z);
        let value = specular.add(self.coat.scale(FRAC_1_PI * t)).keep(both);
        let p_spec = self.prob_specular(t_o);
        let wi_h = wi.dot(h);
        let spec_pdf = wi_h.gt(0.0).keep(pdf_visible(wo, h, alpha) / (4.0 * wi_h));
        let diffuse_pdf = wi.z.max(0.0) * FRAC_1_PI;
        let pdf = both.keep(p_spec * spec_pdf + (1.0 - p_spec) * diffuse_pdf);
        (value, pdf)
    }
}

/// `RoughPlastic::{eval, pdf}` for the light direction `wi` in the lanes of `light`,
/// and `RoughPlastic::sample` with the numbers `u_lobe`, `u` in the lanes of `active`.
#[inline(always)]
pub(super) fn rough_plastic(
    p: &PlasticParams<'_>,
    wo: V3,
    wi: V3,
    u_lobe: Fw,
    u: [Fw; 2],
    light: Mw,
    active: Mw,
) -> RoughSample {
    let t_o = p.transmittance(wo.z);
    let (f_light, pdf_light) = p.eval_pdf(wo, wi, t_o);

    // The sample: the coating's reflection about a visible normal, or the base's
    // cosine-weighted direction.
    let specular = u_lobe.lt(p.prob_specular(t_o));
    let m = sample_visible(wo, u, p.alpha);
    let m_ok = wo.z.gt(0.0) & m.finite() & m.z.gt(0.0);
    let pdf_m = m_ok.keep(pdf_visible(wo, m, p.alpha));
    let reflected = m.scale(2.0 * wo.dot(m)).sub(wo).normalize();
    let wi_s = V3::select(specular, reflected, cosine_hemisphere(u));
    let (f, pdf) = p.eval_pdf(wo, wi_s, t_o);
    let ok = active & wo.z.gt(0.0) & (!specular | pdf_m.gt(0.0)) & wi_s.z.gt(0.0) & pdf.gt(0.0);
    RoughSample {
        f_light: f_light.keep(light),
        pdf_light: light.keep(pdf_light),
        ok,
        wi: wi_s,
        weight: f.scale(wi_s.z / pdf).keep(ok),
        pdf: ok.keep(pdf),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec2, Vec3};
    use irradia_core::Rng;
    use irradia_scatter::microfacet::{Microfacet, MicrofacetType};
    use irradia_scatter::Scatter;

    fn v(w: Vec3) -> V3 {
        let mut l = V3::ZERO;
        for lane in 0..W {
            l.set_lane(lane, w);
        }
        l
    }

    /// Lanes of `RoughPlastic` against the scalar BSDF: α 0.01 to 0.8, η 1.33 to 1.9,
    /// several diffuse reflectances, linear and `nonlinear` (a unit test of the BSDF
    /// alone; the kernel's agreement is tests/path_wide_rough*.rs).
    #[test]
    fn value_density_and_sample_match_the_scalar_bsdf() {
        let close = |a: f32, b: f32| (a - b).abs() <= 2e-4 * a.abs().max(b.abs()) + 1e-6;
        let mut rng = Rng::new(5, 17);
        let mut plastics = Vec::new();
        for (k, alpha) in [0.01, 0.1, 0.3, 0.8].into_iter().enumerate() {
            for (j, eta) in [1.33, 1.5, 1.9].into_iter().enumerate() {
                let rho = [
                    Rgb::new(0.1, 0.27, 0.36),
                    Rgb::splat(0.5),
                    Rgb::new(0.9, 0.2, 0.05),
                ][(k + j) % 3];
                plastics.push(RoughPlastic::new(
                    Microfacet::new(MicrofacetType::Ggx, alpha, alpha, true),
                    eta,
                    rho,
                    Rgb::new(1.0, 0.95, 0.9),
                    (k + j) % 2 == 1,
                ));
            }
        }
        let mut rows = Vec::new();
        let mut table = Vec::new();
        for p in &plastics {
            let mut row = [0.0; mat::LEN];
            table.extend(record(p, &mut row).map(|t| [t]));
            rows.push(row);
        }
        let table = Table::new(table);
        let mut lobes = [0usize; 2];
        for _ in 0..4000 {
            let which = (rng.next_f32() * plastics.len() as f32) as usize % plastics.len();
            let (b, row) = (&plastics[which], &rows[which]);
            let mut dir = || {
                let z = (2.0 * rng.next_f32() - 1.0) * 0.98;
                let phi = std::f32::consts::TAU * rng.next_f32();
                let s = (1.0 - z * z).sqrt();
                Vec3::new(s * phi.cos(), s * phi.sin(), z)
            };
            let (mut wo, wi) = (dir(), dir());
            wo.z = wo.z.abs();
            let (u_lobe, u) = (rng.next_f32(), Vec2::new(rng.next_f32(), rng.next_f32()));
            let p = PlasticParams {
                alpha: Fw::splat(row[mat::ALPHA]),
                eta: Fw::splat(row[mat::ETA]),
                spec_r: v(Vec3::from_slice(&row[mat::SPEC_R..])),
                coat: v(Vec3::from_slice(&row[mat::COAT..])),
                spec_weight: Fw::splat(row[mat::SPEC_WEIGHT]),
                table: &table,
                first: [which as u32 * ROWS as u32; W],
            };
            let s = rough_plastic(
                &p,
                v(wo),
                v(wi),
                Fw::splat(u_lobe),
                [Fw::splat(u.x), Fw::splat(u.y)],
                Mw::TRUE,
                Mw::TRUE,
            );
            let lane = 5;
            let (f, pdf) = (s.f_light.lane(lane), s.pdf_light.0[lane]);
            let want = b.eval(wo, wi);
            assert!(
                close(f.x, want.r) && close(f.y, want.g) && close(f.z, want.b),
                "f {f:?} vs {want:?}"
            );
            assert!(close(pdf, b.pdf(wo, wi)), "pdf {pdf} vs {}", b.pdf(wo, wi));
            match b.sample(wo, u_lobe, u) {
                Some(want) => {
                    assert!(s.ok.get(lane), "no lane sample where the scalar has one");
                    assert!((s.wi.lane(lane) - want.wi).abs().max_element() < 1e-4);
                    assert!(close(s.pdf.0[lane], want.pdf));
                    let w = s.weight.lane(lane);
                    assert!(close(w.x, want.weight.r) && close(w.y, want.weight.g));
                    assert!(close(w.z, want.weight.b));
                    let glossy = want.lobe == irradia_scatter::LobeFlags::GLOSSY_REFLECTION;
                    lobes[glossy as usize] += 1;
                }
                None => assert!(!s.ok.get(lane), "a lane sample where the scalar has none"),
            }
        }
        // Both lobes were exercised.
        assert!(lobes[0] > 300 && lobes[1] > 300, "{lobes:?}");
    }

    #[test]
    fn transmittance_interpolates_as_the_scalar_table() {
        let p = RoughPlastic::new(
            Microfacet::new(MicrofacetType::Ggx, 0.2, 0.2, true),
            1.5,
            Rgb::splat(0.5),
            Rgb::WHITE,
            false,
        );
        let mut row = [0.0; mat::LEN];
        let table: Vec<[f32; 1]> = [[0.0; ROWS], record(&p, &mut row)]
            .concat()
            .into_iter()
            .map(|t| [t])
            .collect();
        let table = Table::new(table);
        let params = PlasticParams {
            alpha: Fw::splat(0.2),
            eta: Fw::splat(1.5),
            spec_r: V3::ZERO,
            coat: V3::ZERO,
            spec_weight: Fw::ZERO,
            table: &table,
            first: [ROWS as u32; W],
        };
        for k in 0..=200 {
            let c = k as f32 / 200.0;
            let got = params.transmittance(Fw::splat(c)).0[0];
            assert_eq!(got, p.tables.transmittance(c), "T({c})");
        }
    }
}
