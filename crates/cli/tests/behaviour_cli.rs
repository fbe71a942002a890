//! What every subcommand does alike (docs/cli.md, "What every subcommand does alike"):
//! outputs checked before any work (exit 2, one line), a scene folder named as such,
//! clap's errors in one line, a default image for `parallel`, examples at the end of
//! every `--help` and `--quiet` under "General options", every `radiosity --builtin`
//! name listed, and progress lines when standard error is not a terminal.

mod common;
use common::{irradia, stderr};
use std::path::Path;
use std::time::{Duration, Instant};

/// Exit 2 with exactly one line on stderr, which contains `needle`.
fn one_line_exit_2(args: &[&str], dir: &Path, needle: &str) -> String {
    let t = Instant::now();
    let o = irradia(args, dir);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
    assert_eq!(e.trim_end().lines().count(), 1, "{args:?}: {e}");
    assert!(e.contains(needle), "{args:?}: {e}");
    // Found before any work: well under the time of the smallest job.
    assert!(t.elapsed() < Duration::from_secs(20), "{args:?}");
    e
}

#[test]
fn outputs_are_checked_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let e = one_line_exit_2(
        &["radiosity", "-o", "no/such/dir/x.png"],
        d,
        "does not exist",
    );
    assert_eq!(e.matches("x.png").count(), 1, "the path once: {e}");
    one_line_exit_2(
        &["radiosity", "-o", "r.jpg"],
        d,
        "unsupported image extension",
    );
    one_line_exit_2(
        &["radiosity", "--mesh-out", "m.obj", "-o", "r.png"],
        d,
        "--mesh-out",
    );
    one_line_exit_2(
        &["radiosity", "--convergence", "no/such/r.csv"],
        d,
        "--convergence",
    );
    one_line_exit_2(
        &["parallel", "-o", "r.jpg"],
        d,
        "unsupported image extension",
    );
    one_line_exit_2(&["parallel", "-o", "no/such/p.png"], d, "does not exist");
    one_line_exit_2(&["parallel", "--report", "r.txt"], d, "--report");
    std::fs::write(d.join("afile"), b"").unwrap();
    one_line_exit_2(
        &["wall", "--config", "missing.toml", "-o", "afile"],
        d,
        "missing.toml",
    );
    let cfg = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/examples/wall-3x2.toml");
    let cfg = cfg.to_str().unwrap();
    one_line_exit_2(&["wall", "--config", cfg, "-o", "afile"], d, "is a file");
    one_line_exit_2(&["bench", "parallel", "-o", "afile"], d, "is a file");
    // Nothing was written.
    assert!(!d.join("r.png").exists() && !d.join("parallel.png").exists());
}

#[test]
fn a_scene_folder_is_named_as_a_folder() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_str().unwrap();
    one_line_exit_2(&["render", d], dir.path(), "is a directory");
    one_line_exit_2(&["radiosity", d], dir.path(), "is a directory");
}

#[test]
fn option_errors_are_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let e = one_line_exit_2(&["render", "--foo"], dir.path(), "'--foo'");
    assert!(e.starts_with("irradia: ") && e.contains("--help"), "{e}");
    one_line_exit_2(&["radiosity", "--solver", "magic"], dir.path(), "magic");
    one_line_exit_2(&["parallel", "--ranks", "x"], dir.path(), "--ranks");
}

#[test]
fn parallel_without_output_writes_parallel_png() {
    let dir = tempfile::tempdir().unwrap();
    let o = irradia(
        &[
            "parallel",
            "--workload",
            "random-triangles",
            "--triangles",
            "200",
            "--width",
            "64",
            "--height",
            "48",
            "--ranks",
            "2",
            "--quiet",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let im = irradia_core::io::load(&dir.path().join("parallel.png")).unwrap();
    assert_eq!((im.width(), im.height()), (64, 48));
    assert!(stderr(&o).is_empty(), "--quiet: {}", stderr(&o));
}

#[test]
fn every_help_ends_with_examples_and_lists_quiet_under_general_options() {
    let dir = tempfile::tempdir().unwrap();
    for cmd in [
        &["render"][..],
        &["radiosity"],
        &["parallel"],
        &["wall"],
        &["bench", "parallel"],
        &["scenes"],
        &["formfactor"],
        &["trace-pixel"],
    ] {
        let mut args = cmd.to_vec();
        args.push("--help");
        let o = irradia(&args, dir.path());
        let out = String::from_utf8_lossy(&o.stdout).into_owned();
        assert!(o.status.success(), "{args:?}");
        assert!(out.contains("Examples:"), "{args:?} has no examples");
        let examples = out.rfind("Examples:").unwrap();
        assert!(
            out[examples..].contains("irradia "),
            "{args:?}: the examples come last"
        );
        if ["radiosity", "parallel", "wall", "bench"].contains(&cmd[0]) {
            let general = out
                .find("General options:")
                .unwrap_or_else(|| panic!("{args:?}: no General options heading:\n{out}"));
            assert!(out[general..].contains("--quiet"), "{args:?}");
        }
    }
}

#[test]
fn radiosity_help_lists_every_builtin_it_accepts() {
    let dir = tempfile::tempdir().unwrap();
    let o = irradia(&["radiosity", "--help"], dir.path());
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    let mut names = vec!["cornell", "cornell-empty", "furnace", "cornell-specular"];
    let rt: Vec<&str> = irradia_scene::builtin::names()
        .into_iter()
        .map(|(n, _)| n)
        .collect();
    names.extend(rt);
    let list = &out[out.find("Built-in scenes").expect("a list of built-ins")..];
    for n in names {
        assert!(
            list.lines()
                .any(|l| l.trim_start().starts_with(&format!("{n} "))),
            "{n} missing:\n{list}"
        );
    }
}

#[test]
fn long_jobs_print_progress_lines_when_stderr_is_not_a_terminal() {
    let dir = tempfile::tempdir().unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_irradia"))
        .args(["radiosity", "--elements", "400", "-o", "r.png"])
        .env("IRRADIA_PROGRESS_INTERVAL", "0.05")
        .current_dir(dir.path())
        .output()
        .unwrap();
    let e = stderr(&o);
    assert!(o.status.success(), "{e}");
    let lines: Vec<&str> = e
        .lines()
        .filter(|l| l.starts_with("irradia: radiosity"))
        .collect();
    assert!(!lines.is_empty(), "no progress lines:\n{e}");
    assert!(lines.iter().all(|l| l.contains("elapsed")), "{lines:?}");
    // --quiet: none.
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_irradia"))
        .args(["radiosity", "--elements", "400", "-o", "r.png", "--quiet"])
        .env("IRRADIA_PROGRESS_INTERVAL", "0.05")
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(
        o.status.success() && stderr(&o).is_empty(),
        "{}",
        stderr(&o)
    );
}
