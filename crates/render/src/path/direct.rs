//! Direct illumination, as Mitsuba 3's `direct` integrator plugin: at the first surface
//! a camera ray hits, `emitter_samples` samples of the lights (next-event estimation)
//! and `bsdf_samples` samples of the BSDF, each BSDF direction counted only when it
//! reaches an emitter, combined by multiple importance sampling with the power
//! heuristic (Veach and Guibas 1995, "Optimally combining sampling techniques for Monte
//! Carlo rendering"). Emitters seen directly from the camera add their radiance.
//!
//! As in Mitsuba, the techniques are weighted by their sample counts: a light sample
//! of density `p_e` weighs `w(p_e n_e / n, p_b n_b / n) / n_e` and a BSDF sample of
//! density `p_b` weighs `w(p_b n_b / n, p_e n_e / n) / n_b` (`n = n_e + n_b`, `w(a, b) =
//! a² / (a² + b²)`); delta lights and delta BSDF lobes weigh `1 / n_e` and `1 / n_b`.
//! The expected value is the path tracer's at `max_depth = 2`.

use super::integrator::{emission_at, mis, surface_at, PathCounters, PathScene};
use super::tracer::Tracer;
use irradia_core::{offset_ray_origin, Ray, Rgb, Rng};
use irradia_scatter::Scatter;

/// Mitsuba's `emitter_samples` and `bsdf_samples` (its `shading_samples` sets both).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DirectParams {
    pub emitter_samples: u32,
    pub bsdf_samples: u32,
}

impl Default for DirectParams {
    fn default() -> Self {
        Self {
            emitter_samples: 1,
            bsdf_samples: 1,
        }
    }
}

/// One sample of the direct radiance arriving along the camera ray `ray`.
pub fn radiance_direct<T: Tracer>(
    ps: &PathScene<'_, T>,
    params: &DirectParams,
    ray: Ray,
    rng: &mut Rng,
    counters: &mut PathCounters,
) -> Rgb {
    let (scene, tracer, lights) = (ps.scene, &ps.tracer, ps.lights);
    counters.paths += 1;
    counters.rays += 1;
    let Some(sh) = tracer.intersect(&ray, f32::INFINITY) else {
        return if lights.has_environment() {
            lights.environment_radiance(ray.dir)
        } else {
            Rgb::BLACK
        };
    };
    let hit = sh.hit;
    let material = &scene.materials[sh.material as usize];
    let n = hit.normal;
    let wo_world = -ray.dir.normalize();
    let mut l = Rgb::BLACK;
    if !material.emission.is_black() && (material.emission_two_sided || n.dot(wo_world) > 0.0) {
        l += emission_at(scene, material, &sh);
    }
    let Some((bsdf, frame)) = surface_at(ps, &sh) else {
        return l;
    };
    let wo = frame.to_local(wo_world);
    let (ne, nb) = (params.emitter_samples, params.bsdf_samples);
    let total = (ne + nb) as f32;
    let (frac_e, frac_b) = (ne as f32 / total, nb as f32 / total);

    if bsdf.flags().has_smooth() {
        for _ in 0..ne {
            let Some(ls) = lights.sample(scene, hit.point, rng.next_f32(), rng.next_2d()) else {
                continue;
            };
            let wi = frame.to_local(ls.wi);
            let f = bsdf.eval(wo, wi);
            if f.is_black() || ls.wi.dot(n) * wi.z <= 0.0 {
                continue;
            }
            let side = if ls.wi.dot(n) > 0.0 { n } else { -n };
            let origin = offset_ray_origin(hit.point, side, hit.error);
            counters.shadow_rays += 1;
            let (shadow, t_max) = match ls.target {
                Some(t) => (Ray::new(origin, t - origin), 1.0),
                None => (Ray::new(origin, ls.wi), f32::INFINITY),
            };
            if tracer.occluded(&shadow, t_max) {
                continue;
            }
            let w = if ls.delta {
                1.0
            } else {
                mis(ls.pdf * frac_e, bsdf.pdf(wo, wi) * frac_b)
            } / ne as f32;
            l += f * ls.li * (wi.z.abs() * w / ls.pdf);
        }
    } else {
        // Keep the random stream the same length whatever the material.
        for _ in 0..ne {
            rng.next_f32();
            rng.next_2d();
        }
    }

    for _ in 0..nb {
        let Some(s) = bsdf.sample(wo, rng.next_f32(), rng.next_2d()) else {
            continue;
        };
        let wi_world = frame.to_world(s.wi);
        if wi_world.dot(n) * s.wi.z <= 0.0 {
            continue;
        }
        let side = if wi_world.dot(n) > 0.0 { n } else { -n };
        let next = Ray::new(offset_ray_origin(hit.point, side, hit.error), wi_world);
        counters.rays += 1;
        let (le, pdf_e) = match tracer.intersect(&next, f32::INFINITY) {
            None if lights.has_environment() => lights.environment_radiance_pdf(wi_world, true),
            None => continue,
            Some(eh) => {
                let m = &scene.materials[eh.material as usize];
                let (q, nq) = (eh.hit.point, eh.hit.normal);
                if m.emission.is_black() || !(m.emission_two_sided || nq.dot(-wi_world) > 0.0) {
                    continue;
                }
                let pdf = lights.pdf_object(scene, eh.instance, hit.point, q, nq);
                (emission_at(scene, m, &eh), pdf)
            }
        };
        if le.is_black() {
            continue;
        }
        let w = if s.is_delta() {
            1.0
        } else {
            mis(s.pdf * frac_b, pdf_e * frac_e)
        } / nb as f32;
        l += s.weight * le * w;
    }
    l
}
