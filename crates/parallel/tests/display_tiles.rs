//! Compositing onto a tiled display: every display rank receives exactly its rectangle
//! of the serial composite, for every strategy, rank counts 1 to 9, grids with and
//! without overlap, and display ranks that are not the ranks holding the pieces.

mod common;

use common::*;
use irradia_parallel::comm::{run_local, Comm, LocalOptions};
use irradia_parallel::composite::{CompositeOptions, Layer, Operator, Strategy};
use irradia_parallel::display_tiles::{composite_to_tiles, DisplayLayout, DisplayTile};

const STRATEGIES: [Strategy; 5] = [
    Strategy::DirectSend,
    Strategy::Tree,
    Strategy::BinarySwap,
    Strategy::RadixK(3),
    Strategy::RadixK(4),
];

/// Runs the tiled composite; returns each rank's tile (or `None`).
fn tiles_of<P: TestPixel>(
    rects: &[Rect],
    ranks: usize,
    s: Strategy,
    layout: &DisplayLayout,
    rle: bool,
) -> Vec<Option<Layer<P>>> {
    let opts = CompositeOptions {
        rle,
        ..Default::default()
    };
    run_local(ranks, LocalOptions::default(), |c| {
        let layer = render_opaque::<P>(&block(rects, c.rank(), ranks));
        composite_to_tiles(c, s, layer, layout, &opts).unwrap()
    })
    .into_iter()
    .map(|r| r.expect("no rank fails"))
    .collect()
}

fn check<P: TestPixel>(ranks: usize, layout: &DisplayLayout, serial: &Layer<P>, rects: &[Rect]) {
    layout.validate(ranks, W, H).unwrap();
    for s in STRATEGIES {
        for rle in [true, false] {
            let got = tiles_of::<P>(rects, ranks, s, layout, rle);
            for (rank, tile) in got.iter().enumerate() {
                match (layout.tile_of(rank), tile) {
                    (Some(t), Some(img)) => assert!(
                        *img == DisplayLayout::crop(serial, t),
                        "{} (rle {rle}), {ranks} ranks: rank {rank}'s tile {t:?} differs from the serial image",
                        s.name()
                    ),
                    (None, None) => {}
                    (want, have) => panic!(
                        "rank {rank}: expected a tile {want:?}, got one: {}",
                        have.is_some()
                    ),
                }
            }
        }
    }
}

#[test]
fn every_display_gets_its_rectangle_of_the_serial_composite() {
    let rects = random_rects(30, 5, 255);
    let serial = render_opaque::<[u8; 4]>(&rects.iter().collect::<Vec<_>>());
    assert!(serial.active_fraction(Operator::Depth) > 0.3);
    for ranks in 1..=9usize {
        for (cols, rows) in [(1, 1), (2, 1), (1, 2), (2, 2), (3, 3)] {
            if (cols * rows) as usize > ranks {
                continue;
            }
            for overlap in [0, 5] {
                let layout = DisplayLayout::grid(W, H, cols, rows, overlap).unwrap();
                check(ranks, &layout, &serial, &rects);
            }
        }
    }
}

/// With each rank's active rectangle, decoy pixels left outside every rectangle never
/// reach a display (the reduce steps and the delivery to the tiles read inside the
/// rectangles only).
#[test]
fn pixels_outside_every_rectangle_never_reach_a_display() {
    use irradia_parallel::composite::ActiveRect;
    use irradia_parallel::display_tiles::composite_to_tiles_bounded;
    // Everything drawn lies in the top-left 40x30; decoys go in the bottom-right corner.
    let rects: Vec<Rect> = random_rects(20, 9, 255)
        .into_iter()
        .map(|mut r| {
            (r.x1, r.y1) = (r.x1.min(40), r.y1.min(30));
            r
        })
        .filter(|r| r.x0 < r.x1 && r.y0 < r.y1)
        .collect();
    let serial = render_opaque::<[u8; 4]>(&rects.iter().collect::<Vec<_>>());
    for ranks in [1, 2, 3, 4, 6] {
        let (cols, rows) = match ranks {
            1 => (1, 1),
            2 | 3 => (2, 1),
            _ => (2, 2),
        };
        let layout = DisplayLayout::grid(W, H, cols, rows, 4).unwrap();
        for s in STRATEGIES {
            let got = run_local(ranks, LocalOptions::default(), |c| {
                let mut layer = render_opaque::<[u8; 4]>(&block(&rects, c.rank(), ranks));
                let rect = ActiveRect::of_layer(&layer, Operator::Depth);
                for k in 0..4 {
                    let i = (44 + k) as usize * W as usize + 56 + c.rank();
                    layer.color[i] = [255, 0, 255, 255];
                    layer.depth[i] = 0.0;
                }
                let opts = CompositeOptions::default();
                composite_to_tiles_bounded(c, s, layer, rect, &layout, &opts).unwrap()
            });
            for (rank, tile) in got.into_iter().enumerate() {
                if let (Some(t), Some(img)) = (layout.tile_of(rank), tile.unwrap()) {
                    assert!(
                        img == DisplayLayout::crop(&serial, t),
                        "{} with {ranks} ranks: rank {rank}'s tile got a pixel from outside the rectangles",
                        s.name()
                    );
                }
            }
        }
    }
}

#[test]
fn float_pixels_and_display_ranks_at_the_end() {
    let rects = random_rects(25, 9, 255);
    let serial = render_opaque::<[f32; 4]>(&rects.iter().collect::<Vec<_>>());
    // Two overlapping tiles driven by the last two of five ranks.
    let layout = DisplayLayout {
        width: W,
        height: H,
        tiles: vec![
            DisplayTile {
                rank: 4,
                x: 0,
                y: 3,
                width: 40,
                height: 30,
            },
            DisplayTile {
                rank: 3,
                x: 30,
                y: 10,
                width: W - 30,
                height: H - 10,
            },
        ],
    };
    check(5, &layout, &serial, &rects);
}

#[test]
fn a_grid_overlap_widens_inner_edges_only() {
    let l = DisplayLayout::grid(100, 60, 2, 2, 4).unwrap();
    let t: Vec<_> = l
        .tiles
        .iter()
        .map(|t| (t.x, t.y, t.width, t.height))
        .collect();
    assert_eq!(
        t,
        vec![
            (0, 0, 54, 34),
            (46, 0, 54, 34),
            (0, 26, 54, 34),
            (46, 26, 54, 34)
        ]
    );
}

#[test]
fn bad_layouts_are_refused_with_a_reason() {
    let l = DisplayLayout::grid(W, H, 2, 2, 0).unwrap();
    let e = l.validate(3, W, H).unwrap_err();
    assert!(e.contains("rank 3") && e.contains("3 rank"), "{e}");
    let e = l.validate(4, W + 1, H).unwrap_err();
    assert!(e.contains("image"), "{e}");
    let mut twice = l.clone();
    twice.tiles[1].rank = 0;
    assert!(twice
        .validate(4, W, H)
        .unwrap_err()
        .contains("two display tiles"));
    let mut outside = l.clone();
    outside.tiles[3].width += 1;
    assert!(outside.validate(4, W, H).unwrap_err().contains("outside"));
    assert!(DisplayLayout::grid(W, H, 0, 1, 0).is_err());
    assert!(DisplayLayout::grid(4, 4, 5, 1, 0).is_err());
}
