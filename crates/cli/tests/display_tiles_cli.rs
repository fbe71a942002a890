//! `irradia parallel --display-tiles`: sort-last composited onto a grid of displays. Each
//! display's file equals its rectangle of the single-display image (raster: PNG bytes
//! decoded; ray tracer: PFM floats), overlap included, and bad grids exit with code 2.

mod common;
use common::{irradia, stderr};

use irradia_core::Image;
use std::path::Path;

/// `image` cut to the rectangle `x, y, width, height`.
fn crop(image: &Image, x: u32, y: u32, width: u32, height: u32) -> Vec<irradia_core::Rgb> {
    let mut out = Vec::new();
    for row in y..y + height {
        for col in x..x + width {
            out.push(image.get(col, row));
        }
    }
    out
}

fn run_ok(args: &[&str], d: &Path) -> String {
    let mut all = vec!["parallel"];
    all.extend_from_slice(args);
    let o = irradia(&all, d);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    stderr(&o)
}

/// Renders once to one display and once to a 2x2 grid with 3 pixels of overlap, and
/// checks every tile against the one image.
fn check_tiles(workload_args: &[&str], ext: &str, d: &Path) {
    let whole = format!("whole.{ext}");
    let wall = format!("wall.{ext}");
    let common = [
        "--mode",
        "sort-last",
        "--ranks",
        "5",
        "--width",
        "64",
        "--height",
        "48",
        "--compositor",
        "radix-k",
    ];
    let mut a: Vec<&str> = common.to_vec();
    a.extend_from_slice(workload_args);
    let mut single = a.clone();
    single.extend_from_slice(&["-o", &whole, "--quiet"]);
    run_ok(&single, d);
    let mut tiled = a.clone();
    tiled.extend_from_slice(&[
        "--display-tiles",
        "2x2",
        "--display-overlap",
        "3",
        "-o",
        &wall,
    ]);
    let log = run_ok(&tiled, d);
    assert!(log.contains("display 3 (rank 3)"), "{log}");
    assert!(
        !d.join(&wall).exists(),
        "no whole image is written with tiles"
    );
    let image = irradia_core::io::load(&d.join(&whole)).unwrap();
    // 64 x 48 cut in 2 x 2, each tile widened by 3 pixels into its neighbours.
    let rects = [
        (0, 0, 35, 27, "0-0"),
        (29, 0, 35, 27, "0-1"),
        (0, 21, 35, 27, "1-0"),
        (29, 21, 35, 27, "1-1"),
    ];
    for (x, y, w, h, name) in rects {
        let tile = irradia_core::io::load(&d.join(format!("wall-{name}.{ext}"))).unwrap();
        assert_eq!((tile.width(), tile.height()), (w, h), "tile {name}");
        assert!(
            tile.pixels() == crop(&image, x, y, w, h).as_slice(),
            "{workload_args:?}: tile {name} differs from its part of the single image"
        );
    }
    assert!(image.mean().max_component() > 0.05, "the image is black");
}

#[test]
fn display_tiles_equal_their_part_of_the_single_display_image() {
    let dir = tempfile::tempdir().unwrap();
    check_tiles(&["--workload", "teapot"], "png", dir.path());
    check_tiles(
        &["--workload", "builtin:whitted", "--renderer", "raytrace"],
        "pfm",
        dir.path(),
    );
}

#[test]
fn bad_display_grids_exit_with_code_2() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&[&str], &str); 5] = [
        (&["--display-tiles", "2by2"], "expected COLUMNSxROWS"),
        (&["--display-tiles", "0x2"], "expected COLUMNSxROWS"),
        (
            &["--display-tiles", "3x2", "--ranks", "4"],
            "at least 6 ranks",
        ),
        (
            &["--display-tiles", "2x1", "--mode", "sort-first"],
            "use --mode sort-last",
        ),
        (&["--display-overlap", "4"], "belongs to --display-tiles"),
    ];
    for (args, needle) in cases {
        let mut all = vec!["parallel", "--width", "32", "--height", "24"];
        all.extend_from_slice(args);
        let o = irradia(&all, dir.path());
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
    }
}
