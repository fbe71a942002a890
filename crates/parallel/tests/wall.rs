//! Tiled walls: blend weights sum to one, a uniform grey wall photographs uniform within
//! 1%, projectors with different responses are matched, bad wall files are rejected;
//! the wall job writes every display's image and the photographs, and a rank failing
//! during it ends every rank with an error naming it.

use glam::Vec3;
use irradia_parallel::comm::{run_local, Comm, CommError, LocalOptions};
use irradia_parallel::wall::{self, blend, color, job, WallConfig, WallSource};
use std::time::{Duration, Instant};

/// A hang guard, not a speed check: a job that deadlocks never ends, and a loaded 2-core
/// CI machine may take many times the timeout to notice a silent rank, so the bound is
/// generous. The errors' content is what these tests check.
const HANG_GUARD: Duration = Duration::from_secs(60);

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

fn quick() -> LocalOptions {
    LocalOptions {
        timeout: Duration::from_millis(300),
        delay: None,
    }
}

#[test]
fn the_wall_job_writes_every_display_and_both_photographs() {
    let c = WallConfig::parse(GRID).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let src = WallSource::Uniform(Vec3::new(0.3, 0.5, 0.7));
    let out = run_local(c.displays(), LocalOptions::default(), |comm| {
        job::run(comm, &c, &src, dir.path()).unwrap()
    });
    let mut names: Vec<String> = out
        .into_iter()
        .flat_map(|r| r.unwrap())
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "display-0-0.png",
            "display-0-1.png",
            "display-0-2.png",
            "display-1-0.png",
            "display-1-1.png",
            "display-1-2.png",
            "photo-uncorrected.png",
            "photo.png"
        ]
    );
    // Each display's file holds its drive values (8-bit).
    let f = run_local(c.displays(), LocalOptions::default(), |comm| {
        wall::frame(comm, &c, &src, true).unwrap()
    })
    .into_iter()
    .next()
    .unwrap()
    .unwrap()
    .unwrap();
    for i in 0..c.displays() {
        let img = irradia_core::io::load(&dir.path().join(job::display_file(&c, i))).unwrap();
        assert_eq!((img.width(), img.height()), (c.width, c.height));
        for (k, p) in img.pixels().iter().enumerate() {
            // The file's 8-bit values are the drive levels.
            for (ch, lin) in [p.r, p.g, p.b].into_iter().enumerate() {
                let byte = (irradia_core::color::linear_to_srgb(lin) * 255.0).round();
                let want = f.frames[i][k][ch] * 255.0;
                assert!(
                    (byte - want).abs() <= 0.5 + 1e-3,
                    "display {i} pixel {k}: {byte} vs {want}"
                );
            }
        }
    }
}

#[test]
fn a_wrong_rank_count_is_an_error() {
    let c = WallConfig::parse(GRID).unwrap();
    let out = run_local(4, quick(), |comm| {
        wall::frame(comm, &c, &WallSource::Uniform(Vec3::ONE), true)
    });
    for r in out {
        let e = r.unwrap().err().expect("4 ranks for 6 displays");
        assert!(e.to_string().contains("6 displays"), "{e}");
    }
}

/// Every rank but `culprit` ends with an error naming it, within a few timeouts.
fn all_blame(
    out: Vec<Result<Result<Vec<std::path::PathBuf>, job::WallError>, CommError>>,
    culprit: usize,
) {
    for (r, res) in out.into_iter().enumerate() {
        if r == culprit {
            continue;
        }
        let e = res
            .expect("no panic")
            .expect_err("the job must fail on every rank");
        assert_eq!(e.culprit(), Some(culprit), "rank {r} blamed: {e}");
        assert!(e.to_string().contains(&format!("rank {culprit}")), "{e}");
    }
}

#[test]
fn a_rank_failing_during_the_wall_ends_every_rank_naming_it() {
    let c = WallConfig::parse(GRID).unwrap();
    let src = WallSource::Uniform(Vec3::splat(0.5));
    // A rank that cannot write its display image (a folder is in the way).
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("display-0-1.png")).unwrap();
    let t0 = Instant::now();
    let out = run_local(c.displays(), quick(), |comm| {
        job::run(comm, &c, &src, dir.path())
    });
    assert!(t0.elapsed() < HANG_GUARD, "took {:?}", t0.elapsed());
    let own = out[1].as_ref().unwrap().as_ref().unwrap_err();
    assert!(
        matches!(own, job::WallError::Write { rank: 1, .. }),
        "{own}"
    );
    assert!(own.to_string().contains("display-0-1.png"), "{own}");
    all_blame(out, 1);

    // A rank that crashes while rendering.
    let dir = tempfile::tempdir().unwrap();
    let out = run_local(c.displays(), quick(), |comm| {
        if comm.rank() == 4 {
            panic!("simulated crash of display 4");
        }
        job::run(comm, &c, &src, dir.path())
    });
    assert!(out[4].is_err());
    all_blame(out, 4);

    // A rank that hangs (never reaches the frame barrier).
    let t0 = Instant::now();
    let out = run_local(c.displays(), quick(), |comm| {
        if comm.rank() == 3 {
            std::thread::sleep(Duration::from_millis(900));
            return Ok(Vec::new());
        }
        job::run(comm, &c, &src, dir.path())
    });
    assert!(t0.elapsed() < HANG_GUARD, "took {:?}", t0.elapsed());
    all_blame(out, 3);
}
