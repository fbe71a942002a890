//! The exchange step every compositing strategy is made of, cheap enough to run near the
//! bandwidth bound: [`transfer`] sends spans of the layer to some ranks and composites
//! what others send into the span it keeps. A pairwise swap of binary swap (Ma, Painter,
//! Hansen, Krogh 1994; [`swap`]) gives one half and keeps the other; a radix-k round
//! (Peterka et al. 2009) sends one part to each group member; direct send is one such
//! round of all ranks; binary swap's fold and the tree send a whole layer one way.
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
//! * Run lengths of at most [`INLINE_MAX`] bytes travel inside the header message
//!   itself: a sparse span costs one message per partner and direction instead of a
//!   header and then its pieces, i.e. one rendezvous per round instead of two. Where
//!   latency dominates (sparse images, or more ranks than cores) that is most of the
//!   time of a round.
//! * The depth test is branch-free ([`super::depth::blend`]).
//! * The sender's [`ActiveRect`] travels in the header: nothing outside it is read when
//!   trimming or encoding, and the receiver's rectangle grows by it (IceT's bounding
//!   boxes, Moreland et al. 2011).

use super::active::{self, ActiveRect};
use super::{depth, over, profile, rle, split_span, Layer, LayerRef, Operator, Pixel};
use crate::comm::{Comm, CommError, PiecesIn, PiecesOut};
use std::cell::RefCell;
use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

pub(crate) const DENSE: u32 = 0;
const RLE: u32 = 1;
/// Run lengths carried in the header message, after the piece sizes.
const RLE_INLINE: u32 = 2;
/// Run-length messages up to this many bytes are sent inside the header message (the
/// receiver learns the size by probing); larger ones go as pieces, pipelined with the
/// blending on the receiver. [`set_inline_max`] changes it for one rank's thread.
pub const INLINE_MAX: usize = 1 << 20;
/// Run lengths are sent when fewer than this fraction of the sampled pixels are active
/// (dense bytes scale with the trimmed span, run-length bytes with the active pixels).
pub const RLE_BELOW: f64 = 0.5;
/// Pixels sampled (evenly spaced) to estimate the active fraction of a trimmed span.
pub const SAMPLES: usize = 64;
/// Pieces are at least this many pixels (below it, per-message latency dominates).
pub const MIN_PIECE_PIXELS: usize = 1024;
/// Pieces carry the header's tag plus this.
const PIECE_TAG: u32 = 0x4000;
/// Words of a header before the run-length piece sizes: mode, span start and end,
/// pieces, active rectangle.
const HEADER_WORDS: usize = 8;
/// Largest piece count a header may announce.
const MAX_HEADER_PIECES: usize = 4096;

static MAX_PIECES: AtomicUsize = AtomicUsize::new(4);

/// Sets how many pieces a span is cut into at most (default 4; 1 = no pipelining). The
/// benchmark sweeps it; both sides of a swap need not agree (the header says).
pub fn set_max_pieces(n: usize) {
    MAX_PIECES.store(n.max(1), Ordering::Relaxed);
}

thread_local! {
    static INLINE_MAX_HERE: std::cell::Cell<usize> = const { std::cell::Cell::new(INLINE_MAX) };
}

/// Sets the largest run-length message sent inline with its header, for the calling
/// thread (one rank; 0 sends every run-length span as pieces after its header). Only
/// speed depends on it: the receiver reads the mode from the header.
pub fn set_inline_max(bytes: usize) {
    INLINE_MAX_HERE.with(|m| m.set(bytes));
}

/// Bytes of a dense span's header message.
pub const HEADER_BYTES: usize = 4 * HEADER_WORDS;

/// The number of pieces for a span of `n` pixels (each sent as a colour and a depth
/// message).
pub fn piece_count(n: usize) -> usize {
    if n == 0 {
        return 0;
    }
    n.div_ceil(MIN_PIECE_PIXELS)
        .clamp(1, MAX_PIECES.load(Ordering::Relaxed))
}

/// Buffers reused by every swap on this thread: run-length messages out, pieces in,
/// header messages (with any inline run lengths) in.
#[derive(Default)]
struct Scratch {
    send: Vec<u8>,
    recv: Vec<u32>,
    headers: Vec<Vec<u8>>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// What one side sends: an encoding of a sub-span of its give span, in `pieces` pieces.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Plan {
    pub(crate) mode: u32,
    pub(crate) span: Range<usize>,
    pieces: usize,
    /// Byte length of each run-length piece (empty for dense).
    lens: Vec<usize>,
    /// The sender's active rectangle: the receiver's layer holds active pixels inside
    /// it afterwards.
    rect: ActiveRect,
}

impl Plan {
    fn header(&self) -> Vec<u8> {
        let r = &self.rect;
        let mut w = vec![
            self.mode,
            self.span.start as u32,
            self.span.end as u32,
            self.pieces as u32,
            r.x0,
            r.y0,
            r.x1,
            r.y1,
        ];
        w.extend(self.lens.iter().map(|&l| l as u32));
        bytemuck::cast_slice(&w).to_vec()
    }

    /// Bytes of this plan's header (the inline run lengths follow it).
    fn header_len(&self) -> usize {
        4 * (HEADER_WORDS + if self.mode == DENSE { 0 } else { self.pieces })
    }

    /// Parses and validates the partner's header message: its span must lie inside
    /// `keep` and its rectangle on the `width` x `height` screen. Returns the plan and
    /// the inline run lengths (empty unless the mode is inline).
    fn parse<'b>(
        buf: &'b [u8],
        keep: &Range<usize>,
        pixel_bytes: usize,
        width: u32,
        height: u32,
    ) -> Result<(Plan, &'b [u8]), String> {
        if !buf.len().is_multiple_of(4) || buf.len() < 4 * HEADER_WORDS {
            return Err(format!("swap header of {} bytes", buf.len()));
        }
        let w: Vec<u32> = bytemuck::pod_collect_to_vec(&buf[..4 * HEADER_WORDS]);
        let (mode, a, b, k) = (w[0], w[1] as usize, w[2] as usize, w[3] as usize);
        if a > b || a < keep.start || b > keep.end {
            return Err(format!("sent span {a}..{b}, expected inside {keep:?}"));
        }
        if k > MAX_HEADER_PIECES || (k == 0) != (a == b) || k > b - a {
            return Err(format!("{k} pieces for span {a}..{b}"));
        }
        let rect = ActiveRect {
            x0: w[4],
            y0: w[5],
            x1: w[6],
            y1: w[7],
        };
        if !rect.fits(width, height) {
            return Err(format!(
                "active rectangle {rect:?} off a {width}x{height} screen"
            ));
        }
        let (lens, inline): (Vec<usize>, &[u8]) = match mode {
            DENSE if buf.len() == 4 * HEADER_WORDS => (Vec::new(), &[]),
            RLE | RLE_INLINE if buf.len() >= 4 * (HEADER_WORDS + k) => {
                let (head, body) = buf.split_at(4 * (HEADER_WORDS + k));
                let lens: Vec<usize> = bytemuck::pod_collect_to_vec::<u8, u32>(head)
                    [HEADER_WORDS..]
                    .iter()
                    .map(|&l| l as usize)
                    .collect();
                let most = 12 * k + (b - a) * (pixel_bytes + 8);
                let total: usize = lens.iter().sum();
                if lens.iter().any(|&l| !l.is_multiple_of(4) || l < 12) || total > most {
                    return Err(format!("run-length piece sizes {lens:?} for span {a}..{b}"));
                }
                let body_len = if mode == RLE_INLINE { total } else { 0 };
                if body.len() != body_len {
                    return Err(format!(
                        "swap message carries {} bytes after its header, announced {body_len}",
                        body.len()
                    ));
                }
                (lens, body)
            }
            _ => {
                return Err(format!(
                    "swap header mode {mode} with {} bytes for {k} pieces",
                    buf.len()
                ))
            }
        };
        let plan = Plan {
            mode,
            span: a..b,
            pieces: k,
            lens,
            rect,
        };
        Ok((plan, inline))
    }

    /// Byte length of each piece this plan sends (dense: colour, depth per part).
    fn piece_lens(&self, pixel_bytes: usize) -> Vec<usize> {
        match self.mode {
            DENSE => split_span(&self.span, self.pieces)
                .iter()
                .flat_map(|c| [c.len() * pixel_bytes, c.len() * 4])
                .collect(),
            RLE => self.lens.clone(),
            _ => Vec::new(), // inline: nothing follows the header message
        }
    }
}

/// Chooses how to send `give`: dense when `rle` is off; else trimmed to the active
/// pixels (looking only inside `rect`), and run lengths when the sampled active fraction
/// is below [`RLE_BELOW`].
pub(crate) fn choose<'a, P: Pixel>(
    layer: impl Into<LayerRef<'a, P>>,
    give: &Range<usize>,
    op: Operator,
    rle: bool,
    rect: &ActiveRect,
) -> Plan {
    let layer = layer.into();
    let plan = |mode, span: Range<usize>| Plan {
        mode,
        pieces: piece_count(span.len()),
        span,
        lens: Vec::new(),
        rect: *rect,
    };
    if !rle {
        return plan(DENSE, give.clone());
    }
    let Range { start: a, end: b } = active::trim_in(layer, op, give, rect);
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

/// Splits `v` around `keep`: the read-only pixels before it, `keep` itself (writable),
/// and the read-only pixels after it.
fn split_around<'a, T>(v: &'a mut [T], keep: &Range<usize>) -> (&'a [T], &'a mut [T], &'a [T]) {
    let (lo, rest) = v.split_at_mut(keep.start);
    let (keep, hi) = rest.split_at_mut(keep.len());
    (lo, keep, hi)
}

/// The pixels `give` (which must not overlap `keep`) from the two sides of
/// [`split_around`].
fn outside<'a, T>(lo: &'a [T], hi: &'a [T], keep: &Range<usize>, give: &Range<usize>) -> &'a [T] {
    if give.end <= keep.start {
        &lo[give.clone()]
    } else {
        assert!(
            give.start >= keep.end,
            "give {give:?} overlaps keep {keep:?}"
        );
        &hi[give.start - keep.end..give.end - keep.end]
    }
}

/// Swaps with `partner`: sends `give` of `layer`, receives the partner's `give` (our
/// `keep`) and composites it into `layer` with `op`; `incoming_front` says whether the
/// partner is in front in compositing order. `rle` allows run lengths; without it the
/// whole of `give` is sent dense. Uses `tag` and `tag + 0x4000`. `rect` holds every
/// active pixel of `layer` and is widened by the partner's.
#[allow(clippy::too_many_arguments)]
pub fn swap<P: Pixel, C: Comm>(
    comm: &C,
    partner: usize,
    layer: &mut Layer<P>,
    rect: &mut ActiveRect,
    give: Range<usize>,
    keep: Range<usize>,
    tag: u32,
    op: Operator,
    incoming_front: bool,
    rle: bool,
) -> Result<(), CommError> {
    swap_from(
        comm,
        partner,
        layer,
        None,
        rect,
        give,
        keep,
        tag,
        op,
        incoming_front,
        rle,
    )
}

/// [`swap`] reading the layer from `src` when given (see [`transfer_from`]).
#[allow(clippy::too_many_arguments)]
pub fn swap_from<P: Pixel, C: Comm>(
    comm: &C,
    partner: usize,
    layer: &mut Layer<P>,
    src: Option<LayerRef<'_, P>>,
    rect: &mut ActiveRect,
    give: Range<usize>,
    keep: Range<usize>,
    tag: u32,
    op: Operator,
    incoming_front: bool,
    rle: bool,
) -> Result<(), CommError> {
    let step = Step {
        sends: &[(partner, give)],
        recvs: &[(partner, incoming_front)],
        keep,
        tag,
        op,
        rle,
    };
    transfer_from(comm, layer, src, rect, &step)
}

/// One step of a compositing strategy as seen by one rank: the spans it sends and to
/// whom, the ranks it receives from, and the span `keep` it composites them into.
#[derive(Clone, Debug)]
pub struct Step<'a> {
    /// `(rank, span)`: send these pixels of the layer to that rank (spans outside `keep`).
    pub sends: &'a [(usize, Range<usize>)],
    /// `(rank, incoming_front)`, in the order to composite them: for each source
    /// whether it is in front of everything composited so far. For the bit-exact
    /// result, sources in front come nearest first, then those behind, nearest first
    /// (see [`super::radix_k::group_round`]).
    pub recvs: &'a [(usize, bool)],
    /// What this rank composites into; every received span must lie inside it.
    pub keep: Range<usize>,
    /// Headers use `tag`, pieces `tag + 0x4000`.
    pub tag: u32,
    pub op: Operator,
    /// Allow run lengths (else every span is sent dense, untrimmed).
    pub rle: bool,
}

/// Runs one [`Step`]: every send chooses dense or run lengths on its own, all headers are
/// exchanged (one small message per partner and direction), then every piece of every
/// send is posted at once while the pieces of each source are composited as they
/// arrive, in the order of `step.recvs`. `rect` holds every active pixel of `layer` and
/// is widened by each source's rectangle (sent in the header).
pub fn transfer<P: Pixel, C: Comm>(
    comm: &C,
    layer: &mut Layer<P>,
    rect: &mut ActiveRect,
    step: &Step<'_>,
) -> Result<(), CommError> {
    transfer_from(comm, layer, None, rect, step)
}

/// [`transfer`] of a layer whose pixels are still in the caller's memory, `src` (the
/// Python binding's numpy arrays), when given: the spans sent are read from `src` in
/// place, and only `step.keep` is copied from `src` into `layer` (whose other pixels
/// are neither read nor written) before what arrives is composited into it. A first
/// round of binary swap thus copies half the layer instead of all of it. Without `src`
/// it is [`transfer`].
pub fn transfer_from<P: Pixel, C: Comm>(
    comm: &C,
    layer: &mut Layer<P>,
    src: Option<LayerRef<'_, P>>,
    rect: &mut ActiveRect,
    step: &Step<'_>,
) -> Result<(), CommError> {
    if let Some(s) = &src {
        assert!(
            s.color.len() == layer.len() && s.depth.len() == layer.len(),
            "transfer: source of {} pixels for a layer of {}",
            s.color.len(),
            layer.len()
        );
    }
    let Step {
        sends: give_to,
        recvs: take_from,
        keep,
        tag,
        op,
        rle,
    } = step.clone();
    let px = std::mem::size_of::<P>();
    let (width, height) = (layer.width, layer.height);
    let mut t = Instant::now();
    let mut mine: Vec<Plan> = give_to
        .iter()
        .map(|(_, give)| choose(src.unwrap_or(layer.view()), give, op, rle, rect))
        .collect();
    let decide_s = profile::lap(&mut t);
    SCRATCH.with(|scratch| {
        let mut scratch = scratch.borrow_mut();
        let Scratch {
            send,
            recv,
            headers: incoming,
        } = &mut *scratch;
        send.clear();
        // Each run-length plan's bytes in `send`: a slot for its header, then its pieces.
        // Small ones become inline (header and runs are one message), the others send
        // the header on its own and the pieces from `send[body]`.
        let mut bodies = vec![0..0; mine.len()];
        for (plan, body) in mine.iter_mut().zip(&mut bodies) {
            if plan.mode != RLE {
                continue;
            }
            let slot = send.len();
            send.resize(slot + plan.header_len(), 0);
            for part in split_span(&plan.span, plan.pieces) {
                let at = send.len();
                rle::encode_runs_into(send, src.unwrap_or(layer.view()), part, op, rect);
                plan.lens.push(send.len() - at);
            }
            if send.len() - slot - plan.header_len() <= INLINE_MAX_HERE.with(|m| m.get()) {
                plan.mode = RLE_INLINE;
                send[slot..slot + plan.header_len()].copy_from_slice(&plan.header());
                *body = slot..send.len();
            } else {
                *body = slot + plan.header_len()..send.len();
            }
        }
        let encode_s = profile::lap(&mut t);

        let headers: Vec<Vec<u8>> = mine
            .iter()
            .map(|p| {
                if p.mode == RLE_INLINE {
                    Vec::new()
                } else {
                    p.header()
                }
            })
            .collect();
        let header_sends: Vec<(usize, &[u8])> = give_to
            .iter()
            .zip(mine.iter().zip(&headers).zip(&bodies))
            .map(|((d, _), ((plan, h), body))| match plan.mode {
                RLE_INLINE => (*d, &send[body.clone()]),
                _ => (*d, h.as_slice()),
            })
            .collect();
        let sources: Vec<usize> = take_from.iter().map(|r| r.0).collect();
        comm.exchange_into(&header_sends, &sources, tag, incoming)?;
        let got = &*incoming;
        let mut theirs = Vec::with_capacity(got.len());
        let mut inline = Vec::with_capacity(got.len());
        for (buf, &src) in got.iter().zip(&sources) {
            let (plan, runs) = Plan::parse(buf, &keep, px, width, height)
                .map_err(|message| CommError::Malformed { rank: src, message })?;
            theirs.push(plan);
            inline.push(runs);
        }
        let header_s = profile::lap(&mut t);

        // Receive buffers: one reused allocation, cut into every source's pieces.
        let in_lens: Vec<Vec<usize>> = theirs.iter().map(|p| p.piece_lens(px)).collect();
        let words: usize = in_lens.iter().flatten().map(|l| l / 4).sum();
        if recv.len() < words {
            recv.resize(words, 0);
        }
        let mut rest: &mut [u8] = bytemuck::cast_slice_mut(&mut recv[..words]);
        let mut recvs: Vec<PiecesIn<'_>> = Vec::with_capacity(sources.len());
        for (&src, lens) in sources.iter().zip(&in_lens) {
            let mut bufs = Vec::with_capacity(lens.len());
            for &l in lens {
                let (head, tail) = std::mem::take(&mut rest).split_at_mut(l);
                bufs.push(head);
                rest = tail;
            }
            recvs.push((src, bufs));
        }

        let (lo_c, keep_c, hi_c) = split_around(&mut layer.color, &keep);
        let (lo_d, keep_d, hi_d) = split_around(&mut layer.depth, &keep);
        if let Some(s) = &src {
            keep_c.copy_from_slice(&s.color[keep.clone()]);
            keep_d.copy_from_slice(&s.depth[keep.clone()]);
        }
        let sends: Vec<PiecesOut<'_>> = give_to
            .iter()
            .zip(mine.iter().zip(&bodies))
            .map(|((d, _), (plan, body))| {
                let pieces = match plan.mode {
                    DENSE => split_span(&plan.span, plan.pieces)
                        .iter()
                        .flat_map(|c| match &src {
                            Some(s) => [
                                bytemuck::cast_slice::<P, u8>(&s.color[c.clone()]),
                                bytemuck::cast_slice::<f32, u8>(&s.depth[c.clone()]),
                            ],
                            None => [
                                bytemuck::cast_slice::<P, u8>(outside(lo_c, hi_c, &keep, c)),
                                bytemuck::cast_slice::<f32, u8>(outside(lo_d, hi_d, &keep, c)),
                            ],
                        })
                        .collect(),
                    RLE => {
                        let mut at = body.start;
                        plan.lens
                            .iter()
                            .map(|&l| {
                                at += l;
                                &send[at - l..at]
                            })
                            .collect()
                    }
                    _ => Vec::new(), // inline: already sent with the header
                };
                (*d, pieces)
            })
            .collect();

        let in_parts: Vec<Vec<Range<usize>>> = theirs
            .iter()
            .map(|p| split_span(&p.span, p.pieces))
            .collect();
        let mut blend_s = 0.0;
        let t_exchange = Instant::now();
        // Applies one source's run-length piece `i` (from its pieces or inline).
        let apply_runs = |keep_c: &mut [P],
                          keep_d: &mut [f32],
                          j: usize,
                          i: usize,
                          piece: &[u8]|
         -> Result<(), CommError> {
            let malformed = |message: String| CommError::Malformed {
                rank: sources[j],
                message,
            };
            let how = rle::Apply::Blend {
                op,
                incoming_front: take_from[j].1,
            };
            let s = rle::apply_to(keep_c, keep_d, keep.start, piece, how).map_err(malformed)?;
            if s != in_parts[j][i] {
                return Err(malformed(format!(
                    "run-length piece {i} covers {s:?}, announced {:?}",
                    in_parts[j][i]
                )));
            }
            Ok(())
        };
        // Sources are composited in the order of `take_from`: an inline source is
        // blended when every earlier source is done, i.e. before the first piece of the
        // next source that sends pieces, or after the exchange. `blend_inline(upto)`
        // blends the inline sources before `upto` not blended yet (sources that send
        // pieces are blended as their pieces arrive).
        let mut inline_next = 0;
        let mut blend_inline =
            |upto: usize, keep_c: &mut [P], keep_d: &mut [f32]| -> Result<(), CommError> {
                while inline_next < upto {
                    let j = inline_next;
                    if theirs[j].mode == RLE_INLINE {
                        let mut at = 0;
                        for (i, &l) in theirs[j].lens.iter().enumerate() {
                            apply_runs(keep_c, keep_d, j, i, &inline[j][at..at + l])?;
                            at += l;
                        }
                    }
                    inline_next += 1;
                }
                Ok(())
            };
        let mut arrived = |j: usize, i: usize, pieces: &[&[u8]]| -> Result<(), CommError> {
            let t0 = Instant::now();
            let malformed = |message: String| CommError::Malformed {
                rank: sources[j],
                message,
            };
            let incoming_front = take_from[j].1;
            if i == 0 {
                blend_inline(j, &mut *keep_c, &mut *keep_d)?;
            }
            if theirs[j].mode == DENSE {
                if i.is_multiple_of(2) {
                    return Ok(()); // colour piece: wait for its depths
                }
                let part = &in_parts[j][i / 2];
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
                apply_runs(keep_c, keep_d, j, i, pieces[i])?;
            }
            blend_s += t0.elapsed().as_secs_f64();
            Ok(())
        };
        let pieces_out = sends.iter().any(|s| !s.1.is_empty());
        let pieces_in = recvs.iter().any(|r| !r.1.is_empty());
        if pieces_out || pieces_in {
            comm.exchange_pieces_many(tag + PIECE_TAG, &sends, &mut recvs, &mut arrived)?;
        }
        let t0 = Instant::now();
        blend_inline(theirs.len(), keep_c, keep_d)?;
        blend_s += t0.elapsed().as_secs_f64();
        let exchange_s = t_exchange.elapsed().as_secs_f64();
        let bytes: usize = sends
            .iter()
            .flat_map(|s| &s.1)
            .map(|s| s.len())
            .sum::<usize>()
            + (mine.iter().zip(&bodies))
                .filter(|(p, _)| p.mode == RLE_INLINE)
                .map(|(_, b)| b.len())
                .sum::<usize>();
        for plan in &theirs {
            *rect = rect.union(&plan.rect);
        }
        profile::add(|p| {
            p.swaps += 1;
            p.rle_swaps += mine.iter().filter(|p| p.mode != DENSE).count() as u32;
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
            rect: ActiveRect {
                x0: 1,
                y0: 2,
                x1: 30,
                y1: 9,
            },
        };
        let parse = |h: &[u8]| Plan::parse(h, &keep, 4, 32, 10).map(|(plan, _)| plan);
        assert_eq!(parse(&p.header()).unwrap(), p);
        // Inline: the runs follow the header, exactly as many bytes as announced.
        let inline = Plan {
            mode: RLE_INLINE,
            ..p.clone()
        };
        let mut msg = inline.header();
        msg.extend((0..56u8).collect::<Vec<_>>());
        let (back, runs) = Plan::parse(&msg, &keep, 4, 32, 10).unwrap();
        assert_eq!(
            (back, runs.len(), runs[0], runs[55]),
            (inline.clone(), 56, 0, 55)
        );
        assert!(parse(&msg[..msg.len() - 4]).is_err());
        assert!(parse(&inline.header()).is_err());
        msg.extend([0u8; 4]);
        assert!(parse(&msg).is_err());
        // Run lengths sent as pieces carry nothing after the header.
        let mut trailing = p.header();
        trailing.extend([0u8; 4]);
        assert!(parse(&trailing).is_err());
        let off_screen = Plan {
            rect: ActiveRect::full(33, 10),
            ..p.clone()
        };
        assert!(parse(&off_screen.header()).is_err());
        let outside = Plan {
            span: 90..180,
            ..p.clone()
        };
        assert!(parse(&outside.header()).is_err());
        let odd_len = Plan {
            lens: vec![16, 41],
            ..p.clone()
        };
        assert!(parse(&odd_len.header()).is_err());
        let dense_with_lens = Plan {
            mode: DENSE,
            ..p.clone()
        };
        assert!(parse(&dense_with_lens.header()).is_err());
        assert!(parse(&p.header()[..28]).is_err());
    }

    #[test]
    fn dense_images_are_sent_dense_and_sparse_ones_as_runs() {
        let mut l = Layer::<[u8; 4]>::new(64, 64);
        l.depth.iter_mut().for_each(|d| *d = 0.5);
        let all = ActiveRect::full(64, 64);
        let dense = choose(&l, &(0..4096), Operator::Depth, true, &all);
        assert_eq!((dense.mode, dense.span), (DENSE, 0..4096));
        let mut s = Layer::<[u8; 4]>::new(64, 64);
        for i in (1000..3000).step_by(5) {
            s.depth[i] = 0.5;
        }
        let sparse = choose(&s, &(0..4096), Operator::Depth, true, &all);
        assert_eq!((sparse.mode, sparse.span), (RLE, 1000..2996));
        let off = choose(&s, &(0..4096), Operator::Depth, false, &all);
        assert_eq!((off.mode, off.span), (DENSE, 0..4096));
        let empty = choose(
            &Layer::<[u8; 4]>::new(8, 8),
            &(0..64),
            Operator::Depth,
            true,
            &ActiveRect::full(8, 8),
        );
        assert_eq!((empty.span.len(), empty.pieces), (0, 0));
    }
}
