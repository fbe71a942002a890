//! The compositing tests over MPI: run under `mpirun -np N` (scripts/test-mpi.sh does it
//! for N = 1..16). Every rank renders its share of a deterministic scene of rectangles,
//! every strategy composites with `MpiComm`, and rank 0 compares with the serial render
//! (bit for bit for opaque depth compositing; within 1e-5 for ordered "over"); on a
//! tiled display every display rank compares its tile. Prints one
//! line per case and a closing `N passed, N failed`; exits 1 on any failure.

use irradia_parallel::comm::{Comm, MpiComm};
use irradia_parallel::composite::active::ActiveRect;
use irradia_parallel::composite::{self, pairwise, CompositeOptions, Layer, Operator, Strategy};
use irradia_parallel::display_tiles::{composite_to_tiles, DisplayLayout};
use std::time::Duration;

const W: u32 = 64;
const H: u32 = 48;

/// A splitmix-style hash for deterministic scene generation on every rank.
fn h(i: u64) -> f32 {
    let mut z = i.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
}

#[derive(Clone, Copy)]
struct Rect {
    x0: u32,
    y0: u32,
    x1: u32,
    y1: u32,
    d0: f32,
    dx: f32,
    rgba: [f32; 4],
}

fn rects(n: usize, alpha: f32) -> Vec<Rect> {
    (0..n as u64)
        .map(|i| {
            let x0 = (h(i * 8) * (W - 8) as f32) as u32;
            let y0 = (h(i * 8 + 1) * (H - 8) as f32) as u32;
            Rect {
                x0,
                y0,
                x1: (x0 + 4 + (h(i * 8 + 2) * 30.0) as u32).min(W),
                y1: (y0 + 4 + (h(i * 8 + 3) * 24.0) as u32).min(H),
                // quantised depths: ties between ranks happen
                d0: if alpha < 1.0 {
                    i as f32 * 10.0
                } else {
                    1.0 + (h(i * 8 + 4) * 8.0).floor()
                },
                dx: if alpha < 1.0 {
                    0.0
                } else {
                    0.25 * ((h(i * 8 + 5) * 3.0).floor() - 1.0)
                },
                rgba: [
                    h(i * 8 + 6) * alpha,
                    h(i * 8 + 7) * alpha,
                    0.5 * alpha,
                    alpha,
                ],
            }
        })
        .collect()
}

fn render<P: composite::Pixel>(
    rs: &[Rect],
    to_pixel: impl Fn([f32; 4]) -> P,
    over: bool,
) -> Layer<P> {
    let mut l = Layer::<P>::new(W, H);
    for r in rs {
        for y in r.y0..r.y1 {
            for x in r.x0..r.x1 {
                let i = (y * W + x) as usize;
                let d = r.d0 + r.dx * (x - r.x0) as f32;
                if over {
                    // objects arrive in increasing depth: front to back
                    l.color[i] = P::over(l.color[i], to_pixel(r.rgba));
                    l.depth[i] = l.depth[i].min(d);
                } else if d < l.depth[i] {
                    l.depth[i] = d;
                    l.color[i] = to_pixel(r.rgba);
                }
            }
        }
    }
    l
}

/// Counts and prints the checks (on rank 0).
#[derive(Default)]
struct Tally {
    passed: usize,
    failed: usize,
}

impl Tally {
    fn record(&mut self, ok: bool, line: String) {
        println!("{} {line}", if ok { "ok  " } else { "FAIL" });
        if ok {
            self.passed += 1;
        } else {
            self.failed += 1;
        }
    }
}

fn to8(c: [f32; 4]) -> [u8; 4] {
    c.map(|v| (v * 255.0).round() as u8)
}

fn main() {
    let comm = MpiComm::init(Duration::from_secs(20)).expect("MPI initialises once");
    let (rank, p) = (comm.rank(), comm.size());
    let mut tally = Tally::default();
    let opaque = rects(40, 1.0);
    let transparent = rects(48, 0.55);
    let block =
        |v: &[Rect], r: usize| -> Vec<usize> { (v.len() * r / p..v.len() * (r + 1) / p).collect() };
    let pick =
        |v: &[Rect], idx: Vec<usize>| -> Vec<Rect> { idx.into_iter().map(|i| v[i]).collect() };
    let strategies = [
        Strategy::DirectSend,
        Strategy::Tree,
        Strategy::BinarySwap,
        Strategy::RadixK(2),
        Strategy::RadixK(3),
        Strategy::RadixK(4),
        Strategy::RadixK(8),
    ];
    // Opaque, RGBA8 and RGBA32F, against the serial z-buffer of all objects in order.
    let serial8 = render(&opaque, to8, false);
    let serial32 = render(&opaque, |c| c, false);
    // Run lengths inline with their headers (the default), run lengths as pieces after
    // the header, and no run lengths.
    let encodings = [
        (true, pairwise::INLINE_MAX, "inline"),
        (true, 0, "pieces"),
        (false, 0, "off"),
    ];
    for s in strategies {
        for (rle, inline_max, how) in encodings {
            pairwise::set_inline_max(inline_max);
            let opts = CompositeOptions {
                rle,
                ..Default::default()
            };
            let mine8 = render(&pick(&opaque, block(&opaque, rank)), to8, false);
            let got8 =
                composite::composite(&comm, s, mine8, &opts).unwrap_or_else(|e| comm.fail(&e));
            let mine32 = render(&pick(&opaque, block(&opaque, rank)), |c| c, false);
            let got32 =
                composite::composite(&comm, s, mine32, &opts).unwrap_or_else(|e| comm.fail(&e));
            if rank == 0 {
                let ok = got8.as_ref() == Some(&serial8) && got32.as_ref() == Some(&serial32);
                tally.record(
                    ok,
                    format!(
                        "opaque {} rle={how} np={p}: {}",
                        s.name(),
                        if ok { "bit-exact" } else { "differs" }
                    ),
                );
            }
        }
    }
    pairwise::set_inline_max(pairwise::INLINE_MAX);
    // Each rank's active rectangle (the union of its rectangles) handed to the
    // compositor: pixels outside it are never read.
    for s in strategies {
        let mine = pick(&opaque, block(&opaque, rank));
        let rect = mine.iter().fold(ActiveRect::EMPTY, |acc, r| {
            acc.union(&ActiveRect {
                x0: r.x0,
                y0: r.y0,
                x1: r.x1,
                y1: r.y1,
            })
        });
        let got = composite::composite_bounded(
            &comm,
            s,
            render(&mine, to8, false),
            rect,
            &CompositeOptions::default(),
        )
        .unwrap_or_else(|e| comm.fail(&e));
        if rank == 0 {
            let ok = got.as_ref() == Some(&serial8);
            tally.record(
                ok,
                format!(
                    "bounded {} np={p}: {}",
                    s.name(),
                    if ok { "bit-exact" } else { "differs" }
                ),
            );
        }
    }
    // Tiled display: the largest grid of at most 2x2 that the ranks can drive, with
    // overlap; every display rank checks its tile against the serial image.
    let (cols, rows) = match p {
        1 => (1, 1),
        2 | 3 => (2, 1),
        _ => (2, 2),
    };
    let layout = DisplayLayout::grid(W, H, cols, rows, 3).expect("grid fits");
    for s in strategies {
        let mine8 = render(&pick(&opaque, block(&opaque, rank)), to8, false);
        let tile = composite_to_tiles(&comm, s, mine8, &layout, &CompositeOptions::default())
            .unwrap_or_else(|e| comm.fail(&e));
        let ok = match (layout.tile_of(rank), tile) {
            (Some(t), Some(img)) => img == DisplayLayout::crop(&serial8, t),
            (None, None) => true,
            _ => false,
        };
        let all = comm
            .gather(0, &[ok as u8])
            .unwrap_or_else(|e| comm.fail(&e));
        if rank == 0 {
            let bad: Vec<usize> = (0..p).filter(|&r| all[r] != [1]).collect();
            let ok = bad.is_empty();
            tally.record(
                ok,
                format!(
                    "tiles {cols}x{rows} {} np={p}: {}",
                    s.name(),
                    if ok {
                        "every display bit-exact".to_string()
                    } else {
                        format!("ranks {bad:?} differ")
                    }
                ),
            );
        }
    }
    // Transparent: objects sorted by depth, dealt out in blocks, so the visibility order
    // seen from the front is rank order and from behind its reverse.
    for from_behind in [false, true] {
        let order: Vec<usize> = if from_behind {
            (0..p).rev().collect()
        } else {
            (0..p).collect()
        };
        let layer_of = |r: usize| {
            let mut mine = pick(&transparent, block(&transparent, r));
            if from_behind {
                mine.reverse();
            }
            render(&mine, |c| c, true)
        };
        let layers: Vec<Layer<[f32; 4]>> = (0..p).map(layer_of).collect();
        let serial = composite::serial(&layers, Operator::Over, Some(&order));
        for s in strategies {
            let opts = CompositeOptions {
                op: Operator::Over,
                order: Some(order.clone()),
                ..Default::default()
            };
            let got = composite::composite(&comm, s, layers[rank].clone(), &opts)
                .unwrap_or_else(|e| comm.fail(&e));
            if rank == 0 {
                let got = got.expect("rank 0 holds the image");
                let d = got
                    .color
                    .iter()
                    .zip(&serial.color)
                    .flat_map(|(a, b)| (0..4).map(move |k| (a[k] - b[k]).abs()))
                    .fold(0f32, f32::max);
                let ok = d < 1e-5;
                tally.record(
                    ok,
                    format!(
                        "over {} behind={from_behind} np={p}: max diff {d:.2e}",
                        s.name()
                    ),
                );
            }
        }
    }
    if rank == 0 {
        println!("np={p}: {} passed, {} failed", tally.passed, tally.failed);
        if tally.failed > 0 {
            std::process::exit(1);
        }
    }
}
