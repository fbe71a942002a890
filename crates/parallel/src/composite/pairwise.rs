//! One pairwise swap of binary swap (Ma, Painter, Hansen, Krogh 1994) made cheap enough to
//! run at the bandwidth bound: each partner gives one half of its span and composites the
//! other half with what it receives.
//!
//! * Dense spans are sent straight from the layer's memory: the colour plane and the
//!   depth plane of each piece are two messages read in place (no packing copy), and
//!   they are received into one buffer per rank thread that is reused by every round and
//!   frame (no allocation, no page faults after the first frame).
//! * The span is cut into a few pieces, all posted at once; the receiver blends piece i
//!   while pieces i+1.. are still arriving, so the depth test runs on data that is still
//!   in cache and overlaps the transfer where the transport allows it.
//! * Run lengths ([`super::rle`], Ahrens and Painter 1998) are used only where they pay:
//!   the sender trims the span to its first and last active pixel (constant time for a
//!   dense image) and samples [`SAMPLES`] pixels of what is left; below [`RLE_BELOW`]
//!   active it sends run lengths, else the trimmed span dense. The decision travels in a
//!   small header that each side sends before its pieces, so the receiver knows what to
//!   expect and validates it (a malformed header names the sender).
//! * The depth test is branch-free ([`super::depth::blend`]).

use super::{active, depth, over, profile, rle, split_span, Layer, Operator, Pixel};
use crate::comm::{Comm, CommError};
use std::cell::RefCell;
use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

const DENSE: u32 = 0;
const RLE: u32 = 1;
/// Run lengths are sent when fewer than this fraction of the sampled pixels are active
/// (dense bytes scale with the trimmed span, run-length bytes with the active pixels).
pub const RLE_BELOW: f64 = 0.5;
/// Pixels sampled (evenly spaced) to estimate the active fraction of a trimmed span.
pub const SAMPLES: usize = 64;
/// Pieces are at least this many pixels (below it, per-message latency dominates).
pub const MIN_PIECE_PIXELS: usize = 1024;
/// Pieces carry the header's tag plus this.
const PIECE_TAG: u32 = 0x4000;
/// Largest piece count a header may announce.
const MAX_HEADER_PIECES: usize = 4096;

static MAX_PIECES: AtomicUsize = AtomicUsize::new(4);

/// Sets how many pieces a span is cut into at most (default 4; 1 = no pipelining). The
/// benchmark sweeps it; both sides of a swap need not agree (the header says).
pub fn set_max_pieces(n: usize) {
    MAX_PIECES.store(n.max(1), Ordering::Relaxed);
}

/// The number of pieces for a span of `n` pixels.
fn piece_count(n: usize) -> usize {
    if n == 0 {
        return 0;
    }
    n.div_ceil(MIN_PIECE_PIXELS)
        .clamp(1, MAX_PIECES.load(Ordering::Relaxed))
}

/// Buffers reused by every swap on this thread: run-length messages out, pieces in.
#[derive(Default)]
struct Scratch {
    send: Vec<u8>,
    recv: Vec<u32>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// What one side sends: an encoding of a sub-span of its give span, in `pieces` pieces.
#[derive(Clone, Debug, PartialEq)]
struct Plan {
    mode: u32,
    span: Range<usize>,
    pieces: usize,
    /// Byte length of each run-length piece (empty for dense).
    lens: Vec<usize>,
}

impl Plan {
    fn header(&self) -> Vec<u8> {
        let mut w = vec![
            self.mode,
            self.span.start as u32,
            self.span.end as u32,
            self.pieces as u32,
        ];
        w.extend(self.lens.iter().map(|&l| l as u32));
        bytemuck::cast_slice(&w).to_vec()
    }

    /// Parses and validates the partner's header: its span must lie inside `keep`.
    fn parse(buf: &[u8], keep: &Range<usize>, pixel_bytes: usize) -> Result<Plan, String> {
        if !buf.len().is_multiple_of(4) || buf.len() < 16 {
            return Err(format!("swap header of {} bytes", buf.len()));
        }
        let w: Vec<u32> = bytemuck::pod_collect_to_vec(buf);
        let (mode, a, b, k) = (w[0], w[1] as usize, w[2] as usize, w[3] as usize);
        if a > b || a < keep.start || b > keep.end {
            return Err(format!("sent span {a}..{b}, expected inside {keep:?}"));
        }
        if k > MAX_HEADER_PIECES || (k == 0) != (a == b) || k > b - a {
            return Err(format!("{k} pieces for span {a}..{b}"));
        }
        let lens: Vec<usize> = w[4..].iter().map(|&l| l as usize).collect();
        match mode {
            DENSE if lens.is_empty() => {}
            RLE if lens.len() == k => {
                let most = 12 * k + (b - a) * (pixel_bytes + 8);
                if lens.iter().any(|&l| !l.is_multiple_of(4) || l < 12)
                    || lens.iter().sum::<usize>() > most
                {
                    return Err(format!("run-length piece sizes {lens:?} for span {a}..{b}"));
                }
            }
            _ => {
                return Err(format!(
                    "swap header mode {mode} with {} lengths",
                    lens.len()
                ))
            }
        }
        Ok(Plan {
            mode,
            span: a..b,
            pieces: k,
            lens,
        })
    }

    /// Byte length of each piece this plan sends (dense: colour, depth per part).
    fn piece_lens(&self, pixel_bytes: usize) -> Vec<usize> {
        match self.mode {
            DENSE => split_span(&self.span, self.pieces)
                .iter()
                .flat_map(|c| [c.len() * pixel_bytes, c.len() * 4])
                .collect(),
            _ => self.lens.clone(),
        }
    }
}

/// Chooses how to send `give`: dense when `rle` is off; else trimmed to the active
/// pixels, and run lengths when the sampled active fraction is below [`RLE_BELOW`].
fn choose<P: Pixel>(layer: &Layer<P>, give: &Range<usize>, op: Operator, rle: bool) -> Plan {
    let plan = |mode, span: Range<usize>| Plan {
        mode,
        pieces: piece_count(span.len()),
        span,
        lens: Vec::new(),
    };
    if !rle {
        return plan(DENSE, give.clone());
    }
    let Range { start: a, end: b } = active::trim(layer, op, give);
    let n = b - a;
    if n == 0 {
        return plan(DENSE, a..b);
    }
    let samples = n.min(SAMPLES);
    let active = (0..samples)
        .filter(|&j| op.active(layer, a + (2 * j + 1) * n / (2 * samples)))
        .count();
    if (active as f64) < RLE_BELOW * samples as f64 {
        plan(RLE, a..b)
    } else {
        plan(DENSE, a..b)
    }
}

/// Splits `v` into the read-only `give` range and the writable `keep` range (disjoint).
fn give_and_keep<'a, T>(
    v: &'a mut [T],
    give: &Range<usize>,
    keep: &Range<usize>,
) -> (&'a [T], &'a mut [T]) {
    if give.end <= keep.start {
        let (lo, hi) = v.split_at_mut(keep.start);
        (&lo[give.clone()], &mut hi[..keep.len()])
    } else {
        assert!(keep.end <= give.start, "give and keep overlap");
        let (lo, hi) = v.split_at_mut(give.start);
        (&hi[..give.len()], &mut lo[keep.clone()])
    }
}

/// Swaps with `partner`: sends `give` of `layer`, receives the partner's `give` (our
/// `keep`) and composites it into `layer` with `op`; `incoming_front` says whether the
/// partner is in front in compositing order. `rle` allows run lengths; without it the
/// whole of `give` is sent dense. Uses `tag` and `tag + 0x4000`.
#[allow(clippy::too_many_arguments)]
pub fn swap<P: Pixel, C: Comm>(
    comm: &C,
    partner: usize,
    layer: &mut Layer<P>,
    give: Range<usize>,
    keep: Range<usize>,
    tag: u32,
    op: Operator,
    incoming_front: bool,
    rle: bool,
) -> Result<(), CommError> {
    let px = std::mem::size_of::<P>();
    let mut t = Instant::now();
    let mut mine = choose(layer, &give, op, rle);
    let decide_s = profile::lap(&mut t);
    SCRATCH.with(|scratch| {
        let mut scratch = scratch.borrow_mut();
        let Scratch { send, recv } = &mut *scratch;
        send.clear();
        if mine.mode == RLE {
            for part in split_span(&mine.span, mine.pieces) {
                let at = send.len();
                rle::encode_runs_into(send, layer, part, op);
                mine.lens.push(send.len() - at);
            }
        }
        let encode_s = profile::lap(&mut t);

        let malformed = |message: String| CommError::Malformed {
            rank: partner,
            message,
        };
        let got = comm.exchange(&[(partner, &mine.header())], &[partner], tag)?;
        let theirs = Plan::parse(&got[0], &keep, px).map_err(malformed)?;
        let header_s = profile::lap(&mut t);

        // Receive buffers: one reused allocation, cut into the partner's pieces.
        let in_lens = theirs.piece_lens(px);
        let words: usize = in_lens.iter().map(|l| l / 4).sum();
        if recv.len() < words {
            recv.resize(words, 0);
        }
        let mut rest: &mut [u8] = bytemuck::cast_slice_mut(&mut recv[..words]);
        let mut recvs: Vec<&mut [u8]> = Vec::with_capacity(in_lens.len());
        for &l in &in_lens {
            let (head, tail) = rest.split_at_mut(l);
            recvs.push(head);
            rest = tail;
        }

        let (give_c, keep_c) = give_and_keep(&mut layer.color, &give, &keep);
        let (give_d, keep_d) = give_and_keep(&mut layer.depth, &give, &keep);
        let out_parts = split_span(&mine.span, mine.pieces);
        let sends: Vec<&[u8]> = match mine.mode {
            DENSE => out_parts
                .iter()
                .flat_map(|c| {
                    let c = c.start - give.start..c.end - give.start;
                    [
                        bytemuck::cast_slice::<P, u8>(&give_c[c.clone()]),
                        bytemuck::cast_slice::<f32, u8>(&give_d[c]),
                    ]
                })
                .collect(),
            _ => {
                let mut at = 0;
                mine.lens
                    .iter()
                    .map(|&l| {
                        at += l;
                        &send[at - l..at]
                    })
                    .collect()
            }
        };

        let in_parts = split_span(&theirs.span, theirs.pieces);
        let mut blend_s = 0.0;
        let t_exchange = Instant::now();
        let mut arrived = |i: usize, pieces: &[&[u8]]| -> Result<(), CommError> {
            let t0 = Instant::now();
            if theirs.mode == DENSE {
                if i.is_multiple_of(2) {
                    return Ok(()); // colour piece: wait for its depths
                }
                let part = &in_parts[i / 2];
                let colors: &[P] = bytemuck::try_cast_slice(pieces[i - 1])
                    .map_err(|e| malformed(format!("colour piece: {e}")))?;
                let depths: &[f32] = bytemuck::try_cast_slice(pieces[i])
                    .map_err(|e| malformed(format!("depth piece: {e}")))?;
                let at = part.start - keep.start..part.end - keep.start;
                blend_dense(
                    op,
                    &mut keep_c[at.clone()],
                    &mut keep_d[at],
                    colors,
                    depths,
                    incoming_front,
                );
            } else {
                let how = rle::Apply::Blend { op, incoming_front };
                let s = rle::apply_to(&mut keep_c[..], &mut keep_d[..], keep.start, pieces[i], how)
                    .map_err(malformed)?;
                if s != in_parts[i] {
                    return Err(malformed(format!(
                        "run-length piece {i} covers {s:?}, announced {:?}",
                        in_parts[i]
                    )));
                }
            }
            blend_s += t0.elapsed().as_secs_f64();
            Ok(())
        };
        comm.exchange_pieces(partner, tag + PIECE_TAG, &sends, &mut recvs, &mut arrived)?;
        let exchange_s = t_exchange.elapsed().as_secs_f64();
        let bytes: usize = sends.iter().map(|s| s.len()).sum();
        profile::add(|p| {
            p.swaps += 1;
            p.rle_swaps += (mine.mode == RLE) as u32;
            p.decide_s += decide_s;
            p.encode_s += encode_s;
            p.header_s += header_s;
            p.wait_s += exchange_s - blend_s;
            p.blend_s += blend_s;
            p.bytes_sent += bytes as u64;
        });
        Ok(())
    })
}

#[inline]
fn blend_dense<P: Pixel>(
    op: Operator,
    lc: &mut [P],
    ld: &mut [f32],
    colors: &[P],
    depths: &[f32],
    incoming_front: bool,
) {
    match op {
        Operator::Depth => depth::blend(lc, ld, colors, depths, incoming_front),
        Operator::Over => over::blend(lc, ld, colors, depths, incoming_front),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headers_round_trip_and_bad_ones_are_refused() {
        let keep = 100..200;
        let p = Plan {
            mode: RLE,
            span: 120..180,
            pieces: 2,
            lens: vec![16, 40],
        };
        assert_eq!(Plan::parse(&p.header(), &keep, 4).unwrap(), p);
        let outside = Plan {
            span: 90..180,
            ..p.clone()
        };
        assert!(Plan::parse(&outside.header(), &keep, 4).is_err());
        let odd_len = Plan {
            lens: vec![16, 41],
            ..p.clone()
        };
        assert!(Plan::parse(&odd_len.header(), &keep, 4).is_err());
        let dense_with_lens = Plan {
            mode: DENSE,
            ..p.clone()
        };
        assert!(Plan::parse(&dense_with_lens.header(), &keep, 4).is_err());
        assert!(Plan::parse(&p.header()[..12], &keep, 4).is_err());
    }

    #[test]
    fn dense_images_are_sent_dense_and_sparse_ones_as_runs() {
        let mut l = Layer::<[u8; 4]>::new(64, 64);
        l.depth.iter_mut().for_each(|d| *d = 0.5);
        let dense = choose(&l, &(0..4096), Operator::Depth, true);
        assert_eq!((dense.mode, dense.span), (DENSE, 0..4096));
        let mut s = Layer::<[u8; 4]>::new(64, 64);
        for i in (1000..3000).step_by(5) {
            s.depth[i] = 0.5;
        }
        let sparse = choose(&s, &(0..4096), Operator::Depth, true);
        assert_eq!((sparse.mode, sparse.span), (RLE, 1000..2996));
        let off = choose(&s, &(0..4096), Operator::Depth, false);
        assert_eq!((off.mode, off.span), (DENSE, 0..4096));
        let empty = choose(
            &Layer::<[u8; 4]>::new(8, 8),
            &(0..64),
            Operator::Depth,
            true,
        );
        assert_eq!((empty.span.len(), empty.pieces), (0, 0));
    }
}
