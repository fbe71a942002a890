//! Where the wide kernel's paths start (see [`super`]): a camera sample per sample
//! index, either from a caller's closure or made W at a time from a tile's
//! [`CameraBatch`] ahead of the lanes that take them. A lane whose path has ended takes
//! the next one (Laine, Karras, Aila, "Megakernels Considered Harmful", HPG 2013:
//! regenerating paths in place of finished ones).
//!
//! In scenes whose triangles the kernel walks a hierarchy for (see [`super`]), the W
//! camera rays made at once are also traced then, eight at a time as coherent packets
//! ([`FlatScene::nearest_triangles_packet`]): they are a pixel's samples or two
//! neighbours', so they walk the same nodes, where the kernel's query would hold only
//! the few of them that lanes took in one bounce, among other rays going every way.
//! The lane that takes such a sample takes its nearest hit too ([`super::lane_queries`]).

use super::{escapes, WideScene};
use crate::camera_batch::{CameraBatch, Cursor, StartsW};
use crate::path::flat_scene::FlatScene;
use crate::path::integrator::PathCounters;
use glam::Vec3;
use irradia_core::{Ray, Rgb, Rng};
use irradia_geometry::bvh::packet_traverse::PACKET;
use irradia_geometry::packet::lanes::{Mw, V3, W};
use irradia_geometry::packet::PacketHit;

/// Where the kernel's paths start: a camera sample per sample index.
pub(crate) enum Starts<'a, 'c> {
    /// Sample `k` from a call (tests; cameras and filters the lanes do not make):
    /// its camera ray and its stream, already past the pixel jitter. Called through a
    /// `dyn` reference, so the kernel is compiled once, in this crate.
    Each(&'a mut dyn FnMut(usize) -> (Ray, Rng)),
    /// A tile's camera samples, made W at once in the kernel's own vector width,
    /// and where their filter weights go (`weights[k]` for sample `k`; empty when the
    /// caller needs none: [`CameraBatch::unit_weights`]).
    Camera {
        batch: &'a CameraBatch<'c>,
        weights: &'a mut [f32],
    },
}

/// Camera samples made ahead of the lanes that take them, up to W at once: the
/// rays in lanes and the streams. Those whose ray certainly leaves the scene are
/// finished as they are made ([`super::escapes`]); the others wait for a lane.
pub(super) struct Ahead {
    /// The batch's cursor at the next sample to make ([`Starts::Camera`]).
    cursor: Option<Cursor>,
    pub(super) starts: StartsW,
    /// The sample in lane 0 of [`Self::starts`], and the next sample to make.
    first: usize,
    next: usize,
    /// The lanes of [`Self::starts`] made and not yet taken (bit `i`: lane `i`).
    waiting: u32,
    /// The nearest triangle hits of the samples' camera rays, where known (bit `i` of
    /// `known` for sample `i` of [`Self::starts`]).
    hits: [Option<(u32, PacketHit)>; W],
    known: u32,
}

impl Ahead {
    pub(super) fn new(starts: &Starts<'_, '_>) -> Self {
        Self {
            cursor: match starts {
                Starts::Camera { batch, .. } => Some(batch.cursor()),
                Starts::Each(_) => None,
            },
            starts: StartsW {
                origin: V3::ZERO,
                dir: V3::ZERO,
                rng: std::array::from_fn(|_| Rng::new(0, 0)),
                weight: [1.0; W],
            },
            first: 0,
            next: 0,
            waiting: 0,
            hits: [None; W],
            known: 0,
        }
    }

    /// The next sample for a lane, `(k, i)`: sample `k` of the batch (`out.len()`
    /// samples), made in lane `i` of [`Self::starts`]; `None` when every sample is
    /// taken or finished. Samples are made W at once; those whose camera ray
    /// certainly meets nothing are finished into `out` ([`super::escapes`]).
    // Inlined into the kernel when optimised; its own frame when not (the unoptimised
    // kernel's frame must fit a worker thread's stack: see `kernel.rs`).
    #[cfg_attr(not(debug_assertions), inline(always))]
    #[cfg_attr(debug_assertions, inline(never))]
    pub(super) fn take(
        &mut self,
        ws: &WideScene<'_, '_>,
        starts: &mut Starts<'_, '_>,
        out: &mut [Rgb],
        counters: &mut PathCounters,
    ) -> Option<(usize, usize)> {
        while self.waiting == 0 {
            let total = out.len();
            if self.next == total {
                return None;
            }
            let n = (total - self.next).min(W);
            self.make(starts, self.next, n);
            self.first = self.next;
            self.next += n;
            let made = Mw::from_fn(|i| i < n);
            let s = &self.starts;
            let escaped = escapes::escaping(ws, s.origin, s.dir, made);
            if escaped.any() {
                escapes::finish(ws, s, escaped, self.first, out, counters);
            }
            self.waiting = (made & !escaped).bits();
            // Hierarchy scenes: the camera rays that wait for a lane traced as packets.
            self.known = 0;
            if self.waiting != 0 && ws.rays.is_none() && ws.has_triangles() {
                self.trace(&ws.ps.tracer, n);
            }
        }
        let i = self.waiting.trailing_zeros() as usize;
        self.waiting &= self.waiting - 1;
        Some((self.first + i, i))
    }

    /// The nearest triangle hit of sample `i`'s camera ray, where it is known: as
    /// [`FlatScene::nearest_triangles`] answers it.
    #[inline(always)]
    pub(super) fn known_hit(&self, i: usize) -> Option<Option<(u32, PacketHit)>> {
        (self.known >> i & 1 != 0).then(|| self.hits[i])
    }

    /// Traces the camera rays of the `made` samples of [`Self::starts`], [`PACKET`] at
    /// a time, through `flat`. Not inlined: the kernel's frame stays as it was
    /// (unoptimised builds).
    #[inline(never)]
    fn trace(&mut self, flat: &FlatScene, made: usize) {
        let mut rays = [Ray::new(Vec3::ZERO, Vec3::X); PACKET];
        for first in (0..made).step_by(PACKET) {
            let n = PACKET.min(made - first);
            for (k, r) in rays[..n].iter_mut().enumerate() {
                *r = Ray::new(
                    self.starts.origin.lane(first + k),
                    self.starts.dir.lane(first + k),
                );
            }
            let answered =
                flat.nearest_triangles_packet(&rays[..n], &mut self.hits[first..first + n]);
            self.known |= answered << first;
        }
    }

    /// Makes samples `next..next + n` (`n <= W`, `next` the first not yet made).
    #[inline(always)]
    fn make(&mut self, starts: &mut Starts<'_, '_>, next: usize, n: usize) {
        match starts {
            Starts::Camera { batch, weights } => {
                let cursor = self.cursor.as_mut().expect("a camera batch's cursor");
                self.starts = batch.lanes(cursor, n);
                if !weights.is_empty() {
                    weights[next..next + n].copy_from_slice(&self.starts.weight[..n]);
                }
            }
            Starts::Each(start) => {
                for i in 0..n {
                    let (ray, rng) = (*start)(next + i);
                    self.starts.origin.set_lane(i, ray.origin);
                    self.starts.dir.set_lane(i, ray.dir);
                    self.starts.rng[i] = rng;
                }
            }
        }
    }
}
