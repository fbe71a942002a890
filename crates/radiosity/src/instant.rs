//! Instant radiosity (Keller 1997, "Instant radiosity"; lecture, "Instant Radiosity":
//! many point sources stand in for the light bouncing around the scene).
//!
//! Quasi-random walks (Halton sequence) leave the lights: each walk starts at a point
//! on an emitter carrying the power `Φ = Σ E A / N` and places a virtual point light
//! (VPL) there; it then bounces in a cosine-distributed direction, and at each hit a new
//! VPL takes the power times the reflectance, continuing with probability equal to the
//! mean reflectance (the weight is divided by it, so the estimate stays unbiased).
//! Each VPL lights a point `x` with irradiance `Φ cos θ_y cos θ_x V / (π r²)` (a cosine
//! emitter), shadows by a ray through the BVH.
//!
//! Clamping: the geometric term `cos θ_y cos θ_x / r²` is singular where a VPL sits
//! next to the receiver, which shows as bright splotches in corners. It is clamped to
//! `clamp / A_mean` (A_mean = scene area / element count), trading those spikes for a
//! bias (energy lost in corners). `InstantResult` reports the fraction of contributions
//! clamped and the energy they lost, so the bias is measured, not guessed.

use crate::mesh::Mesh;
use crate::visibility::{ElementTracer, Visibility};
use glam::DVec3;
use irradia_core::sampling::radical_inverse;
use std::f64::consts::PI;

/// Parameters of instant radiosity.
#[derive(Clone, Copy, Debug)]
pub struct InstantOptions {
    /// Walks started from the lights.
    pub paths: usize,
    /// Clamp of the geometric term, in units of 1 / (mean element area); `None` for no
    /// clamp.
    pub clamp: Option<f64>,
    pub max_bounces: usize,
}

impl Default for InstantOptions {
    fn default() -> Self {
        Self {
            paths: 256,
            clamp: Some(1.0),
            max_bounces: 16,
        }
    }
}

/// A virtual point light.
#[derive(Clone, Copy, Debug)]
pub struct Vpl {
    pub position: DVec3,
    pub normal: DVec3,
    pub power: [f64; 3],
}

pub struct InstantResult {
    /// Radiosity at each element's centroid.
    pub b: Vec<[f64; 3]>,
    pub vpls: Vec<Vpl>,
    /// Fraction of (VPL, receiver) contributions whose geometric term was clamped.
    pub clamped_fraction: f64,
    /// Energy removed by the clamp over the energy received (relative bias).
    pub clamped_energy: f64,
}

/// Halton dimensions for the first 24 dimensions; beyond them (deep bounces) a PCG
/// stream per walk. Reusing a prime would repeat earlier decisions of the same walk
/// (a walk that survived once would survive for ever).
fn halton(i: u64, dim: usize) -> f64 {
    const PRIMES: [u64; 24] = [
        2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53, 59, 61, 67, 71, 73, 79, 83, 89,
    ];
    if dim < PRIMES.len() {
        radical_inverse(i, PRIMES[dim])
    } else {
        irradia_core::Rng::new(irradia_core::sampling::hash64(i), dim as u64).next_f64()
    }
}

/// Traces the VPLs of `opts.paths` quasi-random walks.
pub fn trace_vpls(mesh: &Mesh, opts: &InstantOptions) -> Vec<Vpl> {
    let tracer = ElementTracer::new(mesh);
    let emitters: Vec<usize> = (0..mesh.len())
        .filter(|&i| mesh.emission(i).iter().any(|&e| e > 0.0))
        .collect();
    let powers: Vec<f64> = emitters
        .iter()
        .map(|&i| mesh.elements[i].area * mesh.emission(i).iter().sum::<f64>() / 3.0)
        .collect();
    let total: f64 = powers.iter().sum();
    let mut vpls = Vec::new();
    if total <= 0.0 || opts.paths == 0 {
        return vpls;
    }
    let n = opts.paths as u64;
    for k in 0..n {
        let i = k + 1;
        // Choose an emitter element by power, then a point on it.
        let mut u = halton(i, 0) * total;
        let mut idx = emitters.len() - 1;
        for (e, p) in powers.iter().enumerate() {
            if u < *p {
                idx = e;
                break;
            }
            u -= p;
        }
        let ei = emitters[idx];
        let el = &mesh.elements[ei];
        let pick = powers[idx] / total;
        let x = el.poly.sample(halton(i, 1), halton(i, 2));
        let e = mesh.emission(ei);
        // Φ = E A / (N · pick probability)
        let mut power: [f64; 3] = std::array::from_fn(|c| e[c] * el.area / (n as f64 * pick));
        let (mut pos, mut normal) = (x, el.normal);
        vpls.push(Vpl {
            position: pos,
            normal,
            power,
        });
        for bounce in 0..opts.max_bounces {
            let d = 3 + 3 * bounce;
            let (u1, u2) = (halton(i, d), halton(i, d + 1));
            let r = u1.sqrt();
            let phi = 2.0 * PI * u2;
            let s = if normal.x.abs() > 0.9 {
                DVec3::Y
            } else {
                DVec3::X
            }
            .cross(normal)
            .normalize();
            let t = normal.cross(s);
            let dir =
                s * (r * phi.cos()) + t * (r * phi.sin()) + normal * (1.0 - u1).max(0.0).sqrt();
            let Some((j, hit)) = tracer.nearest_hit(pos, normal, dir) else {
                break;
            };
            let ej = &mesh.elements[j];
            if ej.normal.dot(dir) >= 0.0 {
                break; // hit a back face: the walk left through an open side
            }
            let rho = mesh.reflectance(j);
            let p_continue = ((rho[0] + rho[1] + rho[2]) / 3.0).clamp(0.0, 1.0);
            if halton(i, d + 2) >= p_continue || p_continue == 0.0 {
                break;
            }
            power = std::array::from_fn(|c| power[c] * rho[c] / p_continue);
            pos = hit;
            normal = ej.normal;
            vpls.push(Vpl {
                position: pos,
                normal,
                power,
            });
        }
    }
    vpls
}

/// Radiosity at the element centroids from the VPLs (emission added).
pub fn solve(mesh: &Mesh, opts: &InstantOptions) -> InstantResult {
    use rayon::prelude::*;
    let vpls = trace_vpls(mesh, opts);
    let vis = Visibility::new(mesh);
    let mean_area = mesh.total_area() / mesh.len().max(1) as f64;
    let gmax = opts.clamp.map(|c| c / mean_area).unwrap_or(f64::INFINITY);
    let per: Vec<([f64; 3], usize, usize, f64, f64)> = (0..mesh.len())
        .into_par_iter()
        .map(|i| {
            let e = &mesh.elements[i];
            let rho = mesh.reflectance(i);
            let mut irr = [0.0; 3];
            let (mut clamped, mut count, mut lost, mut got) = (0usize, 0usize, 0.0, 0.0);
            for v in &vpls {
                let d = v.position - e.centroid;
                let r2 = d.length_squared();
                if r2 <= 0.0 {
                    continue;
                }
                let r = r2.sqrt();
                let cx = e.normal.dot(d) / r;
                let cy = -v.normal.dot(d) / r;
                if cx <= 0.0 || cy <= 0.0 {
                    continue;
                }
                if !vis.visible(e.centroid, e.normal, v.position, v.normal) {
                    continue;
                }
                let g = cx * cy / r2;
                count += 1;
                let gc = if g > gmax {
                    clamped += 1;
                    gmax
                } else {
                    g
                };
                let pw = (v.power[0] + v.power[1] + v.power[2]) / 3.0;
                lost += (g - gc) * pw;
                got += g * pw;
                for (e, p) in irr.iter_mut().zip(v.power) {
                    *e += p * gc / PI;
                }
            }
            let em = mesh.emission(i);
            (
                std::array::from_fn(|c| em[c] + rho[c] * irr[c]),
                clamped,
                count,
                lost,
                got,
            )
        })
        .collect();
    let clamped: usize = per.iter().map(|p| p.1).sum();
    let count: usize = per.iter().map(|p| p.2).sum();
    let lost: f64 = per.iter().map(|p| p.3).sum();
    let got: f64 = per.iter().map(|p| p.4).sum();
    InstantResult {
        b: per.into_iter().map(|p| p.0).collect(),
        vpls,
        clamped_fraction: if count > 0 {
            clamped as f64 / count as f64
        } else {
            0.0
        },
        clamped_energy: if got > 0.0 { lost / got } else { 0.0 },
    }
}
