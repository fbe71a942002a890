//! Where the wide kernel's paths start (see [`super`]): a camera sample per sample
//! index, either from a caller's closure or made W at a time from a tile's
//! [`CameraBatch`] ahead of the lanes that take them. A lane whose path has ended takes
//! the next one (Laine, Karras, Aila, "Megakernels Considered Harmful", HPG 2013:
//! regenerating paths in place of finished ones).

use super::{escapes, WideScene};
use crate::camera_batch::{CameraBatch, Cursor, StartsW};
use crate::path::integrator::PathCounters;
use irradia_core::{Ray, Rgb, Rng};
use irradia_geometry::packet::lanes::{Mw, V3, W};

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
        }
    }

    /// The next sample for a lane, `(k, i)`: sample `k` of the batch (`out.len()`
    /// samples), made in lane `i` of [`Self::starts`]; `None` when every sample is
    /// taken or finished. Samples are made W at once; those whose camera ray
    /// certainly meets nothing are finished into `out` ([`super::escapes`]).
    #[inline(always)]
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
        }
        let i = self.waiting.trailing_zeros() as usize;
        self.waiting &= self.waiting - 1;
        Some((self.first + i, i))
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
