//! `irradia render` with the path tracer, end to end: a checkpointed render resumed to
//! more samples equals a render made in one go; bad budgets are refused with exit 2.

use std::path::Path;
use std::process::Command;

fn irradia() -> Command {
    Command::new(env!("CARGO_BIN_EXE_irradia"))
}

fn render(args: &[&str]) -> std::process::Output {
    irradia()
        .arg("render")
        .args(args)
        .output()
        .expect("irradia runs")
}

const SMALL: &[&str] = &[
    "--builtin",
    "cornell",
    "--width",
    "24",
    "--height",
    "24",
    "--quiet",
];

#[test]
fn resumed_render_equals_uninterrupted_render() {
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str| dir.path().join(n).to_string_lossy().into_owned();
    let whole = p("whole.pfm");
    let out = render(&[SMALL, &["--spp", "6", "-o", &whole]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    let ckpt = p("c.ckpt");
    let part = p("part.pfm");
    let out = render(&[SMALL, &["--spp", "2", "--checkpoint", &ckpt, "-o", &part]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(Path::new(&ckpt).exists());
    let resumed = p("resumed.pfm");
    let out = render(&[SMALL, &["--spp", "6", "--resume", &ckpt, "-o", &resumed]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        std::fs::read(&whole).unwrap(),
        std::fs::read(&resumed).unwrap()
    );
    assert_ne!(
        std::fs::read(&whole).unwrap(),
        std::fs::read(&part).unwrap()
    );
}

#[test]
fn bad_budgets_and_mismatched_checkpoints_are_input_errors() {
    let dir = tempfile::tempdir().unwrap();
    let out_png = dir.path().join("x.png").to_string_lossy().into_owned();
    for bad in [
        &["--time", "-1"][..],
        &["--target-error", "0"],
        &["--resume", "/no/such.ckpt"],
    ] {
        let out = render(&[SMALL, bad, &["-o", &out_png]].concat());
        assert_eq!(
            out.status.code(),
            Some(2),
            "{bad:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    // Path-tracer options with the Whitted integrator.
    let out = render(&[
        "--builtin",
        "whitted",
        "--width",
        "8",
        "--height",
        "8",
        "--time",
        "1",
        "-o",
        &out_png,
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--integrator path"));
    // A checkpoint of another image size.
    let ckpt = dir.path().join("c.ckpt").to_string_lossy().into_owned();
    assert!(render(
        &[
            SMALL,
            &["--spp", "1", "--checkpoint", &ckpt, "-o", &out_png]
        ]
        .concat()
    )
    .status
    .success());
    let out = render(&[
        "--builtin",
        "cornell",
        "--width",
        "30",
        "--height",
        "24",
        "--quiet",
        "--resume",
        &ckpt,
        "-o",
        &out_png,
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("another scene"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn time_budget_ends_an_uncapped_render() {
    let dir = tempfile::tempdir().unwrap();
    let out_png = dir.path().join("t.png").to_string_lossy().into_owned();
    let out = render(&[SMALL, &["--time", "0.5", "-o", &out_png]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(Path::new(&out_png).exists());
}
