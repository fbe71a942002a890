//! Microfacet distributions of normals: Beckmann and GGX (Trowbridge-Reitz), isotropic
//! or anisotropic, with Smith's masking and their sampling (Walter, Marschner, Li and
//! Torrance 2007, "Microfacet Models for Refraction through Rough Surfaces"; Heitz 2014,
//! "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs"; as Mitsuba
//! 3's `MicrofacetDistribution` in `microfacet.h`).
//!
//! Directions are in the local frame of the macrosurface (normal +z); `alpha_u` is the
//! roughness along x, `alpha_v` along y.

use crate::special::{erf, erfc, erfinv};
use glam::{Vec2, Vec3};
use std::f64::consts::PI as PI64;

/// Which distribution of microfacet normals.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MicrofacetType {
    /// Beckmann's Gaussian distribution of slopes (Walter et al. 2007, eq. 25).
    Beckmann,
    /// GGX / Trowbridge-Reitz (Walter et al. 2007, eq. 33): longer tails.
    Ggx,
}

impl MicrofacetType {
    /// Mitsuba's `distribution` name: `"beckmann"` or `"ggx"`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "beckmann" => Some(Self::Beckmann),
            "ggx" => Some(Self::Ggx),
            _ => None,
        }
    }

    /// The names [`MicrofacetType::from_name`] accepts.
    pub const NAMES: &'static [&'static str] = &["beckmann", "ggx"];
}

/// The smallest roughness, as Mitsuba (below it the lobe is numerically a delta).
pub const MIN_ALPHA: f32 = 1e-4;

/// A microfacet distribution with its roughness and sampling strategy.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Microfacet {
    pub kind: MicrofacetType,
    pub alpha_u: f32,
    pub alpha_v: f32,
    /// Sample only the normals visible from the incident direction (Heitz and d'Eon
    /// 2014) rather than all normals by `D(m) cos θm`.
    pub sample_visible: bool,
}

impl Microfacet {
    /// A distribution with roughness `alpha_u` along x and `alpha_v` along y, both at
    /// least [`MIN_ALPHA`].
    pub fn new(kind: MicrofacetType, alpha_u: f32, alpha_v: f32, sample_visible: bool) -> Self {
        Self {
            kind,
            alpha_u: alpha_u.max(MIN_ALPHA),
            alpha_v: alpha_v.max(MIN_ALPHA),
            sample_visible,
        }
    }

    /// Whether the roughness depends on the azimuth.
    pub fn is_anisotropic(&self) -> bool {
        self.alpha_u != self.alpha_v
    }

    /// The same distribution with both roughnesses multiplied by `s` (Walter et al.'s
    /// widened sampling distribution, §5.3).
    pub fn scaled(&self, s: f32) -> Self {
        Self::new(
            self.kind,
            self.alpha_u * s,
            self.alpha_v * s,
            self.sample_visible,
        )
    }

    /// The distribution of normals D(m), normalised so that ∫ D(m) cos θm dm = 1.
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let (au, av) = (self.alpha_u as f64, self.alpha_v as f64);
        let (x, y, z) = (m.x as f64, m.y as f64, m.z as f64);
        let cos2 = z * z;
        let slope2 = (x / au).powi(2) + (y / av).powi(2);
        let result = match self.kind {
            MicrofacetType::Beckmann => (-slope2 / cos2).exp() / (PI64 * au * av * cos2 * cos2),
            MicrofacetType::Ggx => 1.0 / (PI64 * au * av * (slope2 + cos2).powi(2)),
        };
        // Numerically negligible values would only add noise, as Mitsuba.
        if result * z > 1e-20 {
            result as f32
        } else {
            0.0
        }
    }

    /// `α² tan² θ` of `v` with the roughness projected on its azimuth.
    fn tan2_alpha(&self, v: Vec3) -> f64 {
        let xy =
            (self.alpha_u as f64 * v.x as f64).powi(2) + (self.alpha_v as f64 * v.y as f64).powi(2);
        if xy == 0.0 {
            0.0
        } else {
            xy / (v.z as f64).powi(2)
        }
    }

    /// Smith's Λ(v) (Heitz 2014, §5.1): the masked projected area over the visible one.
    /// Beckmann's is the exact error-function form, GGX's the closed form.
    pub fn lambda(&self, v: Vec3) -> f32 {
        let t2 = self.tan2_alpha(v);
        if t2 == 0.0 {
            return 0.0;
        }
        match self.kind {
            MicrofacetType::Beckmann => {
                let a = 1.0 / t2.sqrt();
                let l = 0.5 * ((-a * a).exp() / (a * PI64.sqrt()) - erfc(a));
                l.max(0.0) as f32
            }
            MicrofacetType::Ggx => (0.5 * ((1.0 + t2).sqrt() - 1.0)) as f32,
        }
    }

    /// Smith's masking of microfacet `m` seen from `v`, `χ⁺(v·m / v·n) / (1 + Λ(v))`.
    pub fn g1(&self, v: Vec3, m: Vec3) -> f32 {
        if v.dot(m) * v.z <= 0.0 {
            return 0.0;
        }
        1.0 / (1.0 + self.lambda(v))
    }

    /// The separable (uncorrelated) masking-shadowing `G1(wi, m) G1(wo, m)` that
    /// Mitsuba uses.
    pub fn g(&self, wi: Vec3, wo: Vec3, m: Vec3) -> f32 {
        self.g1(wi, m) * self.g1(wo, m)
    }

    /// The density (per solid angle of `m`) with which [`Microfacet::sample`] draws `m`
    /// given `wi` (`wi.z > 0`): the distribution of visible normals
    /// `D(m) G1(wi, m) |wi·m| / cos θi` or of all normals `D(m) cos θm`.
    pub fn pdf(&self, wi: Vec3, m: Vec3) -> f32 {
        if self.sample_visible {
            if wi.z <= 0.0 {
                return 0.0;
            }
            self.pdf_visible(wi, m, || self.g1(wi, m))
        } else {
            self.d(m) * m.z
        }
    }

    /// The density of visible normals `D(m) G1(wi, m) |wi·m| / cos θi` (`wi.z > 0`),
    /// `g1` giving `G1(wi, m)`.
    #[inline]
    fn pdf_visible(&self, wi: Vec3, m: Vec3, g1: impl FnOnce() -> f32) -> f32 {
        self.d(m) * g1() * wi.dot(m).abs() / wi.z
    }

    /// Samples a microfacet normal given the incident direction `wi` (`wi.z > 0`; flip
    /// it first otherwise) and returns it with its [`Microfacet::pdf`] (0: no sample).
    pub fn sample(&self, wi: Vec3, u: Vec2) -> (Vec3, f32) {
        let m = if self.sample_visible {
            if wi.z <= 0.0 {
                return (Vec3::Z, 0.0);
            }
            match self.kind {
                MicrofacetType::Ggx => self.sample_visible_ggx(wi, u),
                MicrofacetType::Beckmann => self.sample_visible_beckmann(wi, u),
            }
        } else {
            self.sample_all(u)
        };
        if !m.is_finite() || m.z <= 0.0 {
            return (Vec3::Z, 0.0);
        }
        (m, self.pdf(wi, m))
    }

    /// All normals by `D(m) cos θm` (Walter et al. 2007, eqs. 28, 35): the azimuth from
    /// `tan φ = (α_v / α_u) tan 2πu₂`, then tan²θ from the inverted radial CDF.
    fn sample_all(&self, u: Vec2) -> Vec3 {
        let (au, av) = (self.alpha_u as f64, self.alpha_v as f64);
        let phi0 = 2.0 * PI64 * u.y as f64;
        let phi = (av * phi0.sin()).atan2(au * phi0.cos());
        let (sin_phi, cos_phi) = phi.sin_cos();
        let alpha2 = 1.0 / ((cos_phi / au).powi(2) + (sin_phi / av).powi(2));
        let ux = u.x as f64;
        let tan2 = match self.kind {
            MicrofacetType::Beckmann => -alpha2 * (1.0 - ux).ln(),
            MicrofacetType::Ggx => alpha2 * ux / (1.0 - ux),
        };
        let cos_theta = 1.0 / (1.0 + tan2).sqrt();
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        Vec3::new(
            (sin_theta * cos_phi) as f32,
            (sin_theta * sin_phi) as f32,
            cos_theta as f32,
        )
    }

    /// GGX's visible normals (Heitz 2018, "Sampling the GGX Distribution of Visible
    /// Normals", JCGT 7(4)): stretch the view to the hemisphere configuration, sample
    /// the projected hemisphere, unstretch.
    fn sample_visible_ggx(&self, wi: Vec3, u: Vec2) -> Vec3 {
        GgxStretch::new(self, wi).warp(&WarpPoint::new(u))
    }

    /// [`Microfacet::sample`] and [`Microfacet::pdf`] prepared for the one incident
    /// direction `wi`: what depends on `wi` alone is computed here, once, for a
    /// quadrature that draws many normals from it (see [`SamplerFrom`]).
    pub fn sampler_from(&self, wi: Vec3) -> SamplerFrom {
        let visible = self.sample_visible && wi.z > 0.0;
        SamplerFrom {
            distr: *self,
            wi,
            g1_wi: if visible {
                1.0 / (1.0 + self.lambda(wi))
            } else {
                0.0
            },
            stretch: (visible && self.kind == MicrofacetType::Ggx)
                .then(|| GgxStretch::new(self, wi)),
        }
    }

    /// Beckmann's visible normals as Mitsuba does it: stretch to unit roughness, sample
    /// the slopes of the visible normals (Jakob 2014, "An Improved Visible Normal
    /// Sampling Routine for the Beckmann Distribution"), rotate and unstretch (Heitz and
    /// d'Eon 2014, §4).
    fn sample_visible_beckmann(&self, wi: Vec3, u: Vec2) -> Vec3 {
        let (au, av) = (self.alpha_u as f64, self.alpha_v as f64);
        let w = glam::DVec3::new(au * wi.x as f64, av * wi.y as f64, wi.z as f64).normalize();
        let sin_theta = (w.x * w.x + w.y * w.y).sqrt();
        let (cos_phi, sin_phi) = if sin_theta > 0.0 {
            (w.x / sin_theta, w.y / sin_theta)
        } else {
            (1.0, 0.0)
        };
        let (sx, sy) = beckmann_visible_slopes_11(w.z, u.x as f64, u.y as f64);
        let rx = cos_phi * sx - sin_phi * sy;
        let ry = sin_phi * sx + cos_phi * sy;
        glam::DVec3::new(-rx * au, -ry * av, 1.0)
            .normalize()
            .as_vec3()
    }
}

/// The slopes of visible normals of the unit-roughness Beckmann distribution seen at
/// `cos θ` from the azimuth 0 (Jakob 2014): x̃ by Newton-bisection on its CDF (with
/// Jakob's fitted initial guess), ỹ by inverting a Gaussian.
fn beckmann_visible_slopes_11(cos_theta: f64, u1: f64, u2: f64) -> (f64, f64) {
    const INV_SQRT_PI: f64 = 0.564_189_583_547_756_3;
    if cos_theta > 0.9999 {
        // Normal incidence: every normal equally visible, a Gaussian of slopes.
        let r = (-(1.0 - u1).ln()).sqrt();
        let (s, c) = (2.0 * PI64 * u2).sin_cos();
        return (r * c, r * s);
    }
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let tan_theta = sin_theta / cos_theta;
    let cot_theta = 1.0 / tan_theta;
    // The CDF of x̃ in b = erf(x̃) on [-1, erf(cot θ)].
    let (mut a, mut c) = (-1.0, erf(cot_theta));
    let ux = u1.max(1e-9);
    let theta = cos_theta.acos();
    let fit = 1.0 + theta * (-0.876 + theta * (0.4265 - 0.0594 * theta));
    let mut b = c - (1.0 + c) * (1.0 - ux).powf(fit);
    let normalization = 1.0 / (1.0 + c + INV_SQRT_PI * tan_theta * (-cot_theta * cot_theta).exp());
    for _ in 0..50 {
        if !(b >= a && b <= c) {
            b = 0.5 * (a + c);
        }
        let x = erfinv(b);
        let value = normalization * (1.0 + b + INV_SQRT_PI * tan_theta * (-x * x).exp()) - ux;
        let derivative = normalization * (1.0 - x * tan_theta);
        if value.abs() < 1e-10 {
            break;
        }
        if value > 0.0 {
            c = b;
        } else {
            a = b;
        }
        b -= value / derivative;
    }
    (erfinv(b), erfinv(2.0 * u2 - 1.0))
}

/// A point of the unit square with what GGX's visible-normal warp takes of it (`√u₁`
/// and the sine and cosine of `2πu₂`), so that a quadrature that warps the same nodes
/// for many directions computes them once.
#[derive(Clone, Copy, Debug)]
pub struct WarpPoint {
    pub u: Vec2,
    r: f32,
    sin_phi: f32,
    cos_phi: f32,
}

impl WarpPoint {
    pub fn new(u: Vec2) -> Self {
        let phi = 2.0 * std::f32::consts::PI * u.y;
        let (sin_phi, cos_phi) = phi.sin_cos();
        Self {
            u,
            r: u.x.sqrt(),
            sin_phi,
            cos_phi,
        }
    }
}

/// GGX's view direction stretched to unit roughness with its tangent frame (Heitz
/// 2018, listing 1): the part of the visible-normal warp that depends on `wi` alone.
#[derive(Clone, Copy, Debug)]
struct GgxStretch {
    alpha_u: f32,
    alpha_v: f32,
    vh: Vec3,
    t1: Vec3,
    t2: Vec3,
}

impl GgxStretch {
    fn new(distr: &Microfacet, wi: Vec3) -> Self {
        let (au, av) = (distr.alpha_u, distr.alpha_v);
        let vh = Vec3::new(au * wi.x, av * wi.y, wi.z).normalize();
        let len2 = vh.x * vh.x + vh.y * vh.y;
        let t1 = if len2 > 0.0 {
            Vec3::new(-vh.y, vh.x, 0.0) / len2.sqrt()
        } else {
            Vec3::X
        };
        Self {
            alpha_u: au,
            alpha_v: av,
            vh,
            t1,
            t2: vh.cross(t1),
        }
    }

    /// The visible normal at `p`: a point of the projected hemisphere, unstretched.
    #[inline]
    fn warp(&self, p: &WarpPoint) -> Vec3 {
        let (r, vh) = (p.r, self.vh);
        let p1 = r * p.cos_phi;
        let s = 0.5 * (1.0 + vh.z);
        let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * p.sin_phi;
        let nh = p1 * self.t1 + p2 * self.t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * vh;
        Vec3::new(self.alpha_u * nh.x, self.alpha_v * nh.y, nh.z.max(0.0)).normalize()
    }
}

/// [`Microfacet::sample`] from one incident direction, made by
/// [`Microfacet::sampler_from`]: the stretched view frame and `G1(wi)` are computed
/// once, and the nodes come as [`WarpPoint`]s; the normals and densities are the same
/// numbers as [`Microfacet::sample`]'s (for the quadratures of `roughplastic`'s tables,
/// Mitsuba's `eval_reflectance` / `eval_transmittance`).
#[derive(Clone, Copy, Debug)]
pub struct SamplerFrom {
    distr: Microfacet,
    wi: Vec3,
    /// `1 / (1 + Λ(wi))` when visible normals are sampled.
    g1_wi: f32,
    /// GGX's stretched frame when visible normals are sampled.
    stretch: Option<GgxStretch>,
}

impl SamplerFrom {
    /// [`Microfacet::sample`]`(wi, p.u)`.
    #[inline]
    pub fn sample(&self, p: &WarpPoint) -> (Vec3, f32) {
        let (distr, wi) = (&self.distr, self.wi);
        if !distr.sample_visible {
            return distr.sample(wi, p.u);
        }
        if wi.z <= 0.0 {
            return (Vec3::Z, 0.0);
        }
        let m = match &self.stretch {
            Some(stretch) => stretch.warp(p),
            None => distr.sample_visible_beckmann(wi, p.u),
        };
        if !m.is_finite() || m.z <= 0.0 {
            return (Vec3::Z, 0.0);
        }
        // `G1(wi, m)` as `Microfacet::g1`: zero on the back of `m`.
        let g1 = || {
            if wi.dot(m) * wi.z <= 0.0 {
                0.0
            } else {
                self.g1_wi
            }
        };
        (m, distr.pdf_visible(wi, m, g1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(theta: f32, phi: f32) -> Vec3 {
        Vec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        )
    }

    /// ∫ D(m) cos θm dω over the hemisphere by the midpoint rule in (θ, φ).
    fn projected_area(d: &Microfacet) -> f64 {
        let (nt, np) = (2000, 256);
        let mut sum = 0.0;
        for i in 0..nt {
            let theta = (i as f64 + 0.5) / nt as f64 * PI64 / 2.0;
            for j in 0..np {
                let phi = (j as f64 + 0.5) / np as f64 * 2.0 * PI64;
                let m = dir(theta as f32, phi as f32);
                sum += d.d(m) as f64 * theta.cos() * theta.sin();
            }
        }
        sum * (PI64 / 2.0 / nt as f64) * (2.0 * PI64 / np as f64)
    }

    #[test]
    fn distributions_are_normalised() {
        for kind in [MicrofacetType::Beckmann, MicrofacetType::Ggx] {
            for (au, av) in [(0.1, 0.1), (0.5, 0.5), (0.2, 0.6), (0.8, 0.3)] {
                let d = Microfacet::new(kind, au, av, true);
                let a = projected_area(&d);
                // GGX's long tail converges slowly near θ = π/2 with the midpoint rule.
                assert!((a - 1.0).abs() < 3e-3, "{kind:?} {au} {av}: {a}");
            }
        }
    }

    /// The projected area of the visible microfacets equals that of the macrosurface:
    /// ∫ G1(v, m) max(0, v·m) D(m) dm = cos θv (Heitz 2014, eq. 9). This ties Λ to D.
    #[test]
    fn smith_lambda_conserves_projected_area() {
        for kind in [MicrofacetType::Beckmann, MicrofacetType::Ggx] {
            for (au, av) in [(0.3, 0.3), (0.2, 0.6)] {
                let d = Microfacet::new(kind, au, av, true);
                for &(theta_v, phi_v) in &[(0.3f32, 0.0f32), (1.0, 0.7), (1.4, 2.0)] {
                    let v = dir(theta_v, phi_v);
                    let (nt, np) = (1500, 300);
                    let mut sum = 0.0f64;
                    for i in 0..nt {
                        let theta = (i as f64 + 0.5) / nt as f64 * PI64 / 2.0;
                        for j in 0..np {
                            let phi = (j as f64 + 0.5) / np as f64 * 2.0 * PI64;
                            let m = dir(theta as f32, phi as f32);
                            sum += (d.g1(v, m) * v.dot(m).max(0.0) * d.d(m)) as f64 * theta.sin();
                        }
                    }
                    sum *= (PI64 / 2.0 / nt as f64) * (2.0 * PI64 / np as f64);
                    let expect = v.z as f64;
                    assert!(
                        (sum - expect).abs() < 4e-3 * expect.max(0.2),
                        "{kind:?} {au},{av} θv={theta_v}: {sum} vs {expect}"
                    );
                }
            }
        }
    }

    /// The prepared sampler of the quadratures gives `Microfacet::sample`'s numbers to
    /// the bit, for both distributions, both strategies and directions from normal
    /// incidence to grazing and below the horizon.
    #[test]
    fn sampler_from_one_direction_is_sample_to_the_bit() {
        for kind in [MicrofacetType::Beckmann, MicrofacetType::Ggx] {
            for visible in [false, true] {
                for (au, av) in [(0.1, 0.1), (0.3, 0.5), (0.005, 0.005)] {
                    let d = Microfacet::new(kind, au, av, visible);
                    for (theta, phi) in [(0.0, 0.0), (0.8, 0.4), (1.55, 2.0), (2.0, 1.0)] {
                        let wi = dir(theta, phi);
                        let sampler = d.sampler_from(wi);
                        for i in 0..23 {
                            for j in 0..19 {
                                let u = Vec2::new(i as f32 / 23.0, (j as f32 + 0.5) / 19.0);
                                let (m0, p0) = d.sample(wi, u);
                                let (m1, p1) = sampler.sample(&WarpPoint::new(u));
                                assert_eq!(
                                    (m0.to_array().map(f32::to_bits), p0.to_bits()),
                                    (m1.to_array().map(f32::to_bits), p1.to_bits()),
                                    "{kind:?} {au},{av} visible={visible} wi={wi} u={u}"
                                );
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn sampled_normals_have_their_pdf() {
        for kind in [MicrofacetType::Beckmann, MicrofacetType::Ggx] {
            for visible in [false, true] {
                let d = Microfacet::new(kind, 0.3, 0.5, visible);
                let wi = dir(0.8, 0.4);
                let (m, pdf) = d.sample(wi, Vec2::new(0.3, 0.7));
                assert!((m.length() - 1.0).abs() < 1e-5);
                assert!(pdf > 0.0 && (pdf - d.pdf(wi, m)).abs() < 1e-6 * pdf);
            }
        }
    }
}
