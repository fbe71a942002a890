//! A rank's memory of resolved geometry queries, and the geometry that replays from it.
//!
//! [`Replay`] is what the unchanged Whitted tracer asks during a generation: a query
//! whose answer is in the [`Cache`] gets it; any other is recorded as a miss and gets a
//! placeholder (no hit, not blocked), so that the rest of the pixel's ray tree is still
//! explored in this generation and its own queries found. A pixel is finished when it
//! was traced without a miss: then every answer it used was the true one, and since the
//! pixel's random numbers are seeded from the pixel alone (`irradia_render::film`), its
//! colour is the serial one bit for bit. This is deterministic replay in the sense of
//! record-and-replay debugging: the tracer's stack is never saved or sent; it is
//! re-executed, which costs computation but keeps the recursive tracer as it is.

use super::wire::{Answer, Kind, Query};
use irradia_core::Ray;
use irradia_geometry::SceneHit;
use irradia_render::whitted::{Geometry, ObjectSet};
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::sync::Mutex;

/// A multiply-rotate hasher for the cache's fixed-size bit keys (the FxHash of the Rust
/// compiler, with a final mix): much cheaper than SipHash, and the keys are not chosen
/// by an adversary.
#[derive(Default, Clone, Copy)]
pub struct BitsHasher(u64);

impl Hasher for BitsHasher {
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(b as u64);
        }
    }
    #[inline]
    fn write_u8(&mut self, i: u8) {
        self.write_u64(i as u64);
    }
    #[inline]
    fn write_u32(&mut self, i: u32) {
        self.write_u64(i as u64);
    }
    #[inline]
    fn write_u64(&mut self, i: u64) {
        self.0 = (self.0.rotate_left(5) ^ i).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    #[inline]
    fn write_usize(&mut self, i: usize) {
        self.write_u64(i as u64);
    }
    /// With a final mix (MurmurHash3's fmix64), so that the low bits hashbrown
    /// indexes buckets by depend on every bit of the key.
    #[inline]
    fn finish(&self) -> u64 {
        let mut h = self.0;
        h ^= h >> 33;
        h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
        h ^= h >> 33;
        h = h.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
        h ^ h >> 33
    }
}

/// Resolved queries of one rank, by their exact bits.
pub type Cache = HashMap<Query, Answer, BuildHasherDefault<BitsHasher>>;

/// Geometry answered from a [`Cache`], recording the queries it cannot answer.
pub struct Replay<'c> {
    cache: &'c Cache,
    /// Whether each object of the scene is a closed solid (replicated, like materials).
    solid: &'c [bool],
    misses: Mutex<Vec<Query>>,
}

impl<'c> Replay<'c> {
    pub fn new(cache: &'c Cache, solid: &'c [bool]) -> Self {
        Self {
            cache,
            solid,
            misses: Mutex::new(Vec::new()),
        }
    }

    /// How many queries missed so far (compare before and after a pixel).
    pub fn miss_count(&self) -> usize {
        self.misses.lock().expect("miss list").len()
    }

    /// The queries that missed, in the order they were asked.
    pub fn into_misses(self) -> Vec<Query> {
        self.misses.into_inner().expect("miss list")
    }

    #[inline]
    fn lookup(&self, q: Query) -> Option<Answer> {
        let a = self.cache.get(&q).copied();
        if a.is_none() {
            self.misses.lock().expect("miss list").push(q);
        }
        a
    }
}

impl Geometry for Replay<'_> {
    #[inline]
    fn intersect(&self, set: ObjectSet, ray: &Ray, t_max: f32) -> Option<SceneHit> {
        match self.lookup(Query::new(Kind::Nearest, set, ray, t_max)) {
            Some(Answer::Nearest(h)) => h,
            _ => None,
        }
    }

    #[inline]
    fn occluded(&self, set: ObjectSet, ray: &Ray, t_max: f32) -> bool {
        matches!(
            self.lookup(Query::new(Kind::Any, set, ray, t_max)),
            Some(Answer::Any(true))
        )
    }

    #[inline]
    fn is_solid(&self, object: u32) -> bool {
        self.solid[object as usize]
    }
}
