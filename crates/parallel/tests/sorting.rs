//! Sort-first, sort-middle and sort-last over `LocalComm` equal the serial render of the
//! same triangles bit for bit, for the three workloads and several rank counts.

use irradia_parallel::comm::{run_local, LocalOptions};
use irradia_parallel::composite::{self, CompositeOptions, Operator, Strategy};
use irradia_parallel::workload::Workload;
use irradia_parallel::{sort_common, sort_first, sort_last, sort_middle};

const W: u32 = 64;
const H: u32 = 48;

fn workloads() -> Vec<Workload> {
    vec![
        Workload::RandomTriangles {
            count: 600,
            seed: 3,
        },
        Workload::Teapot { level: 3 },
        Workload::MarchingCubes { n: 10 },
    ]
}

#[test]
fn every_sorting_scheme_equals_the_serial_render() {
    for w in workloads() {
        let tris = w.triangles();
        let p = w.pipeline(W, H);
        let serial = sort_common::serial(&p, &tris);
        let covered = serial.active_fraction(Operator::Depth);
        assert!(
            covered > 0.05,
            "{}: only {covered} of the screen covered",
            w.name()
        );
        for ranks in [1, 2, 3, 5, 8] {
            for mode in ["sort-first", "sort-middle", "sort-last"] {
                let out = run_local(ranks, LocalOptions::default(), |c| match mode {
                    "sort-first" => sort_first::render(c, &p, &tris, 0).unwrap(),
                    "sort-middle" => sort_middle::render(c, &p, &tris, 0).unwrap(),
                    _ => sort_last::render(
                        c,
                        &p,
                        &tris,
                        Strategy::BinarySwap,
                        &CompositeOptions::default(),
                    )
                    .unwrap(),
                });
                let img = out.into_iter().next().unwrap().unwrap().unwrap();
                let diff = img
                    .color
                    .iter()
                    .zip(&serial.color)
                    .filter(|(a, b)| a != b)
                    .count();
                assert!(
                    img == serial,
                    "{} {mode} with {ranks} ranks: {diff} pixels differ",
                    w.name()
                );
            }
        }
    }
}

#[test]
fn sort_first_tiles_equal_the_serial_render() {
    use sort_first::{Assign, Tiling};
    for w in workloads() {
        let tris = w.triangles();
        let p = w.pipeline(W, H);
        let serial = sort_common::serial(&p, &tris);
        for ranks in [1, 2, 3, 5] {
            for tiling in [
                Tiling {
                    per_rank: 4,
                    assign: Assign::Interleaved,
                },
                Tiling {
                    per_rank: 3,
                    assign: Assign::Cost,
                },
            ] {
                let out = run_local(ranks, LocalOptions::default(), |c| {
                    sort_first::render_tiled(c, &p, &tris, 0, tiling).unwrap()
                });
                let img = out.into_iter().next().unwrap().unwrap().unwrap();
                assert!(
                    img == serial,
                    "{} {tiling:?} with {ranks} ranks differs",
                    w.name()
                );
            }
        }
    }
}

#[test]
fn cost_dealt_tiles_balance_the_raster_estimate_better_than_strips() {
    use sort_first::{imbalance, raster_costs, Assign, TileLayout, Tiling};
    let w = Workload::Teapot { level: 3 };
    let (tris, p) = (w.triangles(), w.pipeline(W, H));
    let ranks = 4;
    let strips = TileLayout::strips(W, H, ranks);
    let a = imbalance(&strips.rank_costs(&raster_costs(&p, &tris, &strips), ranks));
    let tiling = Tiling {
        per_rank: 8,
        assign: Assign::Cost,
    };
    let l = TileLayout::unassigned(W, H, ranks, tiling);
    let costs = raster_costs(&p, &tris, &l);
    let l = TileLayout::assigned(W, H, ranks, tiling, &costs);
    let b = imbalance(&l.rank_costs(&costs, ranks));
    assert!(b < a && b < 1.15, "tiles {b} vs strips {a}");
}

#[test]
fn tiles_meeting_a_box_are_the_tiles_the_box_meets() {
    use sort_first::{meets, Assign, TileLayout, Tiling};
    let layouts = [
        TileLayout::strips(W, H, 5),
        TileLayout::strips(W, 3, 5), // more ranks than rows: empty strips
        TileLayout::unassigned(
            W,
            H,
            3,
            Tiling {
                per_rank: 4,
                assign: Assign::Cost,
            },
        ),
        TileLayout::unassigned(
            W,
            H,
            7,
            Tiling {
                per_rank: 9,
                assign: Assign::Interleaved,
            },
        ),
    ];
    let mut x = 12345u64;
    let mut next = |lo: f32, hi: f32| {
        x = x
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((x >> 40) as f32 / (1u64 << 24) as f32)
    };
    for l in &layouts {
        let all: Vec<usize> = l.meeting(&None).collect();
        assert_eq!(all, (0..l.tiles.len()).collect::<Vec<_>>());
        for _ in 0..500 {
            let (x0, y0) = (next(-20.0, 80.0), next(-20.0, 60.0));
            let b = Some([x0, y0, x0 + next(0.0, 30.0), y0 + next(0.0, 30.0)]);
            let fast: Vec<usize> = l.meeting(&b).collect();
            let slow: Vec<usize> = (0..l.tiles.len())
                .filter(|&k| meets(&b, &l.tiles[k]))
                .collect();
            assert_eq!(fast, slow, "{b:?}");
        }
    }
}

#[test]
fn the_active_rectangle_holds_every_drawn_pixel() {
    let mut smaller = 0;
    for w in workloads() {
        let tris = w.triangles();
        let p = w.pipeline(W, H);
        for ranks in [1, 3, 8] {
            for rank in 0..ranks {
                let mine = &tris[sort_common::block(tris.len(), rank, ranks)];
                let layer = sort_common::serial(&p, mine);
                let r = sort_last::active_rect(&p, mine);
                for y in 0..H {
                    for x in 0..W {
                        let drawn = layer.depth[(y * W + x) as usize] != composite::FAR;
                        let inside = x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1;
                        assert!(
                            !drawn || inside,
                            "{} rank {rank}/{ranks}: pixel ({x}, {y}) drawn outside {r:?}",
                            w.name()
                        );
                    }
                }
                smaller += ((r.x1 - r.x0) * (r.y1 - r.y0) < W * H / 2) as u32;
            }
        }
    }
    // Blocks of the teapot and of the isosurface cover part of the screen only.
    assert!(
        smaller >= 4,
        "only {smaller} rectangles are less than half the screen"
    );
    let p = workloads()[0].pipeline(W, H);
    assert!(sort_last::active_rect(&p, &[]).is_empty());
}
