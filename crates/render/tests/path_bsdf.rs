//! Statistical tests of the path tracer's BSDFs: every lobe's sampling against its own
//! density (Pearson's chi-square, as Mitsuba and PBRT test theirs), energy
//! conservation over incident directions, and the dielectric's Fresnel split.

mod chi_square;

use chi_square::gamma_q;
use glam::{Vec2, Vec3};
use irradia_core::{Rgb, Rng};
use irradia_scatter::bsdfs::{LectureLobe as Lobe, LectureMix as Bsdf};
use irradia_scatter::{BsdfSample, Scatter};
use std::f64::consts::PI;

/// The dielectric Fresnel reflectance of the scattering toolkit's optics.
fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    irradia_scatter::optics::fresnel_dielectric(cos_i, eta).reflectance
}

const THETA_BINS: usize = 10;
const PHI_BINS: usize = 20;

fn dir(cos_t: f64, phi: f64) -> Vec3 {
    let s = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, cos_t as f32)
}

fn bin_of(w: Vec3) -> usize {
    let t = (((w.z as f64 + 1.0) / 2.0) * THETA_BINS as f64)
        .floor()
        .clamp(0.0, THETA_BINS as f64 - 1.0) as usize;
    let mut phi = (w.y as f64).atan2(w.x as f64);
    if phi < 0.0 {
        phi += 2.0 * PI;
    }
    let p = ((phi / (2.0 * PI)) * PHI_BINS as f64)
        .floor()
        .clamp(0.0, PHI_BINS as f64 - 1.0) as usize;
    t * PHI_BINS + p
}

/// 5-point Gauss-Legendre nodes and weights on [-1, 1].
const X: [f64; 5] = [
    -0.906_179_845_938_664,
    -0.538_469_310_105_683,
    0.0,
    0.538_469_310_105_683,
    0.906_179_845_938_664,
];
const W: [f64; 5] = [
    0.236_926_885_056_189,
    0.478_628_670_499_366,
    0.568_888_888_888_889,
    0.478_628_670_499_366,
    0.236_926_885_056_189,
];

/// Expected probability of each (cos θ, φ) bin: the density integrated by composite
/// 5-point Gauss-Legendre quadrature (the measure d(cos θ) dφ is the solid angle).
fn expected(pdf: impl Fn(Vec3) -> f64) -> Vec<f64> {
    let sub = 6;
    let (dz, dp) = (2.0 / THETA_BINS as f64, 2.0 * PI / PHI_BINS as f64);
    let (hz, hp) = (dz / sub as f64, dp / sub as f64);
    let mut out = vec![0.0; THETA_BINS * PHI_BINS];
    for t in 0..THETA_BINS {
        for p in 0..PHI_BINS {
            let mut s = 0.0;
            for i in 0..sub {
                for j in 0..sub {
                    let z0 = -1.0 + dz * t as f64 + hz * (i as f64 + 0.5);
                    let p0 = dp * p as f64 + hp * (j as f64 + 0.5);
                    for (xa, wa) in X.iter().zip(W) {
                        for (xb, wb) in X.iter().zip(W) {
                            s += wa * wb * pdf(dir(z0 + 0.5 * hz * xa, p0 + 0.5 * hp * xb));
                        }
                    }
                }
            }
            out[t * PHI_BINS + p] = s * 0.25 * hz * hp;
        }
    }
    out
}

/// Pearson's test of `n` samples of `bsdf` at `wo` against its `pdf`; returns the
/// p-value. Bins expecting fewer than 5 samples are pooled; samples of delta lobes
/// count with the rejected ones (the mass the pdf does not have).
fn chi_square(bsdf: &Model, wo: Vec3, n: usize, seed: u64) -> f64 {
    let exp = expected(|wi| (bsdf.pdf)(wo, wi) as f64);
    let mut obs = vec![0.0f64; exp.len()];
    let mut rng = Rng::new(seed, 11);
    let mut missing = 0.0;
    for _ in 0..n {
        match (bsdf.sample)(wo, rng.next_f32(), rng.next_2d()) {
            Some(s) if !s.is_delta() => {
                assert!(
                    (s.wi.length() - 1.0).abs() < 1e-3,
                    "sampled direction not unit: {}",
                    s.wi
                );
                assert!(
                    (s.pdf - (bsdf.pdf)(wo, s.wi)).abs() <= 1e-3 * s.pdf.max(1.0),
                    "sample pdf disagrees with pdf()"
                );
                obs[bin_of(s.wi)] += 1.0;
            }
            _ => missing += 1.0,
        }
    }
    // Samples the lobe rejects (below the horizon) are the mass the pdf does not have.
    let total_exp: f64 = exp.iter().sum();
    let (mut chi2, mut dof) = (0.0, 0i64);
    let (mut pool_o, mut pool_e) = (missing, (1.0 - total_exp).max(0.0) * n as f64);
    for (o, e) in obs.iter().zip(&exp) {
        let e = e * n as f64;
        if e < 5.0 {
            pool_o += o;
            pool_e += e;
        } else {
            chi2 += (o - e) * (o - e) / e;
            dof += 1;
        }
    }
    if pool_e >= 5.0 {
        chi2 += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
        dof += 1;
    } else {
        assert!(
            pool_o <= 10.0 + 3.0 * pool_e,
            "{pool_o} samples where the density expects {pool_e}"
        );
    }
    gamma_q((dof - 1) as f64 / 2.0, chi2 / 2.0)
}

fn lobes() -> Vec<(&'static str, Bsdf)> {
    vec![
        (
            "lambert",
            Bsdf::new().with(Lobe::Lambert {
                albedo: Rgb::splat(0.8),
            }),
        ),
        (
            "phong n=1",
            Bsdf::new().with(Lobe::Phong {
                ks: Rgb::splat(0.9),
                exponent: 1.0,
            }),
        ),
        (
            "phong n=20",
            Bsdf::new().with(Lobe::Phong {
                ks: Rgb::splat(0.9),
                exponent: 20.0,
            }),
        ),
        (
            "lambert+phong",
            Bsdf::new()
                .with(Lobe::Lambert {
                    albedo: Rgb::new(0.5, 0.3, 0.2),
                })
                .with(Lobe::Phong {
                    ks: Rgb::splat(0.3),
                    exponent: 8.0,
                }),
        ),
    ]
}

#[test]
fn sampling_matches_density_chi_square() {
    let wos = [
        Vec3::Z,
        Vec3::new(0.5, 0.2, 0.6).normalize(),
        Vec3::new(-0.9, 0.1, 0.2).normalize(),
        Vec3::new(0.3, 0.3, -0.8).normalize(),
    ];
    let tests = lobes().len() * wos.len();
    let alpha = 0.01 / tests as f64; // Šidák-style correction for many tests
    for (seed, (name, bsdf)) in lobes().into_iter().enumerate() {
        for (k, wo) in wos.iter().enumerate() {
            let p = chi_square(&Model::of(&bsdf), *wo, 200_000, (seed * 10 + k) as u64);
            assert!(p > alpha, "{name} at wo {wo}: chi-square p-value {p:e}");
        }
    }
}

#[test]
fn chi_square_detects_a_wrong_density() {
    // Guard that the test above can fail: a Phong lobe sampled with one exponent and
    // checked against another must be rejected.
    let sampled = Bsdf::new().with(Lobe::Phong {
        ks: Rgb::splat(0.9),
        exponent: 20.0,
    });
    let claimed = Bsdf::new().with(Lobe::Phong {
        ks: Rgb::splat(0.9),
        exponent: 16.0,
    });
    let wo = Vec3::new(0.5, 0.2, 0.6).normalize();
    let exp = expected(|wi| claimed.pdf(wo, wi) as f64);
    let mut obs = vec![0.0; exp.len()];
    let mut rng = Rng::new(3, 3);
    let n = 200_000;
    for _ in 0..n {
        if let Some(s) = sampled.sample(wo, rng.next_f32(), rng.next_2d()) {
            obs[bin_of(s.wi)] += 1.0;
        }
    }
    let chi2: f64 = obs
        .iter()
        .zip(&exp)
        .filter(|(_, e)| **e * n as f64 >= 5.0)
        .map(|(o, e)| (o - e * n as f64).powi(2) / (e * n as f64))
        .sum();
    let dof = exp.iter().filter(|e| **e * n as f64 >= 5.0).count();
    assert!(gamma_q((dof - 1) as f64 / 2.0, chi2 / 2.0) < 1e-6);
}

#[test]
fn every_lobe_conserves_energy() {
    let lobes = [
        Lobe::Lambert { albedo: Rgb::WHITE },
        Lobe::Phong {
            ks: Rgb::WHITE,
            exponent: 1.0,
        },
        Lobe::Phong {
            ks: Rgb::WHITE,
            exponent: 10.0,
        },
        Lobe::Phong {
            ks: Rgb::WHITE,
            exponent: 200.0,
        },
        Lobe::Mirror { r: Rgb::WHITE },
    ];
    for lobe in lobes {
        for i in 0..=18 {
            let theta = (i as f32) * 5.0f32.to_radians().min(89.0f32.to_radians());
            let theta = theta.min(89.5f32.to_radians());
            let wo = Vec3::new(theta.sin(), 0.0, theta.cos());
            let a = lobe.albedo(wo, 40_000).max_component();
            assert!(
                a <= 1.0 + 2e-3,
                "{lobe:?} at {:.0}°: albedo {a}",
                theta.to_degrees()
            );
        }
    }
    // The Lambertian lobe of albedo 1 reflects everything, at every angle.
    let a = Lobe::Lambert { albedo: Rgb::WHITE }
        .albedo(Vec3::new(0.6, 0.0, 0.8), 40_000)
        .g;
    assert!((a - 1.0).abs() < 1e-3);
}

#[test]
fn dielectric_splits_by_fresnel_and_refracts_by_snell() {
    let eta = 1.5f32;
    let lobe = Lobe::Dielectric {
        eta,
        tint: Rgb::WHITE,
        weight: 1.0,
    };
    let mut rng = Rng::new(5, 5);
    for cos in [1.0f32, 0.8, 0.4, 0.1, -0.95, -0.8] {
        let wo = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
        // The exact Fresnel reflectance, from the independent formula below.
        let f = fresnel_exact(cos as f64, eta as f64) as f32;
        let n = 20_000;
        let mut reflected = 0;
        for _ in 0..n {
            let s = lobe
                .sample(wo, rng.next_2d())
                .expect("a smooth dielectric always scatters");
            if s.wi.z * wo.z > 0.0 {
                reflected += 1;
                assert!((s.wi - Vec3::new(-wo.x, -wo.y, wo.z)).length() < 1e-5);
            } else {
                // Snell: η_i sin θ_i = η_t sin θ_t.
                let (ei, et) = if wo.z > 0.0 { (1.0, eta) } else { (eta, 1.0) };
                let sin_i = (1.0 - wo.z * wo.z).sqrt();
                let sin_t = (1.0 - s.wi.z * s.wi.z).sqrt();
                assert!((ei * sin_i - et * sin_t).abs() < 1e-4, "cos {cos}");
            }
        }
        let frac = reflected as f32 / n as f32;
        let sigma = (f * (1.0 - f) / n as f32).sqrt();
        assert!(
            (frac - f).abs() <= 5.0 * sigma + 1e-6,
            "cos {cos}: reflected {frac}, Fresnel {f}"
        );
    }
    // Beyond the critical angle everything reflects.
    let crit = (1.0f32 / eta).asin();
    let t = crit + 0.05;
    assert_eq!(fresnel_dielectric(-t.cos(), eta), 1.0);
    let wo = Vec3::new(t.sin(), 0.0, -t.cos());
    for _ in 0..100 {
        assert!(
            lobe.sample(wo, Vec2::new(rng.next_f32(), 0.3))
                .unwrap()
                .wi
                .z
                < 0.0
        );
    }
}

// ---------------------------------------------------------------------------------
// eval, pdf and sample tied together, and checked against independent closed forms.
// ---------------------------------------------------------------------------------

/// What the consistency checks see of a BSDF: its three entry points, so that the
/// power tests below can hand them deliberately broken versions.
struct Model<'a> {
    eval: Box<dyn Fn(Vec3, Vec3) -> Rgb + 'a>,
    pdf: Box<dyn Fn(Vec3, Vec3) -> f32 + 'a>,
    sample: Box<dyn Fn(Vec3, f32, Vec2) -> Option<BsdfSample> + 'a>,
}

impl<'a> Model<'a> {
    fn of(b: &'a Bsdf) -> Self {
        Model {
            eval: Box::new(move |wo, wi| b.eval(wo, wi)),
            pdf: Box::new(move |wo, wi| b.pdf(wo, wi)),
            sample: Box::new(move |wo, ul, u| b.sample(wo, ul, u)),
        }
    }
}

/// Composite 5-point Gauss-Legendre quadrature over the unit sphere in (cos θ, φ)
/// (whose measure is the solid angle): `f(direction, weight)` at every node. The
/// horizon cos θ = 0 is a cell boundary, so the integrands' jump there costs nothing.
fn sphere_quadrature(mut f: impl FnMut(Vec3, f64)) {
    const NZ: usize = 64;
    const NP: usize = 128;
    let (hz, hp) = (2.0 / NZ as f64, 2.0 * PI / NP as f64);
    for i in 0..NZ {
        for j in 0..NP {
            let (zc, pc) = (-1.0 + hz * (i as f64 + 0.5), hp * (j as f64 + 0.5));
            for (xa, wa) in X.iter().zip(W) {
                for (xb, wb) in X.iter().zip(W) {
                    let w = wa * wb * 0.25 * hz * hp;
                    f(dir(zc + 0.5 * hz * xa, pc + 0.5 * hp * xb), w);
                }
            }
        }
    }
}

/// ∫ pdf dω and ∫ f |cos θi| dω over the sphere, by quadrature.
fn integrals(m: &Model, wo: Vec3) -> (f64, [f64; 3]) {
    let (mut p, mut a) = (0.0, [0.0; 3]);
    sphere_quadrature(|wi, w| {
        p += w * (m.pdf)(wo, wi) as f64;
        let f = (m.eval)(wo, wi);
        let c = w * wi.z.abs() as f64;
        a[0] += c * f.r as f64;
        a[1] += c * f.g as f64;
        a[2] += c * f.b as f64;
    });
    (p, a)
}

/// The Monte Carlo side of a lobe at one `wo`.
struct Sampled {
    /// Fraction of samples from smooth lobes (the mass the pdf must integrate to).
    smooth: f64,
    /// Mean and standard error of the sampled weight, per channel.
    mean: [f64; 3],
    sigma: [f64; 3],
}

/// Draws `n` samples at `wo`, checking for each smooth one that its weight is
/// eval·|cos|/pdf at its direction and that its pdf is `pdf()` there.
fn draw(m: &Model, wo: Vec3, n: usize, seed: u64, errors: &mut Vec<String>) -> Sampled {
    let mut rng = Rng::new(seed, 7);
    let (mut smooth, mut sum, mut sum2) = (0usize, [0.0f64; 3], [0.0f64; 3]);
    let mut bad_weight = 0usize;
    let mut bad_pdf = 0usize;
    let mut first_bad = None;
    for _ in 0..n {
        let Some(s) = (m.sample)(wo, rng.next_f32(), rng.next_2d()) else {
            continue;
        };
        if !s.is_delta() {
            smooth += 1;
            let pdf = (m.pdf)(wo, s.wi);
            let expect = (m.eval)(wo, s.wi) * (s.wi.z.abs() / pdf);
            for c in 0..3 {
                let tol = 1e-4 * expect[c].abs().max(s.weight[c].abs()) + 1e-7;
                if (s.weight[c] - expect[c]).abs() > tol || pdf <= 0.0 || pdf.is_nan() {
                    bad_weight += 1;
                    first_bad.get_or_insert((s.wi, s.weight, expect));
                    break;
                }
            }
            if (s.pdf - pdf).abs() > 1e-4 * pdf.max(s.pdf) {
                bad_pdf += 1;
            }
        }
        for c in 0..3 {
            let w = s.weight[c] as f64;
            sum[c] += w;
            sum2[c] += w * w;
        }
    }
    if let Some((wi, got, want)) = first_bad {
        errors.push(format!(
            "weight: {bad_weight} of {n} sampled weights are not eval·cos/pdf (at wi {wi}: \
             {got:?}, eval·cos/pdf {want:?})"
        ));
    }
    if bad_pdf > 0 {
        errors.push(format!(
            "pdf: {bad_pdf} of {n} samples report a pdf other than pdf()"
        ));
    }
    let nf = n as f64;
    let mean = sum.map(|s| s / nf);
    let sigma = [0, 1, 2].map(|c| ((sum2[c] / nf - mean[c] * mean[c]).max(0.0) / nf).sqrt());
    Sampled {
        smooth: smooth as f64 / nf,
        mean,
        sigma,
    }
}

/// Ties eval, pdf and sample together at `wo`: the weight identity, ∫ pdf = the
/// fraction of smooth samples, the mean sampled weight = ∫ f |cos| (by quadrature)
/// plus `delta_albedo` (the delta lobes' part, from closed forms), and the histogram of
/// directions against the pdf (chi-square). Returns what failed, with the numbers.
fn check_consistency(
    m: &Model,
    wo: Vec3,
    delta_albedo: [f64; 3],
    n: usize,
    seed: u64,
    alpha: f64,
) -> Vec<String> {
    let mut errors = Vec::new();
    let (pdf_mass, albedo) = integrals(m, wo);
    let s = draw(m, wo, n, seed, &mut errors);
    let sd = (s.smooth * (1.0 - s.smooth) / n as f64).sqrt();
    if (pdf_mass - s.smooth).abs() > 5.0 * sd + 2e-4 {
        errors.push(format!(
            "pdf integral: ∫pdf = {pdf_mass:.5}, but {:.5} (±{sd:.1e}) of samples come from \
             the smooth lobes",
            s.smooth
        ));
    }
    for c in 0..3 {
        let want = albedo[c] + delta_albedo[c];
        if (s.mean[c] - want).abs() > 5.0 * s.sigma[c] + 2e-4 {
            errors.push(format!(
                "albedo: channel {c}: mean sampled weight {:.5} (±{:.1e}), quadrature of \
                 eval·cos {:.5} + delta {:.5} = {want:.5}",
                s.mean[c], s.sigma[c], albedo[c], delta_albedo[c]
            ));
        }
    }
    let p = chi_square(m, wo, n, seed ^ 0x5eed);
    if p <= alpha {
        errors.push(format!("chi-square: histogram p-value {p:e}"));
    }
    errors
}

/// Exact unpolarised Fresnel reflectance, written from the angles (Born and Wolf:
/// R_s = sin²(θi−θt)/sin²(θi+θt), R_p = tan²(θi−θt)/tan²(θi+θt)), independently of the
/// library's cosine form. `cos_i > 0`: light arrives from outside (index 1) onto the
/// medium of index `eta`; `cos_i < 0`: from inside.
fn fresnel_exact(cos_i: f64, eta: f64) -> f64 {
    let (n1, n2) = if cos_i > 0.0 { (1.0, eta) } else { (eta, 1.0) };
    let ti = cos_i.abs().min(1.0).acos();
    let st = n1 / n2 * ti.sin();
    if st >= 1.0 {
        return 1.0;
    }
    if ti < 1e-6 {
        let r = (n1 - n2) / (n1 + n2);
        return r * r;
    }
    let tt = st.asin();
    let rs = ((ti - tt).sin() / (ti + tt).sin()).powi(2);
    let rp = ((ti - tt).tan() / (ti + tt).tan()).powi(2);
    0.5 * (rs + rp)
}

/// Schlick's approximation: NOT exact (used only to show the Fresnel check rejects it).
fn fresnel_schlick(cos_i: f64, eta: f64) -> f64 {
    let r0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
    r0 + (1.0 - r0) * (1.0 - cos_i.abs()).powi(5)
}

/// The refracted direction by the vector form of Snell's law (Heckbert and Hanrahan),
/// for `wo` leaving the surface on either side of the +z normal; `None` on total
/// internal reflection. Returns it with η_t/η_i.
fn snell(wo: Vec3, eta: f64) -> Option<(glam::DVec3, f64)> {
    let wo = wo.as_dvec3();
    let (n, e) = if wo.z > 0.0 {
        (glam::DVec3::Z, eta)
    } else {
        (-glam::DVec3::Z, 1.0 / eta)
    };
    // Light travels along -wi into the surface and leaves along wo; trace the camera
    // direction -wo through the boundary: t = -wo / e + (cos_i / e - cos_t) n.
    let cos_i = wo.dot(n);
    let k = 1.0 - (1.0 - cos_i * cos_i) / (e * e);
    if k < 0.0 {
        return None;
    }
    Some((-wo / e + (cos_i / e - k.sqrt()) * n, e))
}

/// The modified Phong lobe as Lafortune and Willems define it, written here from the
/// paper: f = ks (n+2)/(2π) cos^n α, sampled with density (n+1)/(2π) cos^n α (the
/// normalised cos^n lobe around the mirror direction), both zero below the horizon.
fn phong_reference(ks: f64, n: f64, wo: Vec3, wi: Vec3) -> (f64, f64) {
    if wo.z * wi.z <= 0.0 {
        return (0.0, 0.0);
    }
    let r = glam::DVec3::new(-wo.x as f64, -wo.y as f64, wo.z as f64);
    let c = r.dot(wi.as_dvec3()).max(0.0).powf(n);
    (ks * (n + 2.0) / (2.0 * PI) * c, (n + 1.0) / (2.0 * PI) * c)
}

fn wos() -> [Vec3; 5] {
    [
        Vec3::Z,
        Vec3::new(0.5, 0.2, 0.6).normalize(),
        Vec3::new(0.99, 0.0, 0.05).normalize(),
        Vec3::new(0.3, 0.3, -0.8).normalize(),
        -Vec3::Z,
    ]
}

fn lambert(a: Rgb) -> Lobe {
    Lobe::Lambert { albedo: a }
}

fn phong(ks: f32, exponent: f32) -> Lobe {
    Lobe::Phong {
        ks: Rgb::splat(ks),
        exponent,
    }
}

/// Every smooth lobe and mixture (with and without delta lobes), and the delta part of
/// its albedo at `wo` from closed forms (the mirror's r; the dielectric's
/// F + (1 − F) tint / η², F by the independent Fresnel formula above), each times the
/// share the mixture gives that lobe (its coefficients already carry it).
#[allow(clippy::type_complexity)]
fn consistency_cases() -> Vec<(&'static str, Bsdf, Box<dyn Fn(Vec3) -> [f64; 3]>)> {
    let none = || Box::new(|_: Vec3| [0.0; 3]) as Box<dyn Fn(Vec3) -> [f64; 3]>;
    let glass = |eta: f64, tint: [f64; 3], weight: f64| {
        Box::new(move |wo: Vec3| {
            let f = fresnel_exact(wo.z as f64, eta);
            let e = if wo.z > 0.0 { eta } else { 1.0 / eta };
            tint.map(|t| weight * (f + (1.0 - f) * t / (e * e)))
        }) as Box<dyn Fn(Vec3) -> [f64; 3]>
    };
    vec![
        (
            "lambert",
            Bsdf::new().with(lambert(Rgb::new(0.8, 0.5, 0.2))),
            none(),
        ),
        ("phong n=1", Bsdf::new().with(phong(0.9, 1.0)), none()),
        ("phong n=20", Bsdf::new().with(phong(0.9, 20.0)), none()),
        ("phong n=150", Bsdf::new().with(phong(1.0, 150.0)), none()),
        (
            "lambert+phong",
            Bsdf::new()
                .with(lambert(Rgb::new(0.5, 0.3, 0.2)))
                .with(phong(0.3, 8.0)),
            none(),
        ),
        (
            "lambert+mirror",
            Bsdf::new()
                .with(lambert(Rgb::splat(0.4)))
                .with(Lobe::Mirror {
                    r: Rgb::new(0.5, 0.3, 0.1),
                }),
            Box::new(|_| [0.5, 0.3, 0.1]),
        ),
        (
            "lambert+phong+mirror",
            Bsdf::new()
                .with(lambert(Rgb::splat(0.3)))
                .with(phong(0.3, 30.0))
                .with(Lobe::Mirror { r: Rgb::splat(0.3) }),
            Box::new(|_| [0.3; 3]),
        ),
        (
            "lambert+dielectric",
            Bsdf::new()
                .with(lambert(Rgb::splat(0.3)))
                .with(Lobe::Dielectric {
                    eta: 1.5,
                    tint: Rgb::new(1.0, 0.8, 0.5),
                    weight: 0.7,
                }),
            glass(1.5, [1.0, 0.8, 0.5], 0.7),
        ),
        (
            "phong+dielectric",
            Bsdf::new().with(phong(0.4, 40.0)).with(Lobe::Dielectric {
                eta: 1.33,
                tint: Rgb::WHITE,
                weight: 0.6,
            }),
            glass(1.33, [1.0; 3], 0.6),
        ),
    ]
}

#[test]
fn sampled_weight_pdf_and_eval_agree_for_every_lobe_and_mixture() {
    let cases = consistency_cases();
    let alpha = 0.01 / (cases.len() * wos().len()) as f64;
    let mut failures = Vec::new();
    for (k, (name, bsdf, delta)) in cases.iter().enumerate() {
        let m = Model::of(bsdf);
        for (j, wo) in wos().into_iter().enumerate() {
            let seed = (100 + 10 * k + j) as u64;
            for e in check_consistency(&m, wo, delta(wo), 60_000, seed, alpha) {
                failures.push(format!("{name} at wo {wo}: {e}"));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn lambert_and_phong_match_their_closed_forms() {
    // Lambert: f = ρ/π, pdf = |cos|/π: ∫ pdf = 1 and albedo ρ at every wo.
    let rho = Rgb::new(0.8, 0.5, 0.2);
    let l = Bsdf::new().with(lambert(rho));
    for wo in wos() {
        let (p, a) = integrals(&Model::of(&l), wo);
        assert!((p - 1.0).abs() < 1e-5, "lambert ∫pdf {p} at {wo}");
        for (c, want) in rho.to_array().into_iter().enumerate() {
            assert!(
                (a[c] - want as f64).abs() < 1e-5,
                "lambert albedo {} ≠ {want} at {wo}",
                a[c]
            );
        }
    }
    // Phong: eval and pdf are Lafortune's formulas at every quadrature node; at normal
    // incidence the lobe lies wholly above the horizon, where the normalisations
    // (n+2)/(2π) and (n+1)/(2π) make ∫ f cos = ks and ∫ pdf = 1 exactly; elsewhere the
    // horizon clips it: ks cos θo ≤ albedo ≤ ks (the cap's ∫ f cos θi is ks cos θo and
    // the clipped part only adds to it).
    for (ks, n) in [(0.9f32, 1.0f32), (0.7, 10.0), (1.0, 150.0)] {
        let b = Bsdf::new().with(phong(ks, n));
        for wo in wos() {
            let mut worst: f64 = 0.0;
            sphere_quadrature(|wi, _| {
                let (f, p) = phong_reference(ks as f64, n as f64, wo, wi);
                let (bf, bp) = (b.eval(wo, wi).g as f64, b.pdf(wo, wi) as f64);
                worst = worst
                    .max((bf - f).abs() / f.max(1e-3))
                    .max((bp - p).abs() / p.max(1e-3));
            });
            assert!(
                worst < 1e-4,
                "phong {ks} n={n} at {wo}: off the formula by {worst}"
            );
            let (p, a) = integrals(&Model::of(&b), wo);
            let cos_o = wo.z.abs() as f64;
            if cos_o == 1.0 {
                assert!((p - 1.0).abs() < 1e-4, "phong n={n}: ∫pdf {p}");
                assert!(
                    (a[1] - ks as f64).abs() < 1e-4,
                    "phong n={n}: albedo {}",
                    a[1]
                );
            } else {
                assert!(p < 1.0 + 1e-5, "phong n={n} at {wo}: ∫pdf {p}");
                let lo = ks as f64 * cos_o - 1e-4;
                assert!(
                    a[1] >= lo && a[1] <= ks as f64 + 1e-4,
                    "phong {ks} n={n} at {wo}: albedo {} outside [{lo}, {ks}]",
                    a[1]
                );
            }
        }
    }
}

/// The checks above can fail: each broken BSDF is rejected, for the reason built in.
#[test]
fn consistency_checks_reject_broken_lobes() {
    let wo = Vec3::new(0.5, 0.2, 0.6).normalize();
    let b = Bsdf::new().with(phong(0.9, 20.0));
    let has = |errors: &[String], what: &str| errors.iter().any(|e| e.starts_with(what));
    let run = |m: &Model| check_consistency(m, wo, [0.0; 3], 100_000, 9, 1e-4);
    assert!(run(&Model::of(&b)).is_empty(), "{:?}", run(&Model::of(&b)));

    // Sampled weights 2% too large: the identity and the albedo both fail.
    let mut m = Model::of(&b);
    m.sample = Box::new(|wo, ul, u| {
        b.sample(wo, ul, u).map(|mut s| {
            s.weight *= 1.02;
            s
        })
    });
    let e = run(&m);
    assert!(has(&e, "weight") && has(&e, "albedo"), "{e:?}");

    // A density 5% too high everywhere (pdf() and the samples agree on it, and the
    // weight is eval·cos over it): ∫pdf is 1.05× the mass sampled, and the mean weight
    // falls 5% below ∫ f cos.
    let mut m = Model::of(&b);
    m.pdf = Box::new(|wo, wi| 1.05 * b.pdf(wo, wi));
    m.sample = Box::new(|wo, ul, u| {
        b.sample(wo, ul, u).map(|mut s| {
            s.pdf *= 1.05;
            s.weight /= 1.05;
            s
        })
    });
    let e = run(&m);
    assert!(has(&e, "pdf integral") && has(&e, "albedo"), "{e:?}");

    // Phong sampled with exponent 16 while eval and pdf describe exponent 20 (weights
    // from the claimed pdf): only the histogram and the mean weight can tell.
    let other = Bsdf::new().with(phong(0.9, 16.0));
    let mut m = Model::of(&b);
    m.sample = Box::new(|wo, ul, u| {
        let s = other.sample(wo, ul, u)?;
        let pdf = b.pdf(wo, s.wi);
        (pdf > 0.0).then(|| BsdfSample {
            weight: b.eval(wo, s.wi) * (s.wi.z.abs() / pdf),
            pdf,
            ..s
        })
    });
    let e = run(&m);
    assert!(has(&e, "chi-square") && has(&e, "albedo"), "{e:?}");

    // A 2% energy gain in eval (sample and pdf consistent with it) passes the
    // consistency checks, but not the closed-form normalisation at normal incidence.
    let mut m = Model::of(&b);
    m.eval = Box::new(|wo, wi| b.eval(wo, wi) * 1.02);
    let (_, a) = integrals(&m, Vec3::Z);
    assert!((a[1] - 0.9).abs() > 1e-2, "{}", a[1]);
}

#[test]
fn delta_lobes_match_fresnel_and_snell_closed_forms() {
    // The independent Fresnel formula against textbook values: normal incidence
    // ((n−1)/(n+1))², Brewster's angle R_p = 0, total internal reflection.
    assert!((fresnel_exact(1.0, 1.5) - 0.04).abs() < 1e-12);
    let brewster = 1.5f64.atan();
    let (ti, tt) = (brewster, (brewster.sin() / 1.5).asin());
    assert!(((ti - tt).tan() / (ti + tt).tan()).abs() < 1e-12);
    assert_eq!(fresnel_exact(-0.5, 1.5), 1.0);

    let mut rng = Rng::new(21, 4);
    for eta in [1.33f32, 1.5, 2.4] {
        for k in 0..=40 {
            // Both sides, from normal to nearly grazing incidence.
            let c = 1.0 - k as f32 / 40.0 * 0.995;
            for cos in [c, -c] {
                let phi = rng.next_f32() * std::f32::consts::TAU;
                let s = (1.0 - cos * cos).sqrt();
                let wo = Vec3::new(s * phi.cos(), s * phi.sin(), cos);
                let f = fresnel_exact(wo.z as f64, eta as f64);
                let lib = fresnel_dielectric(wo.z, eta) as f64;
                assert!(
                    (lib - f).abs() < 2e-5,
                    "η {eta}, cos {cos}: fresnel_dielectric {lib}, exact {f}"
                );
                let tint = Rgb::new(0.9, 0.6, 0.3);
                let weight = 0.8;
                let lobe = Lobe::Dielectric { eta, tint, weight };
                let e = if wo.z > 0.0 {
                    eta as f64
                } else {
                    1.0 / eta as f64
                };
                // Just below F: reflection with probability F and weight `weight`
                // (F·weight/F), in the mirror direction.
                if f > 1e-3 {
                    let r = lobe.sample(wo, Vec2::new((f - 5e-4) as f32, 0.5)).unwrap();
                    assert!(
                        r.is_delta() && (r.pdf as f64 - f).abs() < 2e-5,
                        "{r:?} F {f}"
                    );
                    assert!((r.wi - Vec3::new(-wo.x, -wo.y, wo.z)).length() < 1e-5);
                    assert!((r.weight.g - weight).abs() < 1e-5);
                }
                // Just above F: refraction by Snell's law with probability 1 − F and
                // weight tint·weight/η² (radiance compressed by the relative index).
                match snell(wo, eta as f64) {
                    Some((t, e_rel)) => {
                        assert!((e_rel - e).abs() < 1e-6);
                        let r = lobe.sample(wo, Vec2::new((f + 5e-4) as f32, 0.5)).unwrap();
                        assert!(r.is_delta() && (r.pdf as f64 - (1.0 - f)).abs() < 2e-5);
                        assert!(
                            (r.wi.as_dvec3() - t).length() < 2e-5,
                            "η {eta} cos {cos}: refracted {}, Snell {t}",
                            r.wi
                        );
                        // Snell as angles too: sin θt = sin θi / e, opposite side.
                        assert!(r.wi.z * wo.z < 0.0);
                        let sin_t = (1.0 - (r.wi.z as f64).powi(2)).max(0.0).sqrt();
                        assert!((sin_t - s as f64 / e).abs() < 1e-4);
                        for (got, t) in r.weight.to_array().iter().zip(tint.to_array()) {
                            let want = (t * weight) as f64 / (e * e);
                            assert!((*got as f64 - want).abs() < 1e-5 * want.max(1.0));
                        }
                    }
                    None => {
                        assert_eq!(f, 1.0);
                        let r = lobe.sample(wo, Vec2::new(0.9999, 0.5)).unwrap();
                        assert!(r.wi.z * wo.z > 0.0 && (r.pdf - 1.0).abs() < 1e-6);
                    }
                }
                // The mirror: direction and weight r, probability 1; no smooth part.
                let r = Lobe::Mirror { r: tint }.sample(wo, rng.next_2d()).unwrap();
                assert!(r.is_delta() && r.pdf == 1.0 && r.weight == tint);
                assert!((r.wi - Vec3::new(-wo.x, -wo.y, wo.z)).length() < 1e-6);
                for l in [lobe, Lobe::Mirror { r: tint }] {
                    let w = rng.next_2d();
                    let wi = dir(w.x as f64 * 2.0 - 1.0, w.y as f64 * 2.0 * PI);
                    assert!(l.eval(wo, wi).is_black() && l.pdf(wo, wi) == 0.0);
                }
            }
        }
    }
    // Schlick's approximation is not the exact formula: the tolerance above rejects it.
    let worst = (0..=100)
        .map(|k| {
            let c = 1.0 - k as f64 / 100.0 * 0.99;
            (fresnel_schlick(c, 1.5) - fresnel_exact(c, 1.5)).abs()
        })
        .fold(0.0, f64::max);
    assert!(worst > 1e-3, "Schlick within {worst}");
}
