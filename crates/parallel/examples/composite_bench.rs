//! Binary-swap compositing benchmark over MPI (bench/composite/run.sh runs it):
//! `mpirun -np P composite_bench [--width 1280] [--height 720] [--reps 9] [--pieces 4]`.
//!
//! Measures, in one run and with the same ranks:
//! * the transfer bound: for every binary-swap round, a concurrent pairwise exchange of
//!   that round's message (every rank with its round partner, as the OSU multi-pair
//!   bidirectional test does) of the size the busiest rank sends in that round, dense
//!   RGBA8 + f32 depth, through the same `Comm::exchange_pieces` (one piece: MPI_Irecv
//!   into a ready buffer, MPI_Isend from the data in place); the bound is the sum over
//!   the rounds of those exchange times, i.e. sum of bytes(round) / bandwidth(round);
//! * binary swap (the reduce-scatter, without the final gather) of a dense image and of
//!   a 10%-active one, with the time of each step (decide, header, encode, wait, blend);
//!   the 10%-active image twice: once found by scanning the depth plane
//!   (`active10`), once with the rectangle the renderer knows it drew into
//!   (`active10rect`, `composite::reduce_bounded`, as IceT's bounding boxes);
//! * the same dense and 10%-active images with direct send and radix-k (k = 4; at 4
//!   ranks it has one round of 4 and is direct send; at 8, rounds of 4 and 2).
//!
//! The 10%-active image is one compact blob: a centred rectangle of 10% of the pixels
//! (sqrt(0.1) of the width by sqrt(0.1) of the height), every pixel inside active with
//! hashed depths, background outside, the same rectangle on every rank.
//!
//! Every repetition runs the round exchanges and every composite back to back, in a
//! rotating order (so that all see the same machine load); the first repetition is a
//! warm-up.
//! Times are the slowest rank's, each started after a barrier; medians (and minima) over
//! the repetitions. Rank 0 prints `RESULT key=value ...` and `PROFILE ...` lines (the
//! median time of each step on each rank).

use irradia_parallel::comm::{Comm, MpiComm};
use irradia_parallel::composite::{
    self, active, depth, pairwise, profile, rle, split_span, ActiveRect, CompositeOptions, Layer,
    Operator, Strategy,
};
use std::time::{Duration, Instant};

fn arg(name: &str, default: usize) -> usize {
    let a: Vec<String> = std::env::args().collect();
    a.iter()
        .position(|x| x == name)
        .and_then(|i| a.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn hash(i: u64) -> u32 {
    let mut z = i.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    (z ^ (z >> 31)) as u32
}

/// The centred rectangle covering `fraction` of a `w` x `h` screen.
fn blob(w: u32, h: u32, fraction: f64) -> ActiveRect {
    let s = fraction.sqrt();
    let (rw, rh) = ((w as f64 * s) as u32, (h as f64 * s) as u32);
    let (x0, y0) = ((w - rw) / 2, (h - rh) / 2);
    ActiveRect {
        x0,
        y0,
        x1: x0 + rw,
        y1: y0 + rh,
    }
}

/// A layer whose pixels are active inside a centred rectangle covering `fraction`.
fn layer(w: u32, h: u32, rank: usize, fraction: f64) -> Layer<[u8; 4]> {
    let mut l = Layer::<[u8; 4]>::new(w, h);
    let ActiveRect { x0, y0, x1, y1 } = blob(w, h, fraction);
    let (rw, rh) = (x1 - x0, y1 - y0);
    for y in y0..y0 + rh {
        for x in x0..x0 + rw {
            let i = (y * w + x) as usize;
            let v = hash(i as u64 ^ ((rank as u64) << 40));
            l.color[i] = v.to_le_bytes();
            l.color[i][3] = 255;
            l.depth[i] = (v >> 8) as f32 / (1u32 << 24) as f32;
        }
    }
    l
}

fn slowest<C: Comm>(c: &C, t: f64) -> f64 {
    let all = c
        .gather(0, &t.to_le_bytes())
        .unwrap_or_else(|_| std::process::exit(3));
    all.iter()
        .map(|b| f64::from_le_bytes(b[..8].try_into().unwrap()))
        .fold(0.0, f64::max)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// Each step's median over the repetitions (robust to a rank being descheduled).
fn median_profile(v: &[profile::SwapProfile]) -> profile::SwapProfile {
    let m = |f: fn(&profile::SwapProfile) -> f64| median(v.iter().map(f).collect());
    profile::SwapProfile {
        swaps: v[0].swaps,
        rle_swaps: v[0].rle_swaps,
        bytes_sent: v[0].bytes_sent,
        decide_s: m(|p| p.decide_s),
        header_s: m(|p| p.header_s),
        encode_s: m(|p| p.encode_s),
        wait_s: m(|p| p.wait_s),
        blend_s: m(|p| p.blend_s),
    }
}

fn min(v: &[f64]) -> f64 {
    v.iter().cloned().fold(f64::INFINITY, f64::min)
}

/// The largest give span (pixels) of any rank in each binary-swap round, for a power of
/// two `p` and an image of `n` pixels, computed as `binary_swap` splits its spans.
fn round_give_pixels(n: usize, p: usize) -> Vec<usize> {
    let mut most = Vec::new();
    let mut spans = vec![0..n; p];
    let mut bit = 1;
    while bit < p {
        let mut m = 0;
        for (v, span) in spans.iter_mut().enumerate() {
            let halves = split_span(span, 2);
            let (keep, give) = if v & bit == 0 {
                (halves[0].clone(), halves[1].clone())
            } else {
                (halves[1].clone(), halves[0].clone())
            };
            m = m.max(give.len());
            *span = keep;
        }
        most.push(m);
        bit <<= 1;
    }
    most
}

/// One timed composite: a strategy, an image, and whether the renderer's rectangle is
/// passed.
struct Case {
    name: &'static str,
    strategy: Strategy,
    fraction: f64,
    rect: bool,
}

/// Median and minimum seconds of `f` over `reps` calls (after one warm-up).
fn time_it(reps: usize, mut f: impl FnMut()) -> (f64, f64) {
    f();
    let v: Vec<f64> = (0..reps)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .collect();
    (median(v.clone()), min(&v))
}

/// Session 2's run search, kept here only to compare with [`active`]: blocks of 64
/// depths are tested by counting the infinite ones, and the block where a run ends is
/// walked pixel by pixel.
mod session2_scan {
    const FAR_BITS: u32 = f32::INFINITY.to_bits();
    const BLOCK: usize = 64;

    #[inline(always)]
    fn far_count(d: &[f32]) -> u32 {
        d.iter()
            .fold(0u32, |n, &x| n + (x.to_bits() == FAR_BITS) as u32)
    }

    #[inline(always)]
    fn run_end_impl(d: &[f32], from: usize, end: usize, active: bool) -> usize {
        let uniform = if active { 0 } else { BLOCK as u32 };
        let mut i = from;
        while i + BLOCK <= end && far_count(&d[i..i + BLOCK]) == uniform {
            i += BLOCK;
        }
        while i < end && (d[i].to_bits() != FAR_BITS) == active {
            i += 1;
        }
        i
    }

    #[inline(always)]
    fn trim_back_impl(d: &[f32], a: usize, end: usize) -> usize {
        let mut b = end;
        while b >= a + BLOCK && far_count(&d[b - BLOCK..b]) == BLOCK as u32 {
            b -= BLOCK;
        }
        while b > a && d[b - 1].to_bits() == FAR_BITS {
            b -= 1;
        }
        b
    }

    #[inline(always)]
    fn prepare_impl(d: &[f32], c: &[[u8; 4]], span: std::ops::Range<usize>, out: &mut Vec<u8>) {
        let a = run_end_impl(d, span.start, span.end, false);
        let b = if a == span.end {
            a
        } else {
            trim_back_impl(d, a, span.end)
        };
        let n = b - a;
        for k in 0..4 {
            let (s, e) = (a + n * k / 4, a + n * (k + 1) / 4);
            out.extend_from_slice(bytemuck::cast_slice(&[s as u32, e as u32, 1u32]));
            let mut i = s;
            while i < e {
                let a0 = run_end_impl(d, i, e, false);
                let a1 = run_end_impl(d, a0, e, true);
                out.extend_from_slice(bytemuck::cast_slice(&[(a0 - i) as u32, (a1 - a0) as u32]));
                out.extend_from_slice(bytemuck::cast_slice(&c[a0..a1]));
                out.extend_from_slice(bytemuck::cast_slice(&d[a0..a1]));
                i = a1;
            }
        }
    }

    #[target_feature(enable = "avx2")]
    unsafe fn prepare_avx2(
        d: &[f32],
        c: &[[u8; 4]],
        span: std::ops::Range<usize>,
        out: &mut Vec<u8>,
    ) {
        prepare_impl(d, c, span, out)
    }

    /// Trim + 4 run-length pieces of `span`, as session 2 did it.
    pub fn prepare(d: &[f32], c: &[[u8; 4]], span: std::ops::Range<usize>, out: &mut Vec<u8>) {
        assert!(std::arch::is_x86_feature_detected!("avx2"));
        // SAFETY: AVX2 is present (asserted).
        unsafe { prepare_avx2(d, c, span, out) }
    }
}

/// `--kernels`: the single-process cost of the compositing kernels on rank 0's images
/// (no messages): the z-test of half a dense image, and preparing the sparse half
/// (trim + run-length encoding) found by scanning or given the rectangle.
fn kernels(w: u32, h: u32, reps: usize) {
    let n = w as usize * h as usize;
    let (half, other) = (n / 2..n, 0..n / 2);
    let dense = layer(w, h, 0, 1.0);
    let incoming = layer(w, h, 1, 1.0);
    let mut acc = dense.clone();
    let (c_in, d_in) = (
        &incoming.color[other.clone()],
        &incoming.depth[other.clone()],
    );
    let (t, tmin) = time_it(reps, || {
        acc.color[..n / 2].copy_from_slice(&dense.color[..n / 2]);
        acc.depth[..n / 2].copy_from_slice(&dense.depth[..n / 2]);
    });
    let (b, bmin) = time_it(reps, || {
        acc.color[..n / 2].copy_from_slice(&dense.color[..n / 2]);
        acc.depth[..n / 2].copy_from_slice(&dense.depth[..n / 2]);
        depth::blend(
            &mut acc.color[..n / 2],
            &mut acc.depth[..n / 2],
            c_in,
            d_in,
            false,
        );
    });
    println!(
        "KERNEL name=blend_half_dense pixels={} median_ms={:.3} min_ms={:.3} (copy-back subtracted: {:.3} / {:.3})",
        n / 2,
        b * 1e3,
        bmin * 1e3,
        t * 1e3,
        tmin * 1e3
    );
    let sparse = layer(w, h, 0, 0.1);
    let full = ActiveRect::full(w, h);
    let rect = blob(w, h, 0.1);
    let mut out = Vec::new();
    let (m, mn) = time_it(reps, || {
        out.clear();
        session2_scan::prepare(&sparse.depth, &sparse.color, half.clone(), &mut out);
        std::hint::black_box(&out);
    });
    println!(
        "KERNEL name=prepare_sparse_half_session2_scan bytes={} median_ms={:.3} min_ms={:.3}",
        out.len(),
        m * 1e3,
        mn * 1e3
    );
    for (name, r) in [("scan", full), ("rect", rect)] {
        let (m, mn) = time_it(reps, || {
            let t = active::trim_in(&sparse, Operator::Depth, &half, &r);
            out.clear();
            for part in split_span(&t, 4) {
                rle::encode_runs_into(&mut out, &sparse, part, Operator::Depth, &r);
            }
            std::hint::black_box(&out);
        });
        println!(
            "KERNEL name=prepare_sparse_half_{name} bytes={} median_ms={:.3} min_ms={:.3}",
            out.len(),
            m * 1e3,
            mn * 1e3
        );
    }
}

fn main() {
    if std::env::args().any(|a| a == "--kernels") {
        let reps = arg("--reps", 201);
        return kernels(
            arg("--width", 1280) as u32,
            arg("--height", 720) as u32,
            reps,
        );
    }
    let comm = MpiComm::init(Duration::from_secs(60)).expect("MPI initialises once");
    let (w, h, reps, pieces) = (
        arg("--width", 1280) as u32,
        arg("--height", 720) as u32,
        arg("--reps", 9),
        arg("--pieces", 4),
    );
    pairwise::set_max_pieces(pieces);
    let (rank, p) = (comm.rank(), comm.size());
    let pixels = w as usize * h as usize;
    let pixel_bytes = 8; // RGBA8 + f32 depth
    let ok = |r: Result<(), _>| r.unwrap_or_else(|e| comm.fail(&e));

    let rounds = if p.is_power_of_two() {
        round_give_pixels(pixels, p)
    } else {
        Vec::new() // the bound is defined for powers of two only
    };
    let mut buffers: Vec<(Vec<u8>, Vec<u8>)> = rounds
        .iter()
        .map(|g| (vec![0x5au8; g * pixel_bytes], vec![0u8; g * pixel_bytes]))
        .collect();
    let bs = Strategy::BinarySwap;
    let mut cases = vec![
        Case {
            name: "dense",
            strategy: bs,
            fraction: 1.0,
            rect: false,
        },
        Case {
            name: "active10",
            strategy: bs,
            fraction: 0.1,
            rect: false,
        },
        Case {
            name: "active10rect",
            strategy: bs,
            fraction: 0.1,
            rect: true,
        },
    ];
    if p > 1 {
        for strategy in [Strategy::DirectSend, Strategy::RadixK(4)] {
            cases.push(Case {
                name: "dense",
                strategy,
                fraction: 1.0,
                rect: false,
            });
            cases.push(Case {
                name: "active10",
                strategy,
                fraction: 0.1,
                rect: false,
            });
        }
    }
    let dense = layer(w, h, rank, 1.0);
    let sparse = layer(w, h, rank, 0.1);
    let opts = CompositeOptions::default();
    let mut exchange_times = vec![Vec::new(); rounds.len()];
    let mut times = vec![Vec::new(); cases.len()];
    let mut steps = vec![Vec::new(); cases.len()];
    // Every measurement takes its turn at being first, so that none of them always runs
    // right after the longest one (on a loaded machine a rank that has just used its
    // time slice is the likeliest to be descheduled).
    let m = cases.len() + 1;
    for rep in 0..reps + 1 {
        let keep = rep > 0; // the first repetition warms up
        for k in 0..m {
            match (rep + k) % m {
                0 => {
                    for (r, (send, recv)) in buffers.iter_mut().enumerate() {
                        ok(comm.barrier());
                        let t0 = Instant::now();
                        ok(comm.exchange_pieces(
                            rank ^ (1 << r),
                            0x7000 + r as u32,
                            &[send],
                            &mut [recv],
                            &mut |_, _| Ok(()),
                        ));
                        let t = slowest(&comm, t0.elapsed().as_secs_f64());
                        if keep {
                            exchange_times[r].push(t);
                        }
                    }
                }
                c => {
                    let c = c - 1;
                    let case = &cases[c];
                    let l = if case.fraction < 1.0 {
                        sparse.clone()
                    } else {
                        dense.clone()
                    };
                    let rect = if case.rect {
                        blob(w, h, case.fraction)
                    } else {
                        ActiveRect::full(w, h)
                    };
                    ok(comm.barrier());
                    profile::take();
                    let t0 = Instant::now();
                    let (out, span) =
                        composite::reduce_bounded(&comm, case.strategy, l, rect, &opts)
                            .unwrap_or_else(|e| comm.fail(&e));
                    let t = t0.elapsed().as_secs_f64();
                    // Nobody starts the next case's set-up (a 7 MB layer copy) while a
                    // slower rank is still compositing: with more ranks than cores that
                    // copy would take the slower rank's core and be timed as its work.
                    ok(comm.barrier());
                    let step = profile::take();
                    std::hint::black_box((out, span));
                    let t = slowest(&comm, t);
                    if keep {
                        times[c].push(t);
                        steps[c].push(step);
                    }
                }
            }
        }
    }
    let (mut bound, mut bound_min) = (0.0, 0.0);
    let mut round_lines = Vec::new();
    for (r, ts) in exchange_times.iter().enumerate() {
        let bytes = rounds[r] * pixel_bytes;
        let (t, fastest) = (median(ts.clone()), min(ts));
        bound += t;
        bound_min += fastest;
        round_lines.push(format!(
            "RESULT np={p} swap_round={} bytes={bytes} exchange_ms={:.3} exchange_gbps={:.3} exchange_min_ms={:.3}",
            r + 1,
            t * 1e3,
            bytes as f64 / t / 1e9,
            fastest * 1e3
        ));
    }

    // Per-rank step times (medians over the repetitions) to rank 0.
    for (case, st) in cases.iter().zip(&steps) {
        let prof = median_profile(st);
        let k = 1e-3;
        let line = format!(
            "PROFILE np={p} strategy={} case={} rank={rank} swaps={} rle_swaps={} bytes_sent={} decide_ms={:.3} header_ms={:.3} encode_ms={:.3} wait_ms={:.3} blend_ms={:.3}",
            case.strategy.name(),
            case.name,
            prof.swaps,
            prof.rle_swaps,
            prof.bytes_sent,
            prof.decide_s / k,
            prof.header_s / k,
            prof.encode_s / k,
            prof.wait_s / k,
            prof.blend_s / k,
        );
        let all = comm
            .gather(0, line.as_bytes())
            .unwrap_or_else(|e| comm.fail(&e));
        if rank == 0 {
            for l in all {
                println!("{}", String::from_utf8_lossy(&l));
            }
        }
    }
    if rank == 0 {
        for l in &round_lines {
            println!("{l}");
        }
        println!(
            "RESULT np={p} width={w} height={h} pieces={pieces} bound_ms={:.3} bound_min_ms={:.3}",
            bound * 1e3,
            bound_min * 1e3
        );
        for (case, ts) in cases.iter().zip(&times) {
            let (t, fastest) = (median(ts.clone()), min(ts));
            println!(
                "RESULT np={p} strategy={} case={} median_ms={:.3} over_bound={:.2} min_ms={:.3} min_over_bound_min={:.2}",
                case.strategy.name(),
                case.name,
                t * 1e3,
                t / bound,
                fastest * 1e3,
                fastest / bound_min
            );
        }
    }
}
