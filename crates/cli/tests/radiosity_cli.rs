//! `irradia radiosity --display gouraud|two-pass` end to end: the two-pass image of the
//! built-in specular Cornell box, bad --pixel-samples values (exit 2), and the
//! hierarchical solver on thread ranks (`--comm local`) writing the one-process files.

mod common;
use common::{irradia, mirror_sphere_sum, stderr};

const SMALL: [&str; 11] = [
    "radiosity",
    "--elements",
    "150",
    "--hemicube-resolution",
    "16",
    "--width",
    "40",
    "--height",
    "30",
    "--builtin",
    "cornell-specular",
];

#[test]
fn two_pass_and_gouraud_images_of_the_specular_cornell_box() {
    let dir = tempfile::tempdir().unwrap();
    let mut args = SMALL.to_vec();
    args.extend([
        "--display",
        "two-pass",
        "--pixel-samples",
        "1",
        "-o",
        "t.png",
    ]);
    let o = irradia(&args, dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("two-pass image"), "{}", stderr(&o));
    let traced = irradia_core::io::load(&dir.path().join("t.png")).unwrap();
    assert_eq!((traced.width(), traced.height()), (40, 30));
    let mut args = SMALL.to_vec();
    args.extend(["-o", "g.png"]);
    let o = irradia(&args, dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("black stand-ins"), "{}", stderr(&o));
    let gouraud = irradia_core::io::load(&dir.path().join("g.png")).unwrap();
    // The mirror sphere (lower left of the image) is a black stand-in in the Gouraud
    // image and reflects the lit box in the two-pass image.
    let region = mirror_sphere_sum;
    assert!(region(&gouraud) < 0.02, "{}", region(&gouraud));
    assert!(region(&traced) > 1.0, "{}", region(&traced));
}

#[test]
fn bad_pixel_samples_is_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    for n in ["0", "65"] {
        let o = irradia(
            &[
                "radiosity",
                "--display",
                "two-pass",
                "--pixel-samples",
                n,
                "-q",
            ],
            dir.path(),
        );
        assert_eq!(o.status.code(), Some(2), "{n}: {}", stderr(&o));
        assert!(stderr(&o).contains("--pixel-samples"), "{}", stderr(&o));
    }
}

/// `--solver hierarchical --comm local --ranks N`: the image, the PLY and the iteration
/// history equal the one-process run byte for byte; another solver with --comm exits 2.
#[test]
fn hierarchical_on_thread_ranks_writes_the_one_process_files() {
    let dir = tempfile::tempdir().unwrap();
    let base = [
        "radiosity",
        "--solver",
        "hierarchical",
        "--elements",
        "800",
        "--width",
        "32",
        "--height",
        "32",
        "--quiet",
    ];
    let run = |tag: &str, extra: &[&str]| {
        let (img, ply, csv) = (
            format!("{tag}.pfm"),
            format!("{tag}.ply"),
            format!("{tag}.csv"),
        );
        let mut args = base.to_vec();
        args.extend(["-o", &img, "--mesh-out", &ply, "--convergence", &csv]);
        args.extend(extra);
        let o = irradia(&args, dir.path());
        assert!(o.status.success(), "{tag}: {}", stderr(&o));
        [img, ply, csv].map(|f| std::fs::read(dir.path().join(f)).unwrap())
    };
    let serial = run("serial", &[]);
    for n in ["1", "3"] {
        let got = run(&format!("ranks{n}"), &["--comm", "local", "--ranks", n]);
        assert!(got == serial, "--ranks {n}: files differ");
    }
    let o = irradia(
        &[
            "radiosity",
            "--solver",
            "jacobi",
            "--comm",
            "local",
            "-o",
            "j.png",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("only --solver hierarchical"),
        "{}",
        stderr(&o)
    );
    assert!(!dir.path().join("j.png").exists());
}
