//! The reusable test harness for any [`Bsdf`]: what every BSDF of the crate must satisfy.
//!
//! - [`chi2_sampling`]: Pearson's χ² test of `sample` against `pdf`, as Mitsuba 3's
//!   `mitsuba.chi2` and pbrt's `bsdfs` test: the sphere is cut into bins uniform in
//!   `θ` and `φ` (uniform in θ so that narrow lobes near the poles are resolved by the
//!   quadrature); the expected count of a bin is the sample count times the pdf
//!   integrated over it numerically (a midpoint rule on a fine sub-grid); cells expecting
//!   fewer than 5 are pooled; a cell expecting nothing that receives 10 samples or more
//!   fails at once (fewer join the pool: the quadrature may miss a sliver of support); the p-value must exceed the Sidak-corrected level `1 - 0.99^(1/tests)`.
//! - [`check_samples`]: every smooth sample's weight is `f |cos θi| / pdf` and its pdf is
//!   `pdf(wo, wi)`; delta samples are invisible to `eval` (black for a purely delta
//!   BSDF, no spike at the delta direction in a mixture's smooth lobes); the integral of the
//!   pdf over the sphere equals the fraction of samples that are smooth (up to 5 binomial
//!   standard deviations and the quadrature error); the albedo (mean weight, with the
//!   radiance scaling 1/η² of refraction undone) is at most 1.
//! - [`check_reciprocity`]: `f(wo, wi) = f(wi, wo)` for reflection.
//!
//! Each check panics with a message naming the BSDF (`label`), the incident direction
//! and what failed.

#![allow(dead_code)]

use glam::{Vec2, Vec3};
use irradia_core::{Rgb, Rng};
use irradia_scatter::{Bsdf, LobeFlags, Scatter};
use std::f64::consts::PI;

/// Bins in `θ` over [0, π] and in `φ` over [-π, π].
pub const BINS_THETA: usize = 24;
pub const BINS_PHI: usize = 48;
/// Sub-grid per bin for the numerical integral of the pdf.
pub const SUBDIV: usize = 12;
/// Samples per χ² test.
pub const SAMPLES: usize = 400_000;
/// Cells expecting fewer samples than this are pooled (Mitsuba's `min_exp_frequency`).
const MIN_EXPECTED: f64 = 5.0;

/// A unit direction from polar angle `theta` (from +z) and azimuth `phi`.
pub fn dir(theta: f32, phi: f32) -> Vec3 {
    Vec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

/// Incident directions every BSDF is tested at: near-normal, oblique and grazing, at
/// an azimuth off the axes (for anisotropy); with `back` also from below.
pub fn incident_directions(back: bool) -> Vec<Vec3> {
    let mut v: Vec<Vec3> = [0.05f32, 0.6, 1.1, 1.45]
        .iter()
        .map(|&t| dir(t, 0.7))
        .collect();
    if back {
        v.extend(
            [0.3f32, 1.2]
                .iter()
                .map(|&t| dir(std::f32::consts::PI - t, -2.0)),
        );
    }
    v
}

fn bin_of(w: Vec3) -> usize {
    let theta = (w.z as f64).clamp(-1.0, 1.0).acos();
    let ct = (theta / PI * BINS_THETA as f64).floor() as isize;
    let phi = (w.y as f64).atan2(w.x as f64);
    let cp = ((phi + PI) / (2.0 * PI) * BINS_PHI as f64).floor() as isize;
    let ct = ct.clamp(0, BINS_THETA as isize - 1) as usize;
    let cp = cp.clamp(0, BINS_PHI as isize - 1) as usize;
    ct * BINS_PHI + cp
}

/// The pdf integrated over every bin (midpoint rule on `SUBDIV²` points per bin in
/// `θ` and `φ`, with the solid-angle measure `sin θ dθ dφ`; the sub-cell's exact
/// `cos θ` difference stands for `sin θ dθ`).
pub fn integrated_pdf(bsdf: &Bsdf, wo: Vec3) -> Vec<f64> {
    let mut out = vec![0.0; BINS_THETA * BINS_PHI];
    let n_t = BINS_THETA * SUBDIV;
    let n_p = BINS_PHI * SUBDIV;
    let d_theta = PI / n_t as f64;
    let d_phi = 2.0 * PI / n_p as f64;
    for i in 0..n_t {
        let (t0, t1) = (i as f64 * d_theta, (i + 1) as f64 * d_theta);
        let theta = 0.5 * (t0 + t1);
        let area = (t0.cos() - t1.cos()) * d_phi;
        let (s, z) = theta.sin_cos();
        for j in 0..n_p {
            let phi = -PI + (j as f64 + 0.5) * d_phi;
            let wi = Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, z as f32);
            let p = bsdf.pdf(wo, wi) as f64;
            out[(i / SUBDIV) * BINS_PHI + j / SUBDIV] += p * area;
        }
    }
    out
}

/// The p-value of a χ² statistic with `dof` degrees of freedom.
pub fn chi2_p_value(chi2: f64, dof: usize) -> f64 {
    if chi2 <= 0.0 {
        1.0
    } else {
        statrs::function::gamma::gamma_ur(dof as f64 / 2.0, chi2 / 2.0)
    }
}

/// Samples `n` directions from `wo` with a deterministic generator.
fn samples(
    bsdf: &Bsdf,
    wo: Vec3,
    n: usize,
    seed: u64,
) -> impl Iterator<Item = Option<irradia_scatter::BsdfSample>> + '_ {
    let mut rng = Rng::new(seed, 7);
    (0..n).map(move |_| {
        let u_lobe = rng.next_f32();
        let u = rng.next_2d();
        bsdf.sample(wo, u_lobe, u)
    })
}

/// Pearson's χ² test of the smooth samples from `wo` against the pdf; `tests` is the
/// number of χ² tests the caller runs (the Sidak correction). Skips BSDFs without a
/// smooth lobe.
pub fn chi2_sampling(label: &str, bsdf: &Bsdf, wo: Vec3, tests: usize) {
    if !bsdf.flags().has_smooth() {
        return;
    }
    let mut observed = vec![0.0f64; BINS_THETA * BINS_PHI];
    for s in samples(bsdf, wo, SAMPLES, 1).flatten() {
        if !s.is_delta() {
            observed[bin_of(s.wi)] += 1.0;
        }
    }
    let expected: Vec<f64> = integrated_pdf(bsdf, wo)
        .into_iter()
        .map(|p| p * SAMPLES as f64)
        .collect();
    let mut order: Vec<usize> = (0..expected.len()).collect();
    order.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]));
    let (mut chi2, mut dof) = (0.0, 0usize);
    let (mut pool_obs, mut pool_exp) = (0.0, 0.0);
    for &c in &order {
        let (o, e) = (observed[c], expected[c]);
        if e == 0.0 {
            // The quadrature can miss a sliver of support at a bin's edge: a few samples
            // join the pool, many mean samples where the pdf is 0.
            assert!(
                o < 10.0,
                "{label} wo={wo:?}: {o} samples in bin {c} where the pdf integrates to 0"
            );
            pool_obs += o;
        } else if e < MIN_EXPECTED {
            pool_obs += o;
            pool_exp += e;
        } else {
            chi2 += (o - e) * (o - e) / e;
            dof += 1;
        }
    }
    if pool_exp >= MIN_EXPECTED {
        chi2 += (pool_obs - pool_exp) * (pool_obs - pool_exp) / pool_exp;
        dof += 1;
    } else if pool_obs > 0.0 {
        // Too few to test on their own: fold them into the statistic's last cell count.
        assert!(
            pool_obs < 5.0 * MIN_EXPECTED,
            "{label} wo={wo:?}: {pool_obs} samples in cells expecting {pool_exp} in all"
        );
    }
    let dof = dof.saturating_sub(1).max(1);
    let p = chi2_p_value(chi2, dof);
    let alpha = 1.0 - (1.0 - 0.01f64).powf(1.0 / tests as f64);
    if p <= alpha {
        // The worst cells, for the message.
        let mut worst: Vec<(f64, usize)> = (0..expected.len())
            .filter(|&c| expected[c] >= MIN_EXPECTED)
            .map(|c| ((observed[c] - expected[c]).powi(2) / expected[c], c))
            .collect();
        worst.sort_by(|a, b| b.0.total_cmp(&a.0));
        let worst: Vec<String> = worst
            .iter()
            .take(4)
            .map(|&(_, c)| {
                format!(
                    "bin(θ#{}, φ#{}) obs {} exp {:.1}",
                    c / BINS_PHI,
                    c % BINS_PHI,
                    observed[c],
                    expected[c]
                )
            })
            .collect();
        panic!(
            "{label} wo={wo:?}: χ² = {chi2:.1} with {dof} dof, p = {p:.3e} <= {alpha:.3e}; worst: {}",
            worst.join("; ")
        );
    }
}

/// Per-sample consistency of `sample` with `eval` and `pdf`, the pdf's total mass
/// against the sampled fraction, and the albedo bound.
pub fn check_samples(label: &str, bsdf: &Bsdf, wo: Vec3) {
    let n = 100_000;
    let (mut smooth, mut albedo) = (0usize, Rgb::BLACK);
    let mut albedo_sq = [0.0f64; 3];
    for s in samples(bsdf, wo, n, 2).flatten() {
        assert!(
            s.weight.is_finite() && s.weight.r >= 0.0 && s.weight.g >= 0.0 && s.weight.b >= 0.0,
            "{label} wo={wo:?}: weight {:?}",
            s.weight
        );
        assert!(
            (s.wi.length() - 1.0).abs() < 1e-3,
            "{label}: |wi| = {}",
            s.wi.length()
        );
        assert!(
            s.pdf > 0.0 && s.pdf.is_finite(),
            "{label}: sample pdf {}",
            s.pdf
        );
        let transmitted = s.wi.z * wo.z < 0.0;
        assert_eq!(
            transmitted,
            s.lobe.intersects(LobeFlags::TRANSMISSION),
            "{label} wo={wo:?} wi={:?}: the lobe {:?} says the other side",
            s.wi,
            s.lobe
        );
        if s.is_delta() {
            // `eval` holds the smooth lobes only: black when there are none, and
            // otherwise the same as a hair's breadth away (no spike at the delta
            // direction, which a mixture's smooth lobes would not have).
            let f = bsdf.eval(wo, s.wi);
            if !bsdf.flags().has_smooth() {
                assert!(f.is_black(), "{label}: eval sees a delta lobe: {f:?}");
            } else {
                let near = nudge(s.wi);
                let g = bsdf.eval(wo, near);
                for c in 0..3 {
                    assert!(
                        f[c].is_finite() && (f[c] - g[c]).abs() <= 0.02 * f[c].max(g[c]) + 1e-4,
                        "{label} wo={wo:?} wi={:?}: eval sees a delta lobe: {f:?} there, {g:?} at {near:?}",
                        s.wi
                    );
                }
            }
        } else {
            smooth += 1;
            let f = bsdf.eval(wo, s.wi);
            let pdf = bsdf.pdf(wo, s.wi);
            let rel = |a: f32, b: f32| (a - b).abs() <= 2e-3 * a.abs().max(b.abs()) + 1e-6;
            assert!(
                rel(pdf, s.pdf),
                "{label} wo={wo:?} wi={:?}: sampled pdf {} vs pdf() {pdf}",
                s.wi,
                s.pdf
            );
            let w = f * (s.wi.z.abs() / s.pdf);
            assert!(
                rel(w.r, s.weight.r) && rel(w.g, s.weight.g) && rel(w.b, s.weight.b),
                "{label} wo={wo:?} wi={:?}: weight {:?} but f|cos|/pdf = {w:?}",
                s.wi,
                s.weight
            );
        }
        // Undo the radiance scaling (η_i/η_t)² of refraction: energy is conserved.
        let energy = if transmitted {
            s.weight * (s.eta * s.eta)
        } else {
            s.weight
        };
        albedo += energy;
        for c in 0..3 {
            albedo_sq[c] += (energy[c] as f64).powi(2);
        }
    }
    let mass: f64 = integrated_pdf(bsdf, wo).iter().sum();
    let frac = smooth as f64 / n as f64;
    let sigma = (frac * (1.0 - frac) / n as f64).sqrt();
    assert!(
        (mass - frac).abs() <= 5.0 * sigma + 0.01 * frac.max(0.02),
        "{label} wo={wo:?}: ∫pdf dω = {mass:.4} but {frac:.4} of the samples are smooth"
    );
    for c in 0..3 {
        let mean = albedo[c] as f64 / n as f64;
        let var = (albedo_sq[c] / n as f64 - mean * mean).max(0.0);
        let tol = 5.0 * (var / n as f64).sqrt() + 1e-4;
        assert!(
            mean <= 1.0 + tol,
            "{label} wo={wo:?}: albedo {mean:.4} > 1 (channel {c})"
        );
    }
}

/// `f(wo, wi) = f(wi, wo)` on pairs of directions on the same side (reflection).
pub fn check_reciprocity(label: &str, bsdf: &Bsdf) {
    let mut rng = Rng::new(3, 11);
    for _ in 0..2000 {
        let a = uniform_sphere(rng.next_2d());
        let mut b = uniform_sphere(rng.next_2d());
        if a.z * b.z < 0.0 {
            b.z = -b.z;
        }
        let (f_ab, f_ba) = (bsdf.eval(a, b), bsdf.eval(b, a));
        for c in 0..3 {
            let (x, y) = (f_ab[c], f_ba[c]);
            assert!(
                (x - y).abs() <= 1e-3 * x.abs().max(y.abs()) + 1e-6,
                "{label}: f({a:?}, {b:?}) = {x} but f(wi, wo) = {y}"
            );
        }
    }
}

/// `w` turned by about 2e-3 rad about an axis perpendicular to it (same hemisphere).
fn nudge(w: Vec3) -> Vec3 {
    let axis = if w.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
    let t = w.cross(axis).normalize();
    let v = (w + 2e-3 * t).normalize();
    if v.z * w.z > 0.0 {
        v
    } else {
        (w - 2e-3 * t).normalize()
    }
}

fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * std::f32::consts::PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Every check at every incident direction (`back`: also from below, for two-sided
/// BSDFs); `tests` as [`chi2_sampling`].
pub fn check_bsdf(label: &str, bsdf: &Bsdf, back: bool, tests: usize) {
    for wo in incident_directions(back) {
        chi2_sampling(label, bsdf, wo, tests);
        check_samples(label, bsdf, wo);
    }
    check_reciprocity(label, bsdf);
}
