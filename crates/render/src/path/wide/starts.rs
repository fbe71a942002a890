//! Where the wide kernel's paths start (see [`super`]): a camera sample per sample
//! index, either from a caller's closure or made W at a time from a tile's
//! [`CameraBatch`] ahead of the lanes that take them. A lane whose path has ended takes
//! the next one (Laine, Karras, Aila, "Megakernels Considered Harmful", HPG 2013:
//! regenerating paths in place of finished ones).

use crate::camera_batch::{CameraBatch, Cursor, StartsW};
use irradia_core::{Ray, Rng};
use irradia_geometry::packet::lanes::{V3, W};

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
            made: 0,
            taken: 0,
        }
    }

    /// Takes sample `next` (the first not yet taken, `next < total`), making it with up
    /// to seven more when none made is left: its index in [`Self::starts`].
    #[inline(always)]
    pub(super) fn take(&mut self, starts: &mut Starts<'_, '_>, next: usize, total: usize) -> usize {
        if self.taken == self.made {
            self.make(starts, next, (total - next).min(W));
        }
        let i = self.taken;
        self.taken += 1;
        i
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
