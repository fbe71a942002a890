//! The ray tracer in parallel: image-parallel (sort-first) Whitted ray tracing equals the
//! serial `irradia render` image bit for bit for any rank count and tiling;
//! object-parallel (sort-last) ray casting equals the serial ray cast of the whole scene
//! bit for bit with every compositor.

use irradia_parallel::comm::{run_local, LocalOptions};
use irradia_parallel::composite::Strategy;
use irradia_parallel::sort_first::{imbalance, Assign, TileLayout, Tiling};
use irradia_parallel::{raytrace_first, raytrace_last};
use irradia_render::{driver, Whitted};
use irradia_scene::Scene;

fn scene(name: &str) -> Scene {
    let mut s = irradia_scene::builtin::load(name).unwrap();
    s.settings.width = 64;
    s.settings.height = 48;
    s
}

#[test]
fn image_parallel_ray_tracing_equals_the_serial_render() {
    for name in ["whitted", "csg"] {
        let s = scene(name);
        let serial = driver::render_with(&Whitted::new(&s), &s, &Default::default())
            .unwrap()
            .image;
        let tilings = [
            Tiling::STRIPS,
            Tiling {
                per_rank: 3,
                assign: Assign::Interleaved,
            },
            Tiling {
                per_rank: 4,
                assign: Assign::Cost,
            },
        ];
        for ranks in [1, 2, 3, 5] {
            for tiling in tilings {
                let out = run_local(ranks, LocalOptions::default(), |c| {
                    raytrace_first::render(c, &s, tiling, 0).unwrap()
                });
                let mut rays = 0;
                let mut image = None;
                for r in out {
                    let r = r.unwrap();
                    rays += r.rays;
                    if r.image.is_some() {
                        image = r.image;
                    }
                }
                let layer = image.expect("rank 0 has the image");
                assert_eq!(
                    raytrace_first::unwritten(&layer),
                    0,
                    "{name}: pixels missing"
                );
                let img = raytrace_first::to_image(&layer);
                let diff = img
                    .pixels()
                    .iter()
                    .zip(serial.pixels())
                    .filter(|(a, b)| a != b)
                    .count();
                assert_eq!(
                    diff, 0,
                    "{name}, {ranks} ranks, {tiling:?}: {diff} pixels differ"
                );
                assert!(rays >= 64 * 48, "{name}: {rays} rays traced");
            }
        }
    }
}

#[test]
fn cost_tiles_balance_the_estimate_better_than_strips() {
    // The teapot fills the middle of the screen: strips give the middle ranks the work.
    let s = scene("teapot");
    let ranks = 4;
    let strips = TileLayout::strips(64, 48, ranks);
    let strip_costs = raytrace_first::object_costs(&s, &strips.tiles);
    let tiled = raytrace_first::layout(
        &s,
        ranks,
        Tiling {
            per_rank: 8,
            assign: Assign::Cost,
        },
    );
    let tile_costs = raytrace_first::object_costs(&s, &tiled.tiles);
    let a = imbalance(&strips.rank_costs(&strip_costs, ranks));
    let b = imbalance(&tiled.rank_costs(&tile_costs, ranks));
    assert!(tiled.tiles.len() >= 32);
    assert!(b < a, "tiles {b} vs strips {a}");
    assert!(
        b < 1.1,
        "cost-dealt tiles should balance the estimate within 10% (got {b})"
    );
}

#[test]
fn object_parallel_ray_casting_equals_the_serial_ray_cast() {
    for name in ["whitted", "quadrics", "csg"] {
        let s = scene(name);
        let serial = raytrace_last::serial(&s);
        let hits = serial.depth.iter().filter(|d| d.is_finite()).count();
        assert!(hits > 64 * 48 / 10, "{name}: only {hits} pixels hit");
        for ranks in [1, 2, 3, 4, 7] {
            for strategy in [
                Strategy::BinarySwap,
                Strategy::DirectSend,
                Strategy::RadixK(3),
            ] {
                let out = run_local(ranks, LocalOptions::default(), |c| {
                    raytrace_last::render(c, &s, strategy, 0).unwrap()
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
                    "{name}, {ranks} ranks, {strategy:?}: {diff} pixels differ"
                );
            }
        }
    }
}

#[test]
fn each_ranks_active_rectangle_is_the_box_of_its_hit_pixels() {
    use irradia_parallel::composite::{ActiveRect, FAR};
    let s = scene("quadrics");
    for ranks in [2, 3] {
        let out = run_local(ranks, LocalOptions::default(), |c| {
            raytrace_last::render_layer_bounded(c, &s, raytrace_last::Shading::Local)
        });
        let mut non_empty = 0;
        for (rank, o) in out.into_iter().enumerate() {
            let (layer, rect) = o.unwrap();
            // The box of the hit pixels, found by scanning the whole layer.
            let mut scanned = ActiveRect::EMPTY;
            for (i, &d) in layer.depth.iter().enumerate() {
                if d != FAR {
                    let (x, y) = ((i % 64) as u32, (i / 64) as u32);
                    let px = ActiveRect {
                        x0: x,
                        y0: y,
                        x1: x + 1,
                        y1: y + 1,
                    };
                    scanned = scanned.union(&px);
                }
            }
            assert_eq!(rect, scanned, "{ranks} ranks, rank {rank}");
            non_empty += usize::from(!rect.is_empty() && rect != ActiveRect::full(64, 48));
        }
        assert!(
            non_empty > 0,
            "{ranks} ranks: every rectangle empty or full"
        );
    }
}

#[test]
fn object_parallel_casting_has_no_shadows_or_mirrors() {
    // The Whitted scene's mirror and glass spheres and shadows need other ranks'
    // objects: the local ray cast must differ from the Whitted image there.
    let s = scene("whitted");
    let cast = raytrace_last::serial(&s);
    let traced = driver::render_with(&Whitted::new(&s), &s, &Default::default())
        .unwrap()
        .image;
    let differ = cast
        .color
        .iter()
        .zip(traced.pixels())
        .filter(|(a, b)| (a[0] - b.r).abs() + (a[1] - b.g).abs() + (a[2] - b.b).abs() > 0.05)
        .count();
    assert!(differ > 64 * 48 / 20, "only {differ} pixels differ");
}

#[test]
fn whitted_on_own_objects_only_misses_the_other_ranks_objects() {
    use irradia_parallel::raytrace_last::{render_shaded, whitted_layer, Shading};
    let s = scene("whitted");
    let serial = whitted_layer(&s);
    let differing = |ranks: usize| {
        let out = run_local(ranks, LocalOptions::default(), |c| {
            render_shaded(c, &s, Strategy::BinarySwap, 0, Shading::WhittedOwnObjects).unwrap()
        });
        let img = out.into_iter().next().unwrap().unwrap().unwrap();
        img.color
            .iter()
            .zip(&serial.color)
            .zip(&serial.depth)
            .filter(|((a, b), d)| d.is_finite() && a != b)
            .count()
    };
    // One rank owns every object: the serial Whitted image exactly.
    assert_eq!(differing(1), 0);
    // With objects on different ranks, reflections, refractions and shadows of the
    // other ranks' objects are lost.
    for ranks in [2, 3] {
        let n = differing(ranks);
        assert!(n > 64 * 48 / 20, "{ranks} ranks: only {n} pixels differ");
    }
}
