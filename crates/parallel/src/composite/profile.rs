//! Where the time of the pairwise swaps goes, per rank (thread): choosing the encoding,
//! exchanging the small headers, encoding run lengths, waiting for pieces to arrive, and
//! blending them. The counters are thread-local (one rank per thread under `LocalComm`,
//! one per process under MPI) and cost two clock reads per step; the compositing
//! benchmark reads them with [`take`].

use std::cell::Cell;
use std::time::Instant;

/// Accumulated seconds per step of [`super::pairwise::swap`], and the bytes it sent.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SwapProfile {
    /// Pairwise swaps (rounds) run.
    pub swaps: u32,
    /// Trimming the span to its active pixels and sampling the active fraction.
    pub decide_s: f64,
    /// The header exchange (also where a rank waits for a slower partner to arrive, and
    /// where small run-length spans travel, inline with their header).
    pub header_s: f64,
    /// Encoding run lengths (zero for dense spans, which are sent in place).
    pub encode_s: f64,
    /// Waiting for pieces to arrive (the transfer not hidden behind blending).
    pub wait_s: f64,
    /// Blending arrived pieces into the local layer.
    pub blend_s: f64,
    /// Payload bytes sent (headers excluded, except those of inline run lengths).
    pub bytes_sent: u64,
    /// Spans sent as run lengths rather than dense (one per destination and step).
    pub rle_swaps: u32,
}

impl SwapProfile {
    /// Total seconds over every step.
    pub fn total_s(&self) -> f64 {
        self.decide_s + self.header_s + self.encode_s + self.wait_s + self.blend_s
    }
}

thread_local! {
    static PROFILE: Cell<SwapProfile> = Cell::new(SwapProfile::default());
}

/// Returns this thread's counters and resets them.
pub fn take() -> SwapProfile {
    PROFILE.with(|p| p.replace(SwapProfile::default()))
}

pub(crate) fn add(f: impl FnOnce(&mut SwapProfile)) {
    PROFILE.with(|p| {
        let mut v = p.get();
        f(&mut v);
        p.set(v);
    })
}

/// Seconds since `t`, and restarts `t`.
pub(crate) fn lap(t: &mut Instant) -> f64 {
    let now = Instant::now();
    let s = (now - *t).as_secs_f64();
    *t = now;
    s
}
