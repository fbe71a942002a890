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

use crate::camera_batch::{CameraBatch, Cursor, StartsW};
use crate::path::flat_scene::FlatScene;
use glam::Vec3;
use irradia_core::{Ray, Rng};
use irradia_geometry::bvh::packet_traverse::PACKET;
use irradia_geometry::packet::lanes::{V3, W};
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
/// rays in lanes and the streams.
pub(super) struct Ahead {
    /// The batch's cursor at the next sample to make ([`Starts::Camera`]).
    cursor: Option<Cursor>,
    pub(super) starts: StartsW,
    /// The nearest triangle hits of the samples' camera rays, where known (bit `i` of
    /// `known` for sample `i` of [`Self::starts`]).
    hits: [Option<(u32, PacketHit)>; W],
    known: u32,
    /// How many are made, and how many of them lanes have taken.
    made: usize,
    taken: usize,
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
            hits: [None; W],
            known: 0,
            made: 0,
            taken: 0,
        }
    }

    /// Takes sample `next` (the first not yet taken, `next < total`), making it with up
    /// to W - 1 more when none made is left (their camera rays traced through `packets`
    /// when given): its index in [`Self::starts`].
    #[inline(always)]
    pub(super) fn take(
        &mut self,
        starts: &mut Starts<'_, '_>,
        packets: Option<&FlatScene>,
        next: usize,
        total: usize,
    ) -> usize {
        if self.taken == self.made {
            self.make(starts, next, (total - next).min(W));
            self.trace(packets);
        }
        let i = self.taken;
        self.taken += 1;
        i
    }

    /// The nearest triangle hit of sample `i`'s camera ray, where it is known: as
    /// [`FlatScene::nearest_triangles`] answers it.
    #[inline(always)]
    pub(super) fn known_hit(&self, i: usize) -> Option<Option<(u32, PacketHit)>> {
        (self.known >> i & 1 != 0).then(|| self.hits[i])
    }

    /// Traces the camera rays of the samples made, [`PACKET`] at a time, through
    /// `packets` (none: no hit is known). Not inlined: the kernel's frame stays as it
    /// was (unoptimised builds).
    #[inline(never)]
    fn trace(&mut self, packets: Option<&FlatScene>) {
        self.known = 0;
        let Some(flat) = packets else {
            return;
        };
        let mut rays = [Ray::new(Vec3::ZERO, Vec3::X); PACKET];
        for first in (0..self.made).step_by(PACKET) {
            let n = PACKET.min(self.made - first);
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
        self.made = n;
        self.taken = 0;
    }
}
