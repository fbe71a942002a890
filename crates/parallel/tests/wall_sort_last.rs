//! The wall rendered sort-last: every display's tile equals its rectangle of the serial
//! render of the whole wall bit for bit (overlap and bezel layouts, several
//! compositors), shows what the display's own off-axis frustum shows up to rasterizer
//! rounding, and the whole job's photograph matches the per-display job's.

use glam::Vec3;
use irradia_parallel::comm::{run_local, Comm, LocalOptions};
use irradia_parallel::composite::Strategy;
use irradia_parallel::display_tiles::DisplayLayout;
use irradia_parallel::wall::{self, sort_last, WallConfig, WallRendering, WallSource};
use irradia_parallel::workload::Workload;

const OVERLAP: &str = "columns = 3\nrows = 2\nwidth = 40\nheight = 30\noverlap = 8\n";
const BEZEL: &str = "columns = 2\nrows = 2\nwidth = 36\nheight = 28\nbezel = 5\n";

fn teapot() -> Workload {
    Workload::by_name("teapot", 3000).expect("teapot is a workload")
}

/// Each rank's sort-last tile (linear colour).
fn sort_last_tiles(c: &WallConfig, src: &WallSource, s: Strategy) -> Vec<Vec<Vec3>> {
    run_local(c.displays(), LocalOptions::default(), |comm| {
        sort_last::render_tile(comm, c, src, s).unwrap()
    })
    .into_iter()
    .map(|r| r.unwrap())
    .collect()
}

#[test]
fn sort_last_tiles_equal_the_serial_wall_render() {
    let w = teapot();
    let src = WallSource::Workload(w.clone());
    for text in [OVERLAP, BEZEL] {
        let c = WallConfig::parse(text).unwrap();
        let whole = run_local(1, LocalOptions::default(), |comm| {
            sort_last::wall_layer(comm, &c, &w).0
        })
        .pop()
        .unwrap()
        .unwrap();
        let active = whole.active_fraction(irradia_parallel::composite::Operator::Depth);
        assert!(active > 0.05, "the teapot covers only {active} of the wall");
        let layout = sort_last::layout(&c);
        layout
            .validate(c.displays(), whole.width, whole.height)
            .unwrap();
        for s in [
            Strategy::BinarySwap,
            Strategy::RadixK(3),
            Strategy::DirectSend,
        ] {
            let tiles = sort_last_tiles(&c, &src, s);
            for (i, got) in tiles.iter().enumerate() {
                let want: Vec<Vec3> = DisplayLayout::crop(&whole, &layout.tiles[i])
                    .color
                    .iter()
                    .map(|q| Vec3::new(q[0], q[1], q[2]).clamp(Vec3::ZERO, Vec3::ONE))
                    .collect();
                assert!(
                    *got == want,
                    "{text:?} {}: display {i} differs from its part of the serial wall",
                    s.name()
                );
            }
        }
    }
}

#[test]
fn sort_last_tiles_show_what_each_display_frustum_shows() {
    let src = WallSource::Workload(teapot());
    for text in [OVERLAP, BEZEL] {
        let c = WallConfig::parse(text).unwrap();
        let tiles = sort_last_tiles(&c, &src, Strategy::BinarySwap);
        for (i, tile) in tiles.iter().enumerate() {
            let own = wall::render_display(&c, &src, i);
            let differing = tile
                .iter()
                .zip(&own)
                .filter(|(a, b)| (**a - **b).abs().max_element() > 2.0 / 255.0)
                .count();
            let covered = own.iter().filter(|v| v.max_element() > 0.0).count();
            // The two projections round differently: only pixels on silhouettes and
            // shared edges may differ.
            assert!(
                differing * 20 <= covered.max(20),
                "{text:?}: display {i}: {differing} of {covered} covered pixels differ"
            );
        }
    }
}

#[test]
fn the_sort_last_wall_photographs_like_the_per_display_wall() {
    let src = WallSource::Workload(teapot());
    let c = WallConfig::parse(OVERLAP).unwrap();
    let photo = |rendering: WallRendering| {
        run_local(c.displays(), LocalOptions::default(), |comm| {
            let f = wall::frame_and_own_with(comm, &c, &src, true, rendering).unwrap();
            (comm.rank() == 0).then(|| f.1.unwrap().photo)
        })
        .into_iter()
        .next()
        .unwrap()
        .unwrap()
        .unwrap()
    };
    let a = photo(WallRendering::PerDisplay);
    let b = photo(WallRendering::SortLast(Strategy::RadixK(4)));
    let mean = |p: &[Vec3]| p.iter().copied().sum::<Vec3>() / p.len() as f32;
    let mean_abs = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (*x - *y).abs().max_element())
        .sum::<f32>()
        / a.len() as f32;
    assert!(mean(&a).max_element() > 0.02, "the photograph is black");
    assert!(
        mean_abs < 0.01,
        "sort-last and per-display photographs differ by {mean_abs} on average"
    );
}
