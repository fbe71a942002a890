//! The glossy lobes of the wide kernel's vector stage in one call (see [`super`]):
//! each lane's `roughconductor` ([`super::ggx`]), `roughdielectric`
//! ([`super::rough_dielectric`]) or `roughplastic` ([`super::rough_plastic`]), chosen by
//! its material's [`mat::KIND`], each BSDF run only when some lane needs it. The
//! kernel treats them alike, as the scalar estimator treats a non-delta BSDF: a light
//! sample weighted by the power heuristic against the BSDF's density, and the BSDF's
//! own sample.

use super::ggx::{rough_conductor, shading, RoughSample};
use super::rough_dielectric::{rough_dielectric, DielectricParams};
use super::rough_plastic::{rough_plastic, PlasticParams};
use super::{mat, WideScene};
use irradia_geometry::packet::lanes::{Fw, Mw, V3, W};

/// The glossy lobes' value and density for the light sample's direction, and their own
/// sample.
pub(super) struct Glossy {
    /// `f(wo, wi)` and its density for the light direction `wi` (zero where not asked).
    pub f_light: V3,
    pub pdf_light: Fw,
    /// Lanes whose BSDF also transmits (the rough dielectric): their light sample may
    /// lie on the other side of the surface.
    pub transmits: Mw,
    /// A valid sample: its direction, weight `f |cos θi| / pdf`, density and the
    /// relative index of refraction crossed (1 but for a rough dielectric's
    /// refraction).
    pub ok: Mw,
    pub wi: V3,
    pub weight: V3,
    pub pdf: Fw,
    pub eta: Fw,
}

impl Glossy {
    /// One BSDF's values and sample in the lanes of `kind` (its `ok` is already limited
    /// to those lanes).
    #[inline(always)]
    fn take(&mut self, kind: Mw, r: &RoughSample) {
        self.f_light = V3::select(kind, r.f_light, self.f_light);
        self.pdf_light = kind.select(r.pdf_light, self.pdf_light);
        self.ok = self.ok | r.ok;
        self.wi = V3::select(kind, r.wi, self.wi);
        self.weight = V3::select(kind, r.weight, self.weight);
        self.pdf = kind.select(r.pdf, self.pdf);
    }
}

/// The glossy BSDFs of `material` for the light direction `wi` in the lanes of `light`
/// and sampled with `u_lobe`, `u` in the lanes of `active` (both masks already limited
/// to glossy materials).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(super) fn glossy(
    ws: &WideScene<'_, '_>,
    material: &[u32; W],
    wo: V3,
    wi: V3,
    u_lobe: Fw,
    u: [Fw; 2],
    light: Mw,
    active: Mw,
) -> Glossy {
    let kind = shading(ws, material, mat::KIND);
    let conductor = kind.eq(mat::KIND_CONDUCTOR);
    let dielectric = kind.eq(mat::KIND_DIELECTRIC);
    let plastic = kind.eq(mat::KIND_PLASTIC);
    let wanted = light | active;
    let mut g = Glossy {
        f_light: V3::ZERO,
        pdf_light: Fw::ZERO,
        transmits: dielectric,
        ok: Mw::FALSE,
        wi: V3::ZERO,
        weight: V3::ZERO,
        pdf: Fw::ZERO,
        eta: Fw::splat(1.0),
    };
    if (wanted & conductor).any() {
        let (l, a) = (light & conductor, active & conductor);
        g.take(conductor, &rough_conductor(ws, material, wo, wi, u, l, a));
    }
    if (wanted & dielectric).any() {
        let p = DielectricParams::gather(ws, material);
        let (l, a) = (light & dielectric, active & dielectric);
        let r = rough_dielectric(&p, wo, wi, u_lobe, u, l, a);
        g.take(dielectric, &r.lobe);
        g.eta = dielectric.select(r.eta, g.eta);
    }
    if (wanted & plastic).any() {
        let p = PlasticParams::gather(ws, material);
        let (l, a) = (light & plastic, active & plastic);
        g.take(plastic, &rough_plastic(&p, wo, wi, u_lobe, u, l, a));
    }
    g
}
