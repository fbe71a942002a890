//! `irradia wall` end to end: both ways of rendering the displays (per display, and
//! sort-last composited onto the displays) write every display's image and both
//! photographs, and agree; bad options and wall files exit with code 2.

mod common;
use common::{irradia, stderr};

const WALL: &str = "columns = 2\nrows = 2\nwidth = 48\nheight = 36\noverlap = 6\n\n[[projector]]\ngamma = 2.4\nvignetting = 0.2\n";

fn run_wall(d: &std::path::Path, out: &str, extra: &[&str]) {
    let mut args = vec!["wall", "--config", "wall.toml", "teapot", "-o", out];
    args.extend_from_slice(extra);
    let o = irradia(&args, d);
    assert!(o.status.success(), "{extra:?}: {}", stderr(&o));
}

#[test]
fn sort_last_and_per_display_walls_write_the_same_displays() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("wall.toml"), WALL).unwrap();
    run_wall(d, "per", &[]);
    run_wall(
        d,
        "last",
        &["--render", "sort-last", "--compositor", "radix-k"],
    );
    let mut lit = 0;
    for name in [
        "display-0-0.png",
        "display-0-1.png",
        "display-1-0.png",
        "display-1-1.png",
        "photo.png",
        "photo-uncorrected.png",
    ] {
        let a = irradia_core::io::load(&d.join("per").join(name)).unwrap();
        let b = irradia_core::io::load(&d.join("last").join(name)).unwrap();
        assert_eq!((a.width(), a.height()), (b.width(), b.height()), "{name}");
        let differing = a
            .pixels()
            .iter()
            .zip(b.pixels())
            .filter(|(p, q)| {
                (p.r - q.r)
                    .abs()
                    .max((p.g - q.g).abs())
                    .max((p.b - q.b).abs())
                    > 0.01
            })
            .count();
        assert!(
            differing * 50 <= a.pixels().len(),
            "{name}: {differing} pixels differ between per-display and sort-last"
        );
        lit += a
            .pixels()
            .iter()
            .filter(|p| p.max_component() > 0.05)
            .count();
    }
    assert!(lit > 100, "the wall shows (almost) nothing");
}

#[test]
fn bad_wall_input_exits_with_code_2() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("wall.toml"), WALL).unwrap();
    std::fs::write(
        d.join("bad.toml"),
        "columns = 0\nrows = 1\nwidth = 8\nheight = 8\n",
    )
    .unwrap();
    let cases: [(&[&str], &str); 3] = [
        (
            &[
                "--config",
                "wall.toml",
                "-o",
                "x",
                "--render",
                "sort-last",
                "--compositor",
                "nope",
            ],
            "--compositor",
        ),
        (&["--config", "bad.toml", "-o", "x"], "columns"),
        (&["--config", "wall.toml", "sponge", "-o", "x"], "sponge"),
    ];
    for (args, needle) in cases {
        let mut all = vec!["wall"];
        all.extend_from_slice(args);
        let o = irradia(&all, d);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
    }
}
