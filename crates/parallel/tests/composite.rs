//! Sort-last compositing over `LocalComm`: every strategy, 1 to 16 ranks, equals the
//! serial render bit for bit (opaque), and ordered "over" equals the serial composite
//! of the same partition (transparent) while rank order does not.

mod common;

use common::*;
use irradia_core::Vec3;
use irradia_parallel::comm::{run_local, LocalOptions};
use irradia_parallel::composite::{
    self, over::SpatialSplit, rle, CompositeOptions, Layer, Operator, Strategy,
};

const STRATEGIES: [Strategy; 7] = [
    Strategy::DirectSend,
    Strategy::Tree,
    Strategy::BinarySwap,
    Strategy::RadixK(2),
    Strategy::RadixK(3),
    Strategy::RadixK(4),
    Strategy::RadixK(8),
];

fn parallel_opaque<P: TestPixel>(rects: &[Rect], ranks: usize, s: Strategy, rle: bool) -> Layer<P> {
    let opts = CompositeOptions {
        rle,
        ..Default::default()
    };
    let out = run_local(ranks, LocalOptions::default(), |c| {
        use irradia_parallel::comm::Comm;
        let layer = render_opaque::<P>(&block(rects, c.rank(), ranks));
        composite::composite(c, s, layer, &opts).unwrap()
    });
    out.into_iter()
        .next()
        .unwrap()
        .unwrap()
        .expect("rank 0 holds the image")
}

fn check_opaque<P: TestPixel>() {
    let rects = random_rects(40, 11, 255);
    let serial = render_opaque::<P>(&rects.iter().collect::<Vec<_>>());
    assert!(serial.active_fraction(Operator::Depth) > 0.3);
    for ranks in 1..=16 {
        for s in STRATEGIES {
            let par = parallel_opaque::<P>(&rects, ranks, s, true);
            assert!(
                par == serial,
                "{} with {ranks} ranks differs from the serial render",
                s.name()
            );
        }
        let dense = parallel_opaque::<P>(&rects, ranks, Strategy::BinarySwap, false);
        assert!(
            dense == serial,
            "dense binary swap with {ranks} ranks differs"
        );
    }
}

#[test]
fn opaque_rgba8_composite_equals_serial_for_1_to_16_ranks() {
    check_opaque::<[u8; 4]>();
}

#[test]
fn opaque_rgba32f_composite_equals_serial_for_1_to_16_ranks() {
    check_opaque::<[f32; 4]>();
}

#[test]
fn ties_are_broken_like_the_serial_z_buffer() {
    // Two identical rectangles of different colours on different ranks: rank 0 must win.
    let mut a = random_rects(1, 3, 255);
    let mut b = a[0].clone();
    b.rgba = [1, 2, 3, 255];
    a.push(b);
    let serial = render_opaque::<[u8; 4]>(&a.iter().collect::<Vec<_>>());
    for s in STRATEGIES {
        assert!(
            parallel_opaque::<[u8; 4]>(&a, 2, s, true) == serial,
            "{}",
            s.name()
        );
    }
}

fn transparent_scene() -> (Vec<Rect>, Vec<Vec3>) {
    let mut rects = random_rects(48, 5, 140);
    let mut rng = irradia_core::Rng::new(99, 1);
    for r in rects.iter_mut() {
        r.d0 = rng.next_f32() * 10_000.0;
    }
    let centroids = rects
        .iter()
        .map(|r| Vec3::new((r.x0 + r.x1) as f32 / 2.0, (r.y0 + r.y1) as f32 / 2.0, r.d0))
        .collect();
    (rects, centroids)
}

fn transparent_run(
    ranks: usize,
    s: Strategy,
    ordered: bool,
    from_behind: bool,
) -> (Layer<[f32; 4]>, Layer<[f32; 4]>) {
    let (rects, centroids) = transparent_scene();
    let split = SpatialSplit::build(&centroids, ranks);
    let eye_z = if from_behind { 1.0e6 } else { -1.0e6 };
    let order = split.order(Vec3::new(32.0, 24.0, eye_z));
    let mine = |r: usize| -> Vec<&Rect> {
        rects
            .iter()
            .enumerate()
            .filter(|(i, _)| split.owner[*i] == r)
            .map(|(_, x)| x)
            .collect()
    };
    let layers: Vec<Layer<[f32; 4]>> = (0..ranks)
        .map(|r| render_transparent(&mine(r), from_behind))
        .collect();
    let serial = composite::serial(&layers, Operator::Over, Some(&order));
    let opts = CompositeOptions {
        op: Operator::Over,
        order: if ordered { Some(order.clone()) } else { None },
        ..Default::default()
    };
    let out = run_local(ranks, LocalOptions::default(), |c| {
        use irradia_parallel::comm::Comm;
        composite::composite(c, s, layers[c.rank()].clone(), &opts).unwrap()
    });
    (out.into_iter().next().unwrap().unwrap().unwrap(), serial)
}

fn max_diff(a: &Layer<[f32; 4]>, b: &Layer<[f32; 4]>) -> f32 {
    a.color
        .iter()
        .zip(&b.color)
        .flat_map(|(x, y)| (0..4).map(move |k| (x[k] - y[k]).abs()))
        .fold(0.0, f32::max)
}

#[test]
fn ordered_over_equals_serial_and_unordered_differs() {
    // The spatial split is exact here (objects are thin in z and spread along it), so the
    // serial composite of the partition is also the true depth-sorted image.
    let (rects, _) = transparent_scene();
    for from_behind in [false, true] {
        let truth = render_transparent::<[f32; 4]>(&rects.iter().collect::<Vec<_>>(), from_behind);
        for ranks in [1, 2, 3, 4, 5, 7, 8, 12, 16] {
            for s in STRATEGIES {
                let (par, serial) = transparent_run(ranks, s, true, from_behind);
                let d = max_diff(&par, &serial);
                assert!(d < 1e-5, "{} {ranks} ranks: {d}", s.name());
                assert!(
                    max_diff(&par, &truth) < 1e-5,
                    "{} {ranks} ranks vs depth-sorted truth",
                    s.name()
                );
            }
        }
    }
    // Seen from behind, the visibility order is the reverse of rank order.
    for ranks in [2, 4, 7] {
        let (unordered, serial) = transparent_run(ranks, Strategy::BinarySwap, false, true);
        assert!(
            max_diff(&unordered, &serial) > 0.05,
            "rank-order compositing should be visibly wrong with {ranks} ranks"
        );
    }
}

#[test]
fn rle_round_trip_and_size() {
    let rects = random_rects(6, 21, 255);
    let l = render_opaque::<[u8; 4]>(&rects.iter().collect::<Vec<_>>());
    for (span, op) in [
        (0..l.len(), Operator::Depth),
        (100..2000, Operator::Depth),
        (0..l.len(), Operator::Over),
        (5..5, Operator::Depth),
    ] {
        for dense in [false, true] {
            let buf = rle::encode(&l, span.clone(), op, !dense);
            let back = rle::decode::<[u8; 4]>(W, H, &buf).unwrap();
            for i in 0..l.len() {
                let expect_inside = span.contains(&i) && (dense || op.active(&l, i));
                if expect_inside {
                    assert_eq!(
                        (back.color[i], back.depth[i]),
                        (l.color[i], l.depth[i]),
                        "pixel {i}"
                    );
                } else if !span.contains(&i) {
                    assert_eq!(back.depth[i], f32::INFINITY);
                }
            }
        }
    }
    let active = l.active_fraction(Operator::Depth);
    let rle_len = rle::encode(&l, 0..l.len(), Operator::Depth, true).len();
    let dense_len = rle::encode(&l, 0..l.len(), Operator::Depth, false).len();
    assert!(
        (rle_len as f64) < dense_len as f64 * (active + 0.1),
        "rle {rle_len} dense {dense_len} active {active}"
    );
    // Truncated and malformed messages are errors, not panics.
    let buf = rle::encode(&l, 0..l.len(), Operator::Depth, true);
    assert!(rle::decode::<[u8; 4]>(W, H, &buf[..buf.len() - 4]).is_err());
    assert!(rle::decode::<[u8; 4]>(W / 2, H, &buf).is_err());
}

/// Layers of 256x64 where the top half is dense (hashed, quantised depths: ties happen)
/// and the bottom half sparse (every seventh pixel), so that binary swap's pairwise
/// swaps send some spans dense in several pieces and others as run lengths.
fn mixed_layer(rank: usize) -> Layer<[u8; 4]> {
    let (w, h) = (256u32, 64u32);
    let mut l = Layer::<[u8; 4]>::new(w, h);
    let n = l.len();
    for i in 0..n {
        let v = (i as u64 ^ ((rank as u64) << 32)).wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 40;
        if i < n / 2 || (i + rank).is_multiple_of(7) {
            l.color[i] = [(v & 255) as u8, (v >> 8) as u8, rank as u8, 255];
            l.depth[i] = ((v >> 16) % 16) as f32 * 0.25;
        }
    }
    l
}

#[test]
fn binary_swap_mixes_dense_pieces_and_run_lengths_and_equals_serial() {
    use irradia_parallel::comm::Comm;
    use irradia_parallel::composite::profile;
    for ranks in 2..=8 {
        let layers: Vec<_> = (0..ranks).map(mixed_layer).collect();
        let serial = composite::serial(&layers, Operator::Depth, None);
        for rle in [true, false] {
            let opts = CompositeOptions {
                rle,
                ..Default::default()
            };
            let out = run_local(ranks, LocalOptions::default(), |c| {
                profile::take();
                let img =
                    composite::composite(c, Strategy::BinarySwap, mixed_layer(c.rank()), &opts)
                        .unwrap();
                (img, profile::take())
            });
            let out: Vec<_> = out.into_iter().map(|o| o.unwrap()).collect();
            assert!(
                out[0].0.as_ref().unwrap() == &serial,
                "{ranks} ranks, rle {rle}: differs from the serial composite"
            );
            let swaps: u32 = out.iter().map(|o| o.1.swaps).sum();
            let runs: u32 = out.iter().map(|o| o.1.rle_swaps).sum();
            assert!(swaps > 0);
            if rle {
                assert!(
                    runs > 0 && runs < swaps,
                    "{ranks} ranks: {runs} of {swaps} swaps sent runs"
                );
            } else {
                assert_eq!(runs, 0);
            }
        }
    }
}

#[test]
fn composite_from_reads_the_layer_in_place_and_equals_serial() {
    use irradia_parallel::comm::Comm;
    use irradia_parallel::composite::ActiveRect;
    // The working layer starts as junk of another size (depth 0 wins every z-test, so a
    // pixel read from it instead of the source shows), and is reused for a second frame.
    let junk = || Layer {
        width: 3,
        height: 5,
        color: vec![[7u8; 4]; 15],
        depth: vec![0.0; 15],
    };
    for ranks in 1..=8 {
        let layers: Vec<_> = (0..ranks).map(mixed_layer).collect();
        let serial = composite::serial(&layers, Operator::Depth, None);
        for s in STRATEGIES {
            for rle in [true, false] {
                let opts = CompositeOptions {
                    rle,
                    ..Default::default()
                };
                let out = run_local(ranks, LocalOptions::default(), |c| {
                    let src = mixed_layer(c.rank());
                    let rect = ActiveRect::full(src.width, src.height);
                    let mut work = junk();
                    let mut images = Vec::new();
                    for _ in 0..2 {
                        let mut oc = vec![[9u8; 4]; src.len()];
                        let mut od = vec![-1.0f32; src.len()];
                        let root = c.rank() == 0;
                        let (w, wrote) = composite::composite_from(
                            c,
                            s,
                            src.view(),
                            work,
                            rect,
                            &opts,
                            root.then_some((&mut oc[..], &mut od[..])),
                        )
                        .unwrap();
                        assert_eq!(wrote, root);
                        work = w;
                        work.color.iter_mut().for_each(|p| *p = [7; 4]);
                        work.depth.iter_mut().for_each(|d| *d = 0.0);
                        images.push((oc, od));
                    }
                    images
                });
                let images = out.into_iter().next().unwrap().unwrap();
                for (oc, od) in images {
                    assert!(
                        oc == serial.color && od == serial.depth,
                        "{} with {ranks} ranks, rle {rle}: differs from the serial composite",
                        s.name()
                    );
                }
            }
        }
    }
}

/// Even ranks dense (hashed, quantised depths: ties happen), odd ranks sparse (every
/// fifth pixel): in a direct-send or radix-k round a rank receives dense spans from some
/// sources and run lengths from others, which must still be composited in order.
fn alternating_layer(rank: usize) -> Layer<[u8; 4]> {
    let mut l = Layer::<[u8; 4]>::new(96, 40);
    for i in 0..l.len() {
        let v = (i as u64 ^ ((rank as u64) << 32)).wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 40;
        if rank.is_multiple_of(2) || (i + rank).is_multiple_of(5) {
            l.color[i] = [(v & 255) as u8, (v >> 8) as u8, rank as u8, 255];
            l.depth[i] = ((v >> 16) % 8) as f32 * 0.5;
        }
    }
    l
}

#[test]
fn dense_sources_and_run_lengths_inline_or_in_pieces_composite_in_order() {
    use irradia_parallel::comm::Comm;
    use irradia_parallel::composite::{pairwise, profile};
    for ranks in 2..=7 {
        let layers: Vec<_> = (0..ranks).map(alternating_layer).collect();
        let serial = composite::serial(&layers, Operator::Depth, None);
        for strategy in [
            Strategy::DirectSend,
            Strategy::RadixK(3),
            Strategy::RadixK(4),
            Strategy::BinarySwap,
            Strategy::Tree,
        ] {
            // Run lengths inline with the header (the default), or all sent as pieces.
            for inline_max in [pairwise::INLINE_MAX, 0] {
                let out = run_local(ranks, LocalOptions::default(), |c| {
                    pairwise::set_inline_max(inline_max);
                    profile::take();
                    let l = alternating_layer(c.rank());
                    let img = composite::composite(c, strategy, l, &Default::default()).unwrap();
                    (img, profile::take())
                });
                let out: Vec<_> = out.into_iter().map(|o| o.unwrap()).collect();
                assert!(
                    out[0].0.as_ref().unwrap() == &serial,
                    "{ranks} ranks, {strategy:?}, inline up to {inline_max} bytes: differs from serial"
                );
                // The odd ranks' sparse spans went as run lengths (the even ranks' are
                // dense by construction).
                let runs: u32 = out.iter().map(|o| o.1.rle_swaps).sum();
                assert!(runs > 0, "{ranks} ranks {strategy:?}: no run lengths sent");
            }
        }
    }
}

/// A 256x64 layer whose active pixels lie in a rank-dependent rectangle: solid rows
/// (runs that cross the pairwise pieces' boundaries and the parts of every strategy)
/// with hashed, quantised depths (ties happen), and every fifth pixel of its lower part.
fn blob_layer(rank: usize) -> Layer<[u8; 4]> {
    let (w, h) = (256u32, 64u32);
    let mut l = Layer::<[u8; 4]>::new(w, h);
    let x0 = (rank * 37) % 200;
    let y0 = (rank * 11) % 40;
    let (x1, y1) = (x0 + 20 + (rank * 13) % 37, y0 + 8 + rank % 17);
    for y in y0..y1.min(h as usize) {
        for x in x0..x1 {
            let i = y * w as usize + x;
            let v = (i as u64 ^ ((rank as u64) << 32)).wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 40;
            if y < y0 + 5 || (i + rank).is_multiple_of(5) || x == x0 || x + 1 == x1 {
                l.color[i] = [(v & 255) as u8, (v >> 8) as u8, rank as u8, 255];
                l.depth[i] = ((v >> 16) % 8) as f32 * 0.25;
            }
        }
    }
    l
}

#[test]
fn every_strategy_with_active_rectangles_equals_serial() {
    use irradia_parallel::comm::Comm;
    use irradia_parallel::composite::ActiveRect;
    for ranks in 1..=9 {
        let layers: Vec<_> = (0..ranks).map(blob_layer).collect();
        let serial = composite::serial(&layers, Operator::Depth, None);
        for s in STRATEGIES {
            for (rle, tight) in [(true, true), (true, false), (false, true)] {
                let opts = CompositeOptions {
                    rle,
                    ..Default::default()
                };
                let out = run_local(ranks, LocalOptions::default(), |c| {
                    let l = blob_layer(c.rank());
                    let rect = if tight {
                        ActiveRect::of_layer(&l, Operator::Depth)
                    } else {
                        ActiveRect::full(l.width, l.height)
                    };
                    composite::composite_bounded(c, s, l, rect, &opts).unwrap()
                });
                let img = out.into_iter().next().unwrap().unwrap().unwrap();
                assert!(
                    img == serial,
                    "{} with {ranks} ranks (rle {rle}, tight rectangles {tight}) differs",
                    s.name()
                );
            }
        }
    }
}

/// The rectangle is a promise all the way to the final image: decoy pixels that a rank
/// leaves outside its rectangle (and outside every other rank's) are never read, in the
/// reduce steps nor in the final gather, whichever rank ends up owning them.
#[test]
fn pixels_outside_every_rectangle_never_reach_the_image() {
    use irradia_parallel::comm::Comm;
    use irradia_parallel::composite::ActiveRect;
    for ranks in 1..=5 {
        let layers: Vec<_> = (0..ranks).map(blob_layer).collect();
        let serial = composite::serial(&layers, Operator::Depth, None);
        let rects: Vec<_> = layers
            .iter()
            .map(|l| ActiveRect::of_layer(l, Operator::Depth))
            .collect();
        let union = rects.iter().fold(ActiveRect::EMPTY, |u, r| u.union(r));
        assert!(union.x1 < 230 && union.y1 < 58, "{union:?}");
        for s in STRATEGIES {
            for root in [0, ranks - 1] {
                let opts = CompositeOptions {
                    root,
                    ..Default::default()
                };
                let out = run_local(ranks, LocalOptions::default(), |c| {
                    let mut l = blob_layer(c.rank());
                    // Decoys in the bottom-right corner, a few per rank.
                    for k in 0..4 {
                        let i = (58 + k) * 256 + 230 + 5 * c.rank();
                        l.color[i] = [255, 0, 255, 255];
                        l.depth[i] = 0.0;
                    }
                    composite::composite_bounded(c, s, l, rects[c.rank()], &opts).unwrap()
                });
                let img = out.into_iter().nth(root).unwrap().unwrap().unwrap();
                assert!(
                    img == serial,
                    "{} with {ranks} ranks, root {root}: a pixel outside the rectangles arrived",
                    s.name()
                );
            }
        }
    }
}

#[test]
fn an_empty_active_rectangle_sends_nothing_and_still_composites() {
    use irradia_parallel::comm::Comm;
    use irradia_parallel::composite::ActiveRect;
    // odd ranks drew nothing and say so; the composite is the even ranks' image
    let ranks = 6;
    let layers: Vec<_> = (0..ranks)
        .map(|r| {
            if r % 2 == 0 {
                blob_layer(r)
            } else {
                Layer::new(256, 64)
            }
        })
        .collect();
    let serial = composite::serial(&layers, Operator::Depth, None);
    for s in STRATEGIES {
        let out = run_local(ranks, LocalOptions::default(), |c| {
            let l = layers[c.rank()].clone();
            let rect = ActiveRect::of_layer(&l, Operator::Depth);
            assert_eq!(rect.is_empty(), c.rank() % 2 == 1);
            composite::composite_bounded(c, s, l, rect, &CompositeOptions::default()).unwrap()
        });
        let img = out.into_iter().next().unwrap().unwrap().unwrap();
        assert!(img == serial, "{} differs", s.name());
    }
}

#[test]
fn ordered_over_with_active_rectangles_equals_the_unbounded_composite() {
    use irradia_parallel::comm::Comm;
    use irradia_parallel::composite::ActiveRect;
    let (rects, centroids) = transparent_scene();
    for ranks in [2, 3, 5, 8] {
        let split = SpatialSplit::build(&centroids, ranks);
        let order = split.order(Vec3::new(32.0, 24.0, -1.0e6));
        let layers: Vec<Layer<[f32; 4]>> = (0..ranks)
            .map(|r| {
                let mine: Vec<&Rect> = rects
                    .iter()
                    .enumerate()
                    .filter(|(i, _)| split.owner[*i] == r)
                    .map(|(_, x)| x)
                    .collect();
                render_transparent(&mine, false)
            })
            .collect();
        let opts = CompositeOptions {
            op: Operator::Over,
            order: Some(order.clone()),
            ..Default::default()
        };
        for s in STRATEGIES {
            let out = run_local(ranks, LocalOptions::default(), |c| {
                let l = layers[c.rank()].clone();
                let rect = ActiveRect::of_layer(&l, Operator::Over);
                let bounded = composite::composite_bounded(c, s, l.clone(), rect, &opts).unwrap();
                let plain = composite::composite(c, s, l, &opts).unwrap();
                (bounded, plain)
            });
            let (bounded, plain) = out.into_iter().next().unwrap().unwrap();
            assert!(
                bounded.unwrap() == plain.unwrap(),
                "{} with {ranks} ranks: the rectangles changed the image",
                s.name()
            );
        }
    }
}
