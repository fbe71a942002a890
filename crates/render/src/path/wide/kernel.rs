//! The bounce loop of the wide path kernel (see [`super`] for the stages and the
//! sources). A lane holds one path; when it ends, its estimate is written to the
//! output slot of its sample and the lane takes the next sample of the batch, so the
//! vector stays full until the batch runs out (Laine, Karras, Aila 2013:
//! regenerating paths in place of finished ones).
//!
//! The per-lane stages call exactly the scalar estimator's code (the random stream,
//! the light choice when the vector stage does not make it, the flat scene's queries
//! for large scenes); the vector stage repeats the scalar arithmetic of
//! [`radiance_in`](crate::path::integrator::radiance_in) lane by lane and in the same
//! order, with masks where the scalar code branches.

// Lane loops index several arrays by the lane on purpose.
#![allow(clippy::needless_range_loop)]

use super::background::Background;
use super::bsdf::{conductor_fresnel, cosine_hemisphere, dielectric};
use super::gather::{checked, field, field3, Table};
use super::glossy::glossy;
use super::lane_queries::{nearest_in_turns, occluded_in_turns, KnownHits};
use super::light_pick::{at_infinity, far_lights, pick_lights};
use super::sphere_cull;
use super::sphere_hits::SphereHits;
use super::sphere_light::{self, LightPoint};
use super::starts::{Ahead, Starts};
use super::{facet, mat, smooth, tri, WideScene};
use crate::path::integrator::{PathCounters, PathParams};
use crate::path::lights::KernelLight;
use crate::path::tracer::Tracer;
use glam::Vec3;
use irradia_core::{Rgb, Rng};
use irradia_geometry::bvh::node::gamma;
use irradia_geometry::packet::lanes::{offset_ray_origin, Fw, Mw, V3, W};
use irradia_geometry::triangle::TriangleHit;
use std::f32::consts::FRAC_1_PI;

/// No sample in the lane.
const IDLE: usize = usize::MAX;

/// The paths in flight, one per lane.
struct Paths {
    sample: [usize; W],
    rng: [Rng; W],
    depth: [u32; W],
    origin: V3,
    dir: V3,
    beta: V3,
    radiance: V3,
    /// The previous scattering vertex and its BSDF density (MIS on emitter hits);
    /// `has_prev` is false for camera rays.
    prev_p: V3,
    prev_pdf: Fw,
    has_prev: Mw,
    /// The product of the relative indices of refraction crossed (Russian roulette
    /// judges `max(beta) eta²`, as the scalar estimator does).
    eta: Fw,
}

/// What the per-lane stage hands to the vector stage, per bounce: indices into the
/// scene's tables and the lanes' random numbers.
#[derive(Default)]
struct Bounce {
    /// Lanes that hit a surface.
    hit: Mw,
    /// Lanes that go on scattering at this hit (random numbers drawn).
    scatter: Mw,
    /// The triangle hit, its barycentrics `b1`, `b2` and its material.
    triangle: [u32; W],
    b1: Fw,
    b2: Fw,
    material: [u32; W],
    /// Lanes whose hit is on an object left to its own shape's test (a sphere), with
    /// the hit as that test reports it: point, geometric and shading normals, error
    /// bound (`triangle` is then 0, a valid index whose record is not used).
    other: Mw,
    point: V3,
    normal: V3,
    shading: V3,
    error: Fw,
    /// `pdf_object` of the hit as seen from the previous vertex (emissive hits).
    light_pdf: Fw,
    /// Uniform numbers of the BSDF sample: the lobe choice (the dielectric's
    /// reflection or refraction) and the direction.
    u_lobe: Fw,
    u_bsdf: [Fw; 2],
    /// The light sample: a facet was chosen (`light`), which one, the probability of
    /// choosing its emitter and the point of the square to warp into the triangle.
    light: Mw,
    facet: [u32; W],
    /// The chosen emitter (a sphere warps `u_light` itself: [`sphere_light`]).
    emitter: [u32; W],
    pick: Fw,
    /// The numbers as drawn (a sphere's), and the point of the square to warp into
    /// the chosen facet (the facet choice's).
    u_light: [Fw; 2],
    u_facet: [Fw; 2],
    /// The number that chooses the emitter (when the vector stage chooses).
    u_pick: Fw,
    /// Escaped rays and light samples of emitters at infinity.
    bg: Background,
}

/// What the vector stage hands back to the per-lane stage.
struct Scattered {
    /// Lanes whose light sample passed every test but the shadow ray, with the
    /// shadow ray (`t_max = 1`) and the contribution if it is unblocked.
    nee: Mw,
    shadow_origin: V3,
    shadow_dir: V3,
    nee_value: V3,
    /// The shadow ray's `t_max`: 1 towards a point, infinite towards an emitter at
    /// infinity.
    shadow_t_max: Fw,
    /// Lanes that continue (a valid BSDF sample, throughput not black).
    go_on: Mw,
    /// Russian roulette: survival probability and the throughput divided by it.
    q: Fw,
    beta_rr: V3,
}

/// Power heuristic with β = 2, per lane (as `integrator::mis`).
#[inline(always)]
pub(super) fn mis(a: Fw, b: Fw) -> Fw {
    let (a2, b2) = (a * a, b * b);
    let s = a2 + b2;
    s.gt(0.0).keep(a2 / s)
}

/// `Frame::from_normal` (Duff et al. 2017) in every lane: the tangents `(s, t)`.
#[inline(always)]
pub(super) fn frame(n: V3) -> (V3, V3) {
    let sign = n.z.sign_one();
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let s = V3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let t = V3::new(b, sign + n.y * n.y * a, -n.y);
    (s, t)
}

/// The geometric and shading normals at the hits (`SmoothNormals::at` in every lane):
/// for a mesh triangle the blend of its vertex normals with barycentrics
/// `(b0, b1, b2)`, normalised as `normalize_or_zero` does; given normals turn the
/// geometric normal `n` to their side, then the shading normal is turned to the
/// geometric one's side. Flat faces, and blends that vanish, shade with `n`.
#[inline(always)]
fn smooth_normals(
    table: &Table<{ smooth::LEN }>,
    triangle: &[u32; W],
    (b0, b1, b2): (Fw, Fw, Fw),
    n: V3,
) -> (V3, V3) {
    checked(table, triangle);
    let (n0, n1, n2) = (
        field3(table, triangle, smooth::N0),
        field3(table, triangle, smooth::N1),
        field3(table, triangle, smooth::N2),
    );
    let is_smooth = field(table, triangle, smooth::SMOOTH).ne(0.0);
    let given = field(table, triangle, smooth::GIVEN).ne(0.0);
    let blend = n0.scale(b0).add(n1.scale(b1)).add(n2.scale(b2));
    let rcp = 1.0 / blend.dot(blend).sqrt();
    let interpolated = is_smooth & rcp.finite() & rcp.gt(0.0);
    let ns = blend.scale(rcp);
    let turn = interpolated & given & n.dot(ns).lt(0.0);
    let n = V3::select(turn, n.neg(), n);
    let ns = V3::select(n.dot(ns).lt(0.0), ns.neg(), ns);
    (n, V3::select(interpolated, ns, n))
}

/// `Frame::to_local` in every lane.
#[inline(always)]
fn to_local(v: V3, s: V3, t: V3, n: V3) -> V3 {
    V3::new(v.dot(s), v.dot(t), v.dot(n))
}

/// The vector stage: the hit point, emission, the light sample and the BSDF sample of
/// every lane.
#[inline(always)]
fn scatter(ws: &WideScene<'_, '_>, paths: &mut Paths, b: &Bounce) -> Scattered {
    // The hit: `TriangleHit::point_and_error` on the gathered corners.
    checked(&ws.triangles, &b.triangle);
    checked(&ws.shading, &b.material);
    let (light, facet_index, pick, u_light, emitter) =
        (b.light, b.facet, b.pick, b.u_facet, b.emitter);
    checked(&ws.facets, &facet_index);
    let t = &ws.triangles;
    let (p0, p1, p2) = (
        field3(t, &b.triangle, tri::P0),
        field3(t, &b.triangle, tri::P1),
        field3(t, &b.triangle, tri::P2),
    );
    let n = field3(t, &b.triangle, tri::N);
    let b0 = 1.0 - b.b1 - b.b2;
    // Mesh triangles: the interpolated shading normal (and the geometric normal turned
    // to given normals); flat faces shade with their geometric normal.
    let (n, ns) = match &ws.smooth {
        Some(table) => smooth_normals(table, &b.triangle, (b0, b.b1, b.b2), n),
        None => (n, n),
    };
    let (q0, q1, q2) = (p0.scale(b0), p1.scale(b.b1), p2.scale(b.b2));
    let p = q0.add(q1).add(q2);
    let abs_sum = q0.abs().add(q1.abs()).add(q2.abs());
    let error = gamma(7) * abs_sum.x.max(abs_sum.y.max(abs_sum.z));
    // Hits on objects with their own tests (spheres): the hit as the shape reports
    // it, the shading normal turned to the geometric one's side (`surface_at`).
    let (p, n, ns, error) = if ws.has_rest {
        let o = b.other;
        let turn = o & b.shading.dot(b.normal).lt(0.0);
        let other_ns = V3::select(turn, b.shading.neg(), b.shading);
        (
            V3::select(o, b.point, p),
            V3::select(o, b.normal, n),
            V3::select(o, other_ns, ns),
            o.select(b.error, error),
        )
    } else {
        (p, n, ns, error)
    };
    let albedo = field3(&ws.shading, &b.material, mat::ALBEDO);
    let mirror = field(&ws.shading, &b.material, mat::MIRROR).ne(0.0);
    let glass = field(&ws.shading, &b.material, mat::GLASS).ne(0.0);
    let rough = field(&ws.shading, &b.material, mat::ROUGH).ne(0.0);
    let lambert = !(mirror | glass | rough);
    let emission = field3(&ws.shading, &b.material, mat::EMISSION);
    let emission_two_sided = field(&ws.shading, &b.material, mat::TWO_SIDED).ne(0.0);
    let front_only = field(&ws.shading, &b.material, mat::FRONT_ONLY).ne(0.0);
    let f = &ws.facets;
    let (la, lb, lc, ln) = (
        field3(f, &facet_index, facet::A),
        field3(f, &facet_index, facet::B),
        field3(f, &facet_index, facet::C),
        field3(f, &facet_index, facet::N),
    );
    let lradiance = field3(f, &facet_index, facet::RADIANCE);
    let pdf_area = field(f, &facet_index, facet::PDF_AREA);
    let ltwo_sided = field(f, &facet_index, facet::TWO_SIDED).ne(0.0);

    // Emission, weighted against light sampling from the previous vertex.
    let wo_world = paths.dir.normalize().neg();

    let facing = n.dot(wo_world).gt(0.0);
    let lit = b.hit & !emission.is_zero() & (emission_two_sided | facing);
    let w = paths
        .has_prev
        .select(mis(paths.prev_pdf, b.light_pdf), Fw::splat(1.0));
    let emitted = paths.beta.mul(emission).scale(w);
    paths.radiance = V3::select(lit, paths.radiance.add(emitted), paths.radiance);
    // Rays that left the scene: the environment, weighted likewise.
    if ws.background {
        paths.radiance = b.bg.add_escaped(
            paths.radiance,
            paths.beta,
            paths.has_prev,
            paths.prev_pdf,
            mis,
        );
    }

    let sc = b.scatter;
    // Shading frame about the shading normal (on the geometric normal's side, as
    // `surface_at` keeps it).
    let (fs, ft) = frame(ns);
    let wo = to_local(wo_world, fs, ft, ns);
    // A one-sided BSDF seen from behind scatters nothing (Mitsuba's `diffuse`: its
    // eval, pdf and sample are zero unless cos(wo) > 0).
    let sc = sc & !(front_only & wo.z.le(0.0));
    let f = albedo.scale(Fw::splat(FRAC_1_PI));

    // Next-event estimation: a point on the chosen facet.
    let s = u_light[0].sqrt();
    let (b1, b2) = (1.0 - s, u_light[1] * s);
    let q = la.scale(1.0 - b1 - b2).add(lb.scale(b1)).add(lc.scale(b2));
    // Or a point of the chosen sphere, from the numbers before the facet choice.
    // (`solid`: the lanes whose density is by solid angle already, a sphere's cone.)
    let (q, ln, lradiance, pdf_area, solid, ltwo_sided) = match &ws.sphere_lights {
        Some(table) => {
            let facet = LightPoint {
                q,
                n: ln,
                radiance: lradiance,
                pdf_area,
                solid: Mw::FALSE,
                two_sided: ltwo_sided,
            };
            let s = sphere_light::sample(table, &emitter, b.u_light, p, facet);
            (s.q, s.n, s.radiance, s.pdf_area, s.solid, s.two_sided)
        }
        None => (q, ln, lradiance, pdf_area, Mw::FALSE, ltwo_sided),
    };
    let d = q.sub(p);
    let dist2 = d.dot(d);
    let wi = d.div(dist2.sqrt());
    let l_facing = -wi.dot(ln);
    let cos_l = ltwo_sided.select(l_facing.abs(), l_facing);
    // No light sample on delta lobes (the scalar code draws its numbers, unused).
    let light_ok = sc & !(mirror | glass) & light & cos_l.gt(0.0) & pdf_area.gt(0.0);
    let l_side = V3::select(l_facing.gt(0.0), ln, ln.neg());
    let target = offset_ray_origin(q, l_side, Fw::ZERO);
    let l_pdf = if solid.any() {
        solid.select(pick * pdf_area, pick * pdf_area * dist2 / cos_l)
    } else {
        pick * pdf_area * dist2 / cos_l
    };
    // Lanes whose light is at infinity: the direction, radiance and density they
    // sampled (lane by lane, as the scalar `sample`), and an unbounded shadow ray.
    let far = b.bg.light;
    let (wi, l_pdf, lradiance, light_ok) = if ws.background {
        (
            V3::select(far, b.bg.wi, wi),
            far.select(b.bg.light_pdf, l_pdf),
            V3::select(far, b.bg.li, lradiance),
            light_ok | (sc & !(mirror | glass) & far),
        )
    } else {
        (wi, l_pdf, lradiance, light_ok)
    };
    let wi_local = to_local(wi, fs, ft, ns);
    // The glossy BSDFs' value and density for the light direction, and their sample.
    // (No closure: it would not inherit the loop's target features.)
    let r = if ws.has_rough {
        let (nee, active) = (light_ok & rough, sc & rough);
        Some(glossy(
            ws,
            &b.material,
            wo,
            wi_local,
            b.u_lobe,
            b.u_bsdf,
            nee,
            active,
        ))
    } else {
        None
    };
    let f = match &r {
        Some(r) => V3::select(rough, r.f_light, f),
        None => f,
    };
    let same_side = (wo.z * wi_local.z).gt(0.0);
    // (A rough dielectric's value is zero where it should be, on either side.)
    let same_side = match &r {
        Some(r) => same_side | (rough & r.transmits),
        None => same_side,
    };
    let f_nonzero = same_side & !f.is_zero();
    let cos_n = wi.dot(n);
    let nee = light_ok & f_nonzero & (cos_n * wi_local.z).gt(0.0);
    let side = V3::select(cos_n.gt(0.0), n, n.neg());
    let shadow_origin = offset_ray_origin(p, side, error);
    let bsdf_pdf = wi_local.z.abs().max(0.0) * FRAC_1_PI;
    let bsdf_pdf = match &r {
        Some(r) => rough.select(r.pdf_light, bsdf_pdf),
        None => bsdf_pdf,
    };
    let w_light = mis(l_pdf, bsdf_pdf);
    let nee_value = paths
        .beta
        .mul(f)
        .mul(lradiance)
        .scale(wi_local.z.abs() * w_light / l_pdf);

    // BSDF sampling: a cosine-weighted direction on the side of `wo` (Lambert), the
    // mirror direction (conductor), or the dielectric's reflection or refraction.
    let mut wi_b = cosine_hemisphere(b.u_bsdf);
    wi_b.z = wo.z.lt(0.0).select(-wi_b.z, wi_b.z);
    let pdf_b = wi_b.z.abs().max(0.0) * FRAC_1_PI;
    let lambert_ok = lambert & wo.z.ne(0.0) & pdf_b.gt(0.0);
    let reflected = V3::new(-wo.x, -wo.y, wo.z);
    let spec_r = field3(&ws.shading, &b.material, mat::SPEC_R);
    let mirror_weight = spec_r.mul(conductor_fresnel(ws, &b.material, wo.z, sc & mirror));
    let g = dielectric(
        wo,
        field(&ws.shading, &b.material, mat::ETA),
        b.u_lobe,
        ws.fresnel_scale,
    );
    let spec_t = field3(&ws.shading, &b.material, mat::SPEC_T);
    let refracts = glass & !g.reflects;
    let wi_s = V3::select(lambert, wi_b, V3::select(refracts, g.refracted, reflected));
    let weight = V3::select(
        lambert,
        albedo,
        V3::select(
            mirror,
            mirror_weight,
            V3::select(refracts, spec_t.scale(g.eta_ti * g.eta_ti), spec_r),
        ),
    );
    let eta_s = refracts.select(g.eta_it, Fw::splat(1.0));
    let sampled = lambert_ok | (mirror & wo.z.gt(0.0)) | glass;
    let (wi_s, weight, sampled, pdf_b, eta_s) = match &r {
        Some(r) => (
            V3::select(rough, r.wi, wi_s),
            V3::select(rough, r.weight, weight),
            sampled | (rough & r.ok),
            rough.select(r.pdf, pdf_b),
            rough.select(r.eta, eta_s),
        ),
        None => (wi_s, weight, sampled, pdf_b, eta_s),
    };
    let wi_world = fs.scale(wi_s.x).add(ft.scale(wi_s.y)).add(ns.scale(wi_s.z));
    let cos_w = wi_world.dot(n);
    let beta = paths.beta.mul(weight);
    let go_on = sc & sampled & (cos_w * wi_s.z).gt(0.0) & !beta.is_zero() & beta.finite();
    let side = V3::select(cos_w.gt(0.0), n, n.neg());
    let origin = offset_ray_origin(p, side, error);
    paths.beta = V3::select(go_on, beta, paths.beta);
    paths.eta = go_on.select(paths.eta * eta_s, paths.eta);
    paths.origin = V3::select(go_on, origin, paths.origin);
    paths.dir = V3::select(go_on, wi_world, paths.dir);
    paths.prev_p = V3::select(go_on, p, paths.prev_p);
    paths.prev_pdf = go_on.select(pdf_b, paths.prev_pdf);
    // After a delta bounce an emitter hit counts in full (no MIS); after a glossy one
    // it is weighted against the light sample.
    paths.has_prev = (go_on & (lambert | rough)) | (!go_on & paths.has_prev);
    let q = (paths.beta.max_component() * (paths.eta * paths.eta)).min(0.95);
    Scattered {
        nee,
        shadow_origin,
        shadow_dir: V3::select(far, wi, target.sub(shadow_origin)),
        nee_value,
        shadow_t_max: far.select(Fw::splat(f32::INFINITY), Fw::splat(1.0)),
        go_on,
        q,
        beta_rr: paths.beta.scale(1.0 / q),
    }
}

/// The whole loop, compiled three times (AVX-512, AVX2 + FMA, portable:
/// [`SimdBuild`](irradia_geometry::packet::SimdBuild)) by the callers below, each its own
/// function, so that an unoptimised build's stack holds one copy of the loop's frame.
#[inline(always)]
fn run<const FMA: bool>(
    ws: &WideScene<'_, '_>,
    params: &PathParams,
    starts: &mut Starts<'_, '_>,
    out: &mut [Rgb],
    counters: &mut PathCounters,
) {
    let ps = ws.ps;
    let mut ahead = Ahead::new(starts);
    let mut paths = Paths {
        sample: [IDLE; W],
        rng: std::array::from_fn(|_| Rng::new(0, 0)),
        depth: [0; W],
        origin: V3::ZERO,
        dir: V3::ZERO,
        beta: V3::ZERO,
        radiance: V3::ZERO,
        prev_p: V3::ZERO,
        prev_pdf: Fw::ZERO,
        has_prev: Mw::FALSE,
        eta: Fw::splat(1.0),
    };
    let mut b = Bounce::default();
    // Hierarchy scenes: the hits of camera rays traced as packets when made.
    let mut known = KnownHits::NONE;
    // Every lane where the scene has emitters at infinity, none elsewhere.
    let background = if ws.background { Mw::TRUE } else { Mw::FALSE };
    loop {
        // Stage 1, per lane: refill; then the nearest hits; then per lane the draws.
        known.lanes = 0;
        let idle = Mw(std::array::from_fn(|lane| {
            -((paths.sample[lane] == IDLE) as i32)
        }));
        for lane in idle.lanes() {
            // The next camera sample that may meet the scene (made with up to W - 1
            // more; those that certainly escape are finished there).
            let Some((k, i)) = ahead.take(ws, starts, out, counters) else {
                continue;
            };
            if let Some(hit) = ahead.known_hit(i) {
                known.lanes |= 1 << lane;
                known.hit[lane] = hit;
            }
            paths.sample[lane] = k;
            paths.rng[lane] = ahead.starts.rng[i].clone();
            paths.depth[lane] = 1;
            paths.origin.set_lane(lane, ahead.starts.origin.lane(i));
            paths.dir.set_lane(lane, ahead.starts.dir.lane(i));
            paths.beta.set_lane(lane, Vec3::ONE);
            paths.radiance.set_lane(lane, Vec3::ZERO);
            paths.has_prev.set(lane, false);
            paths.eta.0[lane] = 1.0;
            counters.paths += 1;
        }
        let live = Mw(std::array::from_fn(|lane| {
            -((paths.sample[lane] != IDLE) as i32)
        }));
        if !live.any() {
            break;
        }
        b.bg.clear();
        // The nearest hits: W rays at once, or lane by lane.
        let hits = match &ws.rays {
            Some(rays) => rays.nearest::<FMA>(paths.origin, paths.dir, live),
            None => nearest_in_turns(ws, &paths.origin, &paths.dir, live, &known),
        };
        // Lanes whose ray may meet a sphere before its triangle (the lane cull):
        // only they run the exact sphere test below.
        let near_sphere = match &ws.cull {
            Some(c) => {
                let t_max = hits.hit.select(hits.t, Fw::splat(f32::INFINITY));
                c.may_hit(paths.origin, paths.dir, t_max, live)
            }
            None => live,
        };
        // Then the objects with their own tests (spheres), up to the triangle's `t`, as
        // the flat scene's `closest_hit` asks them: W rays at once ([`sphere_hits`]).
        let spheres = match &ws.spheres {
            Some(s) if near_sphere.any() => {
                let t_max = hits.hit.select(hits.t, Fw::splat(f32::INFINITY));
                s.nearest(paths.origin, paths.dir, t_max, near_sphere)
            }
            _ => SphereHits::default(),
        };
        // (Lane tests on integers: see `Mw::lanes`.) The masks are made as vectors
        // where they can be: lane by lane stores into a vector that the vector stage
        // then loads whole stall the load.
        let (hit_bits, prev_bits) = (hits.hit.bits(), paths.has_prev.bits());
        let surface = (hits.hit | spheres.hit) & live;
        b.other = spheres.hit & live;
        b.hit = surface;
        b.scatter = Mw::FALSE;
        b.bg.escaped = live.and_not(surface) & background;
        // The triangle lanes' hits (the others' triangle is 0: a valid index whose
        // record is not used).
        let on_triangle = surface.and_not(spheres.hit);
        b.triangle = on_triangle.select_u32(hits.triangle, [0; W]);
        b.b1 = on_triangle.select(hits.b1, b.b1);
        b.b2 = on_triangle.select(hits.b2, b.b2);
        for lane in live.lanes() {
            counters.rays += 1;
            let other = spheres.scene_hit(lane);
            if hit_bits >> lane & 1 == 0 && other.is_none() {
                // The path ends with what it has and, under emitters at infinity, what
                // it sees of them.
                // (What it sees: below, all lanes at once.)
                continue;
            }
            let (material, instance) = match &other {
                Some(sh) => {
                    let material = ps.tracer.material(sh.instance, sh.hit.leaf);
                    b.point.set_lane(lane, sh.hit.point);
                    b.normal.set_lane(lane, sh.hit.normal);
                    b.shading.set_lane(lane, sh.hit.shading_normal);
                    b.error.0[lane] = sh.hit.error;
                    (material, sh.instance)
                }
                None => ws.triangle_owner[hits.triangle[lane] as usize],
            };
            let m = &ws.materials[material as usize];
            b.material[lane] = material;
            if m.emissive && prev_bits >> lane & 1 != 0 {
                // Rare (emitter hits after a bounce): the point as the vector stage
                // and the flat scene compute it.
                let (point, n) = match &other {
                    Some(sh) => (sh.hit.point, sh.hit.normal),
                    None => {
                        let t = hits.triangle[lane];
                        let (b1, b2) = (hits.b1.0[lane], hits.b2.0[lane]);
                        let r = &ws.triangles[t as usize];
                        let v = |k: usize| Vec3::new(r[k], r[k + 1], r[k + 2]);
                        // The geometric normal as the hit reports it (given vertex
                        // normals may turn it).
                        let n = match ws.smooth {
                            Some(_) => ps.tracer.hit_normals(t, b1, b2).map_or(v(tri::N), |x| x.0),
                            None => v(tri::N),
                        };
                        let (point, _) = TriangleHit {
                            t: hits.t.0[lane],
                            b0: 1.0 - b1 - b2,
                            b1,
                            b2,
                        }
                        .point_and_error(
                            v(tri::P0),
                            v(tri::P1),
                            v(tri::P2),
                        );
                        (point, n)
                    }
                };
                b.light_pdf.0[lane] =
                    ps.lights
                        .pdf_object(ps.scene, instance, paths.prev_p.lane(lane), point, n);
            }
            let scatters = m.scatters && paths.depth[lane] < params.max_depth;
            b.scatter.set(lane, scatters);
            // With the light chosen in the vector stage, the numbers are drawn there.
            if !scatters || ws.pick.is_some() {
                continue;
            }
            let rng = &mut paths.rng[lane];
            let u_pick = rng.next_f32();
            let u_light = rng.next_2d();
            // The lobe choice: the dielectric's; drawn and unused by the one-lobe BSDFs
            // (as the scalar code).
            b.u_lobe.0[lane] = rng.next_f32();
            let u_bsdf = rng.next_2d();
            b.u_bsdf[0].0[lane] = u_bsdf.x;
            b.u_bsdf[1].0[lane] = u_bsdf.y;
            match ps.lights.pick_kernel(u_pick, u_light) {
                Some(KernelLight::AtInfinity(ls)) => {
                    b.light.set(lane, false);
                    b.bg.light(lane, &ls, ws.background_scale);
                }
                Some(KernelLight::Envmap(map, pick)) => {
                    // Sampled below, with the other lanes that chose the map.
                    b.light.set(lane, false);
                    b.bg.pick_map(lane, map, pick, u_light);
                }
                Some(KernelLight::Surface(emitter, pick, facet)) => {
                    // A sphere (no facet) warps the numbers as drawn.
                    let (facet, u) = facet.unwrap_or((0, u_light));
                    b.light.set(lane, true);
                    b.facet[lane] = ws.facet_start[emitter] + facet as u32;
                    b.emitter[lane] = emitter as u32;
                    b.pick.0[lane] = pick;
                    b.u_light[0].0[lane] = u.x;
                    b.u_light[1].0[lane] = u.y;
                    b.u_facet[0].0[lane] = u.x;
                    b.u_facet[1].0[lane] = u.y;
                }
                None => b.light.set(lane, false),
            }
        }

        // The light choice of all lanes at once (scenes of few emitters): the lanes
        // that chose an emitter at infinity sample it lane by lane.
        if let Some(lp) = &ws.pick {
            // The scattering lanes' numbers, all lanes at once in the order above (the
            // light choice, the light point, the lobe, the direction).
            let [pick_u, lx, ly, lobe, dx, dy] =
                Rng::next_f32_lanes(&mut paths.rng, b.scatter.bits());
            (b.u_pick, b.u_lobe) = (Fw(pick_u), Fw(lobe));
            b.u_light = [Fw(lx), Fw(ly)];
            b.u_bsdf = [Fw(dx), Fw(dy)];
            let (light, facet, pick, u, emitter) = pick_lights(lp, b.u_pick, b.u_light, b.scatter);
            let far = at_infinity(lp, &emitter, light);
            b.light = light & !far;
            b.facet = facet;
            b.pick = pick;
            b.u_facet = u;
            b.emitter = emitter;
            if far.any() {
                let (u, scale) = (b.u_light, ws.background_scale);
                far_lights(ps.lights, far, &emitter, pick, u, &mut b.bg, scale);
            }
        }

        // The emitters at infinity, all lanes at once: what the escaped rays see, and
        // the environment maps' light samples.
        if let Some(env) = &ws.environment {
            if b.bg.escaped.any() {
                let scale = ws.background_scale;
                b.bg.escaped_radiance(env, paths.dir, paths.has_prev, scale);
            }
            if b.bg.map_light.any() {
                b.bg.sample_maps(env, ws.background_scale);
            }
        }

        // Stage 2, all lanes.
        let s = scatter(ws, &mut paths, &b);

        // Stage 3, per lane: shadow rays, Russian roulette, finished paths.
        let blocked = match &ws.rays {
            Some(rays) => {
                rays.occluded::<FMA>(s.shadow_origin, s.shadow_dir, s.shadow_t_max, s.nee)
            }
            None => occluded_in_turns(ws, &s.shadow_origin, &s.shadow_dir, &s.shadow_t_max, s.nee),
        };
        // And the objects with their own tests (spheres), for shadow rays the
        // triangles leave through.
        // (W at once: [`sphere_hits`].)
        let blocked = match &ws.spheres {
            Some(spheres) => {
                let open = s.nee & !blocked;
                let near_sphere = match &ws.cull {
                    Some(c) => {
                        // The light sphere each shadow ray ends on cannot block it.
                        let own = std::array::from_fn(|lane| match b.light.get(lane) {
                            true => ws.light_ball[b.emitter[lane] as usize],
                            false => sphere_cull::NONE,
                        });
                        let (o, d, t) = (s.shadow_origin, s.shadow_dir, s.shadow_t_max);
                        c.may_hit_but(o, d, t, open, &own)
                    }
                    None => open,
                };
                if near_sphere.any() {
                    let (o, d, t) = (s.shadow_origin, s.shadow_dir, s.shadow_t_max);
                    blocked | spheres.occluded(o, d, t, near_sphere)
                } else {
                    blocked
                }
            }
            None => blocked,
        };
        let (nee, blocked, go_on) = (s.nee.bits(), blocked.bits(), s.go_on.bits());
        for lane in 0..W {
            if paths.sample[lane] == IDLE {
                continue;
            }
            if nee >> lane & 1 != 0 {
                counters.shadow_rays += 1;
                if blocked >> lane & 1 == 0 {
                    let l = paths.radiance.lane(lane) + s.nee_value.lane(lane);
                    paths.radiance.set_lane(lane, l);
                }
            }
            let mut alive = go_on >> lane & 1 != 0;
            if alive && paths.depth[lane] + 1 >= params.rr_depth {
                if paths.rng[lane].next_f32() >= s.q.0[lane] {
                    alive = false;
                } else {
                    let beta = s.beta_rr.lane(lane);
                    paths.beta.set_lane(lane, beta);
                }
            }
            if alive {
                paths.depth[lane] += 1;
            } else {
                let l = paths.radiance.lane(lane);
                out[paths.sample[lane]] = Rgb::new(l.x, l.y, l.z);
                paths.sample[lane] = IDLE;
            }
        }
    }
}

/// The loop with AVX2 and FMA enabled (LLVM turns the lane loops into pairs of
/// 8-wide instructions: W = 16 lanes are two 256-bit registers).
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
pub(super) unsafe fn run_avx2(
    ws: &WideScene<'_, '_>,
    params: &PathParams,
    starts: &mut Starts<'_, '_>,
    out: &mut [Rgb],
    counters: &mut PathCounters,
) {
    run::<true>(ws, params, starts, out, counters)
}

/// The loop with AVX-512 (F, VL, DQ, BW) as well: the same W lanes, with mask
/// registers for the selects and the `f64` lanes of [`super::dw`] in two registers. The
/// same IEEE operations in the same order as [`run_avx2`] (no fast-math), so the same
/// results bit for bit.
///
/// # Safety
/// The CPU must support AVX2, FMA and those AVX-512 subsets.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,avx512f,avx512vl,avx512dq,avx512bw")]
pub(super) unsafe fn run_avx512(
    ws: &WideScene<'_, '_>,
    params: &PathParams,
    starts: &mut Starts<'_, '_>,
    out: &mut [Rgb],
    counters: &mut PathCounters,
) {
    run::<true>(ws, params, starts, out, counters)
}

/// The loop for any CPU (SSE2 on x86_64).
pub(super) fn run_portable(
    ws: &WideScene<'_, '_>,
    params: &PathParams,
    starts: &mut Starts<'_, '_>,
    out: &mut [Rgb],
    counters: &mut PathCounters,
) {
    run::<false>(ws, params, starts, out, counters)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_match_the_scalar_frame_bit_for_bit() {
        let mut rng = Rng::new(5, 9);
        let mut n = V3::ZERO;
        let mut want = Vec::new();
        for lane in 0..W {
            let v = rng.next_centered_vec3().normalize();
            n.set_lane(lane, v);
            want.push(irradia_core::Frame::from_normal(v));
        }
        let (s, t) = frame(n);
        for (lane, f) in want.iter().enumerate() {
            assert_eq!(s.lane(lane), f.s);
            assert_eq!(t.lane(lane), f.t);
        }
    }
}
