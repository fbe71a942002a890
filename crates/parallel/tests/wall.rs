//! Tiled walls: blend weights sum to one, a uniform grey wall photographs uniform within
//! 1%, projectors with different responses are matched, bad wall files are rejected.

use glam::Vec3;
use irradia_parallel::comm::{run_local, LocalOptions};
use irradia_parallel::wall::{self, blend, color, WallConfig, WallSource};

const TWO_DIFFERENT: &str = r#"
columns = 2
rows = 1
width = 48
height = 32
overlap = 12

[[projector]]
gamma = 2.4
matrix = [[0.92, 0.06, 0.02], [0.04, 0.90, 0.06], [0.01, 0.07, 0.80]]
black = [0.010, 0.011, 0.013]
vignetting = 0.3

[[projector]]
gamma = 1.9
matrix = [[0.80, 0.10, 0.05], [0.08, 0.97, 0.03], [0.02, 0.03, 0.95]]
black = [0.020, 0.018, 0.015]
vignetting = 0.1
"#;

const GRID: &str = r#"
columns = 3
rows = 2
width = 32
height = 24
overlap = 8
[[projector]]
vignetting = 0.2
black = [0.01, 0.01, 0.01]
[[projector]]
gamma = 2.6
"#;

fn shoot(text: &str, src: WallSource, corrected: bool) -> (WallConfig, Vec<Vec3>) {
    let c = WallConfig::parse(text).unwrap();
    let out = run_local(c.displays(), LocalOptions::default(), |comm| {
        wall::frame(comm, &c, &src, corrected).unwrap()
    });
    let f = out.into_iter().next().unwrap().unwrap().unwrap();
    (c, f.photo)
}

#[test]
fn blend_weights_sum_to_one_everywhere() {
    for text in [TWO_DIFFERENT, GRID] {
        let c = WallConfig::parse(text).unwrap();
        let w: Vec<Vec<f32>> = (0..c.displays()).map(|i| blend::weights(&c, i)).collect();
        let (ww, wh) = c.wall_size();
        let mut overlapped = 0;
        for wy in 0..wh {
            for wx in 0..ww {
                let cov: Vec<_> = color::covering(&c, wx, wy).collect();
                overlapped += (cov.len() > 1) as usize;
                let s: f32 = cov
                    .iter()
                    .map(|&(j, x, y)| w[j][(y * c.width + x) as usize])
                    .sum();
                assert!((s - 1.0).abs() < 1e-5, "weights sum to {s} at ({wx}, {wy})");
            }
        }
        assert!(overlapped > 0);
    }
}

fn spread(photo: &[Vec3], channel: usize) -> (f32, f32) {
    let v: Vec<f32> = photo.iter().map(|p| p[channel]).collect();
    (
        v.iter().cloned().fold(f32::INFINITY, f32::min),
        v.iter().cloned().fold(0.0, f32::max),
    )
}

#[test]
fn a_uniform_grey_wall_is_uniform_within_one_percent() {
    for text in [TWO_DIFFERENT, GRID] {
        let (_, photo) = shoot(text, WallSource::Uniform(Vec3::splat(0.5)), true);
        for ch in 0..3 {
            let (lo, hi) = spread(&photo, ch);
            assert!((hi - lo) / hi < 0.01, "channel {ch}: {lo}..{hi}");
            assert!(
                (lo - 0.5).abs() < 0.01 && (hi - 0.5).abs() < 0.01,
                "channel {ch}: {lo}..{hi}"
            );
        }
        // Without correction the overlaps and vignetting show: the test can fail.
        let (_, naive) = shoot(text, WallSource::Uniform(Vec3::splat(0.5)), false);
        let (lo, hi) = spread(&naive, 1);
        assert!(
            (hi - lo) / hi > 0.2,
            "naive wall should be visibly non-uniform: {lo}..{hi}"
        );
    }
}

#[test]
fn two_different_projector_responses_are_matched() {
    for want in [
        Vec3::new(0.8, 0.2, 0.1),
        Vec3::new(0.1, 0.6, 0.3),
        Vec3::splat(0.9),
        Vec3::splat(0.05),
    ] {
        let (c, photo) = shoot(TWO_DIFFERENT, WallSource::Uniform(want), true);
        let (ww, wh) = c.wall_size();
        let mean = |x0: u32, x1: u32| {
            let mut s = Vec3::ZERO;
            for y in 0..wh {
                for x in x0..x1 {
                    s += photo[(y * ww + x) as usize];
                }
            }
            s / ((x1 - x0) * wh) as f32
        };
        // Columns only one projector lights: left part of display 0, right part of display 1.
        let left = mean(0, c.width - c.overlap);
        let right = mean(c.width, ww);
        assert!(
            (left - right).abs().max_element() < 0.01 * want.max_element(),
            "{want}: {left} vs {right}"
        );
        assert!(
            (left - want).abs().max_element() < 0.01,
            "{want}: got {left}"
        );
    }
}

#[test]
fn bad_wall_files_name_the_field() {
    for (text, needle) in [
        ("columns = 0\nrows = 1\nwidth = 32\nheight = 32", "columns"),
        ("columns = 2\nrows = 1\nwidth = 32\nheight = 32\noverlap = 20", "overlap"),
        ("columns = 1\nrows = 1\nwidth = 32\nheight = 32\n[[projector]]\ngamma = -1", "gamma"),
        ("columns = 1\nrows = 1\nwidth = 32\nheight = 32\n[[projector]]\nmatrix = [[0,0,0],[0,0,0],[0,0,0]]", "matrix"),
        ("columns = 1\nrows = 1\nwidth = 32\nheight = 32\ncolour = 3", "line 5"),
        ("columns = 1\nrows = 1\nwidth = \"x\"\nheight = 32", "line 3"),
    ] {
        let e = WallConfig::parse(text).expect_err(text);
        assert!(e.contains(needle), "{e:?} should mention {needle}");
    }
}
