//! Emitters at infinity in the wide kernel: the constant environment (the background
//! plus Mitsuba's `constant` emitters) and Mitsuba's `envmap`
//! ([`EnvmapSampler`](crate::path::envmap::EnvmapSampler)).
//!
//! Two places of the path estimator see them (Veach 1997, 9.2; Pharr, Jakob, Humphreys,
//! PBRT 4th ed., 13.4 "Improving the Sampling": lights at infinity):
//! - a ray that leaves the scene gathers the environment's radiance, weighted by the
//!   power heuristic against the light sample's density of its direction when it was
//!   sampled from a non-delta BSDF ([`Background::escaped_radiance`]: the maps' lookups
//!   and densities, `LightSampler::environment_radiance_pdf`, for all lanes at once in
//!   [`envmap_lanes`](super::envmap_lanes); the weight and the sum in
//!   [`Background::add_escaped`]);
//! - next-event estimation chooses an emitter at infinity with its probability and
//!   samples a direction from it (the choice W lanes at once with the other
//!   emitters' in scenes of few emitters, [`super::light_pick`], else per lane with
//!   `LightSampler::pick_kernel`; the sample per lane: the
//!   constant environment's uniform direction with the scalar `sample`'s arithmetic,
//!   [`Background::light`]; an environment map's importance sample for all the lanes
//!   that chose it at once, [`Background::sample_maps`]); the vector stage then
//!   evaluates the BSDF, the MIS weight and the unbounded shadow ray for those lanes as
//!   for facet lights, with the sampled direction in place of the direction to the
//!   facet's point.
//!
//! Both use the scalar estimator's numbers in its order, so samples agree with
//! [`radiance_in`](crate::path::integrator::radiance_in)'s to rounding.

use super::envmap_lanes::EnvironmentW;
use crate::path::lights::LightSample;
use glam::{Vec2, Vec3};
use irradia_geometry::packet::lanes::{Fw, Mw, V3, W};

/// What the per-lane stage records of the emitters at infinity, per bounce.
#[derive(Default)]
pub(crate) struct Background {
    /// Lanes whose ray left the scene, with the environment's radiance along it (times
    /// the test scale) and the light sample's density of its direction (0 after a
    /// delta bounce or from the camera, where it is not used).
    pub escaped: Mw,
    pub le: V3,
    pub pdf: Fw,
    /// Lanes whose light sample is a direction towards an emitter at infinity, with
    /// the direction, the radiance (times the test scale) and the solid-angle density
    /// (choice included).
    pub light: Mw,
    pub wi: V3,
    pub li: V3,
    pub light_pdf: Fw,
    /// Lanes whose light choice fell on an environment map, with the map (its place in
    /// [`EnvironmentW`]), the probability of choosing it and the numbers to sample it
    /// with; [`Background::sample_maps`] turns them into `light` lanes.
    pub map_light: Mw,
    pub map: [u32; W],
    pub map_pick: Fw,
    pub map_u: [Fw; 2],
}

impl Background {
    /// Clears the lanes' records at the start of a bounce.
    #[inline(always)]
    pub fn clear(&mut self) {
        self.escaped = Mw::FALSE;
        self.light = Mw::FALSE;
        self.map_light = Mw::FALSE;
    }

    /// The rays of the `escaped` lanes (directions `dir`) left the scene: the
    /// environment's radiance and, where the path has a previous non-delta vertex
    /// (`has_prev`), the density with which light sampling gives `dir` (else 0), all
    /// lanes at once, bit for bit `LightSampler::environment_radiance_pdf`'s.
    #[inline(always)]
    pub fn escaped_radiance(&mut self, env: &EnvironmentW, dir: V3, has_prev: Mw, scale: f32) {
        let (le, pdf) = env.radiance_pdf(dir);
        self.le = le.scale(Fw::splat(scale));
        self.pdf = has_prev.keep(pdf);
    }

    /// Lane `lane` chose environment map `map` (with probability `pick`), to be
    /// sampled with the numbers `u`.
    #[inline(always)]
    pub fn pick_map(&mut self, lane: usize, map: usize, pick: f32, u: Vec2) {
        self.map_light.set(lane, true);
        self.map[lane] = map as u32;
        self.map_pick.0[lane] = pick;
        self.map_u[0].0[lane] = u.x;
        self.map_u[1].0[lane] = u.y;
    }

    /// The environment maps' samples of the `map_light` lanes, each map's lanes at
    /// once: the lanes that got one become `light` lanes with the direction, the
    /// radiance (times the test scale) and the density `pick` times the map's, as
    /// `LightSampler::sample` gives them.
    #[inline(always)]
    pub fn sample_maps(&mut self, env: &EnvironmentW, scale: f32) {
        for (k, m) in env.maps().iter().enumerate() {
            let lanes = self.map_light & Mw::from_fn(|l| self.map[l] == k as u32);
            if !lanes.any() {
                continue;
            }
            let (ok, wi, li, pdf) = m.sample(self.map_u, lanes);
            self.light = self.light | ok;
            self.wi = V3::select(ok, wi, self.wi);
            self.li = V3::select(ok, li.scale(Fw::splat(scale)), self.li);
            self.light_pdf = ok.select(self.map_pick * pdf, self.light_pdf);
        }
    }

    /// Lane `lane` samples the constant environment: `ls` is the sample.
    #[inline(always)]
    pub fn light(&mut self, lane: usize, ls: &LightSample, scale: f32) {
        self.light.set(lane, true);
        self.wi.set_lane(lane, ls.wi);
        self.li
            .set_lane(lane, Vec3::new(ls.li.r, ls.li.g, ls.li.b) * scale);
        self.light_pdf.0[lane] = ls.pdf;
    }

    /// `radiance` plus, in the escaped lanes, `beta * le * w` with `w` the power
    /// heuristic of the previous vertex's BSDF density `prev_pdf` against the light
    /// density (1 without a previous non-delta vertex), as the scalar estimator adds it.
    #[inline(always)]
    pub fn add_escaped(
        &self,
        radiance: V3,
        beta: V3,
        has_prev: Mw,
        prev_pdf: Fw,
        mis: impl Fn(Fw, Fw) -> Fw,
    ) -> V3 {
        let w = has_prev.select(mis(prev_pdf, self.pdf), Fw::splat(1.0));
        let added = radiance.add(beta.mul(self.le).scale(w));
        V3::select(self.escaped, added, radiance)
    }
}
