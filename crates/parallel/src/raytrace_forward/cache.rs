//! A pixel's memory of resolved geometry queries, and the geometry that replays from it.
//!
//! [`Replay`] is what the unchanged Whitted tracer asks during a generation: a query
//! whose answer is in the pixel's [`Log`] gets it; any other is recorded as a miss and
//! gets a placeholder (no hit, not blocked), so that the rest of the pixel's ray tree
//! is still explored in this generation and its own queries found. A pixel is finished
//! when it was traced without a miss: then every answer it used was the true one, and
//! since the pixel's random numbers are seeded from the pixel alone
//! (`irradia_render::film`), its colour is the serial one bit for bit. This is deterministic replay in the sense of
//! record-and-replay debugging: the tracer's stack is never saved or sent; it is
//! re-executed, which costs computation but keeps the recursive tracer as it is.

use super::wire::{Answer, Kind, Query};
use irradia_core::Ray;
use irradia_geometry::SceneHit;
use irradia_render::whitted::{ObjectSet, RayQuery};
use std::sync::Mutex;

/// A pixel's replay log: the queries its last trace asked, in the order it asked them,
/// with their answers (`None` until resolved).
pub type Log = Vec<(Query, Option<Answer>)>;

/// Where the current pixel's replay stands.
#[derive(Default)]
struct Cursor {
    /// The pixel's log from its last trace, answers filled in.
    old: Log,
    /// The next entry of `old` the trace is expected to ask.
    at: usize,
    /// What this trace asked.
    new: Log,
    missed: bool,
}

/// Geometry answered from a pixel's replay log, recording what the pixel asks.
///
/// A replay asks the same queries in the same order as the last trace of the pixel
/// until it reaches the first answer that was a placeholder then; after that it may ask
/// new ones. So the log is read in order (a comparison, no hashing, memory read in
/// sequence), and a query out of order is looked up by a scan of the log.
pub struct Replay<'c> {
    /// Whether each object of the scene is a closed solid (replicated, like materials).
    solid: &'c [bool],
    /// One pixel at a time (a task's pixels share one `Replay`; the lock is never
    /// contended).
    cursor: Mutex<Cursor>,
}

impl<'c> Replay<'c> {
    pub fn new(solid: &'c [bool]) -> Self {
        Self {
            solid,
            cursor: Mutex::new(Cursor::default()),
        }
    }

    /// Starts replaying a pixel whose last trace asked `log` (empty for a first trace).
    pub fn begin(&self, log: Log) {
        let mut c = self.cursor.lock().expect("replay cursor");
        *c = Cursor {
            old: log,
            at: 0,
            new: Vec::with_capacity(c.new.capacity()),
            missed: false,
        };
    }

    /// Ends the pixel: what it asked, and whether some answer was missing (then its
    /// colour is not the true one yet).
    pub fn end(&self) -> (Log, bool) {
        let mut c = self.cursor.lock().expect("replay cursor");
        (std::mem::take(&mut c.new), c.missed)
    }

    #[inline]
    fn lookup(&self, q: Query) -> Option<Answer> {
        let mut guard = self.cursor.lock().expect("replay cursor");
        let c = &mut *guard;
        let found = match c.old.get(c.at) {
            Some(&(k, a)) if k == q => {
                c.at += 1;
                a
            }
            _ => c.old.iter().position(|e| e.0 == q).and_then(|i| {
                c.at = i + 1;
                c.old[i].1
            }),
        };
        c.new.push((q, found));
        c.missed |= found.is_none();
        found
    }
}
impl RayQuery for Replay<'_> {
    #[inline]
    fn closest_hit(&self, set: ObjectSet, ray: &Ray, t_max: f32) -> Option<SceneHit> {
        match self.lookup(Query::new(Kind::Nearest, set, ray, t_max)) {
            Some(Answer::Nearest(h)) => h,
            _ => None,
        }
    }

    #[inline]
    fn any_hit(&self, set: ObjectSet, ray: &Ray, t_max: f32) -> bool {
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
