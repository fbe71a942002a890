//! Emitters at infinity in the 8-wide kernel: the constant environment (the background
//! plus Mitsuba's `constant` emitters) and Mitsuba's `envmap`
//! ([`EnvmapSampler`](crate::path::envmap::EnvmapSampler)).
//!
//! Two places of the path estimator see them (Veach 1997, 9.2; Pharr, Jakob, Humphreys,
//! PBRT 4th ed., 13.4 "Improving the Sampling": lights at infinity):
//! - a ray that leaves the scene gathers the environment's radiance, weighted by the
//!   power heuristic against the light sample's density of its direction when it was
//!   sampled from a non-delta BSDF ([`Background::escape`] per lane: the map's lookup
//!   and density, `LightSampler::environment_radiance_pdf`, are a gather; the weight
//!   and the sum are vector arithmetic in [`Background::add_escaped`]);
//! - next-event estimation chooses an emitter at infinity with its probability and
//!   samples a direction from it ([`Background::light`] per lane, with
//!   `LightSampler::pick_kernel`, the scalar `sample`'s arithmetic); the vector stage
//!   then evaluates the BSDF, the MIS weight and the unbounded shadow ray for those
//!   lanes as for facet lights, with the sampled direction in place of the direction
//!   to the facet's point.
//!
//! Both use the scalar estimator's numbers in its order, so samples agree with
//! [`radiance_in`](crate::path::integrator::radiance_in)'s to rounding.

use crate::path::lights::{LightSample, LightSampler};
use glam::Vec3;
use irradia_geometry::packet::lanes::{F8, M8, V3};

/// What the per-lane stage records of the emitters at infinity, per bounce.
#[derive(Default)]
pub(crate) struct Background {
    /// Lanes whose ray left the scene, with the environment's radiance along it (times
    /// the test scale) and the light sample's density of its direction (0 after a
    /// delta bounce or from the camera, where it is not used).
    pub escaped: M8,
    pub le: V3,
    pub pdf: F8,
    /// Lanes whose light sample is a direction towards an emitter at infinity, with
    /// the direction, the radiance (times the test scale) and the solid-angle density
    /// (choice included).
    pub light: M8,
    pub wi: V3,
    pub li: V3,
    pub light_pdf: F8,
}

impl Background {
    /// Clears the lanes' records at the start of a bounce.
    #[inline(always)]
    pub fn clear(&mut self) {
        self.escaped = M8::FALSE;
        self.light = M8::FALSE;
    }

    /// Lane `lane`'s ray (direction `dir`) left the scene: the environment's radiance
    /// and, when the path has a previous non-delta vertex (`has_prev`), the density
    /// with which light sampling gives `dir`.
    #[inline(always)]
    pub fn escape(
        &mut self,
        lights: &LightSampler,
        lane: usize,
        dir: Vec3,
        has_prev: bool,
        scale: f32,
    ) {
        let (le, pdf) = lights.environment_radiance_pdf(dir, has_prev);
        self.escaped.set(lane, true);
        self.le.set_lane(lane, Vec3::new(le.r, le.g, le.b) * scale);
        self.pdf.0[lane] = pdf;
    }

    /// Lane `lane` samples an emitter at infinity: `ls` is the sample.
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
        has_prev: M8,
        prev_pdf: F8,
        mis: impl Fn(F8, F8) -> F8,
    ) -> V3 {
        let w = has_prev.select(mis(prev_pdf, self.pdf), F8::splat(1.0));
        let added = radiance.add(beta.mul(self.le).scale(w));
        V3::select(self.escaped, added, radiance)
    }
}
