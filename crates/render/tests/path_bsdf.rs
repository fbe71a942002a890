//! Statistical tests of the path tracer's BSDFs: every lobe's sampling against its own
//! density (Pearson's chi-square, as Mitsuba and PBRT test theirs), energy
//! conservation over incident directions, and the dielectric's Fresnel split.

use glam::{Vec2, Vec3};
use irradia_core::{Rgb, Rng};
use irradia_render::path::bsdf::{fresnel_dielectric, Bsdf, Lobe};
use std::f64::consts::PI;

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

/// Expected probability of each (cos θ, φ) bin: the density integrated by composite
/// 5-point Gauss-Legendre quadrature (the measure d(cos θ) dφ is the solid angle).
fn expected(pdf: impl Fn(Vec3) -> f64) -> Vec<f64> {
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

/// Regularised upper incomplete gamma Q(a, x) (series for x < a + 1, continued
/// fraction otherwise), for the chi-square p-value.
fn gamma_q(a: f64, x: f64) -> f64 {
    let ln_gamma_a = ln_gamma(a);
    if x < a + 1.0 {
        let (mut sum, mut term, mut n) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            n += 1.0;
            term *= x / n;
            sum += term;
            if term.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        1.0 - sum * (-x + a * x.ln() - ln_gamma_a).exp()
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-15 {
                break;
            }
        }
        (-x + a * x.ln() - ln_gamma_a).exp() * h
    }
}

/// Lanczos approximation of ln Γ(x).
fn ln_gamma(x: f64) -> f64 {
    let g = [
        76.180_091_729_471_46,
        -86.505_320_329_416_77,
        24.014_098_240_830_91,
        -1.231_739_572_450_155,
        0.120_865_097_386_617_9e-2,
        -0.539_523_938_495_3e-5,
    ];
    let mut y = x;
    let tmp = x + 5.5;
    let tmp = tmp - (x + 0.5) * tmp.ln();
    let mut ser = 1.000_000_000_190_015;
    for c in g {
        y += 1.0;
        ser += c / y;
    }
    -tmp + (2.506_628_274_631_000_5 * ser / x).ln()
}

/// Pearson's test of `n` samples of `bsdf` at `wo` against its `pdf`; returns the
/// p-value. Bins expecting fewer than 5 samples are pooled.
fn chi_square(bsdf: &Bsdf, wo: Vec3, n: usize, seed: u64) -> f64 {
    let exp = expected(|wi| bsdf.pdf(wo, wi) as f64);
    let mut obs = vec![0.0f64; exp.len()];
    let mut rng = Rng::new(seed, 11);
    let mut missing = 0.0;
    for _ in 0..n {
        match bsdf.sample(wo, rng.next_f32(), rng.next_2d()) {
            Some(s) => {
                assert!(
                    (s.wi.length() - 1.0).abs() < 1e-3,
                    "sampled direction not unit: {}",
                    s.wi
                );
                assert!(
                    (s.pdf - bsdf.pdf(wo, s.wi)).abs() <= 1e-3 * s.pdf.max(1.0),
                    "sample pdf disagrees with pdf()"
                );
                obs[bin_of(s.wi)] += 1.0;
            }
            None => missing += 1.0,
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
            let p = chi_square(&bsdf, *wo, 200_000, (seed * 10 + k) as u64);
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
        let f = fresnel_dielectric(cos, eta);
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
