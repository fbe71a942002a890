//! Every example command of README.md and docs/*.md, run as written: the lines of the
//! code blocks that start with `irradia` (with `\` continuations joined, `# comments`
//! dropped, pipes, `>` and `&&` kept) run through `sh` in a fresh folder that sees the
//! repository's `docs/` and `crates/`, with `irradia` the binary under test. Each must
//! exit 0 within [`LIMIT`]. The commands that cannot run here are skipped, each for a
//! reason listed in [`SKIP`] (long renders, MPI, synopses with placeholders); a skip
//! that matches no command fails too, so the list cannot go stale.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The longest one example may take.
const LIMIT: Duration = Duration::from_secs(120);

/// Commands not run: a piece of the command, and why.
const SKIP: &[(&str, &str)] = &[
    (
        "mpirun",
        "needs MPI (mpirun and a build with --features mpi)",
    ),
    (
        "--comm mpi",
        "needs MPI (mpirun and a build with --features mpi)",
    ),
    ("cargo run --release", "builds the release binary (minutes)"),
    ("irradia render [SCENE]", "a synopsis with placeholders"),
    (
        "irradia convert SCENE -o OUT.toml",
        "a synopsis with placeholders",
    ),
    (
        "irradia trace-pixel [SCENE]",
        "a synopsis with placeholders",
    ),
    (
        "--mode sort-first|sort-middle|sort-last",
        "a synopsis with placeholders",
    ),
    (
        "irradia bench parallel [--ranks",
        "a synopsis with placeholders",
    ),
    ("-o DIR", "a synopsis with placeholders"),
    (
        "irradia bench scale",
        "measures this machine's rates first (seconds in a release build, minutes in the test build)",
    ),
    (
        "--spp 4096",
        "4096 samples per pixel of the 512x512 Cornell box (minutes)",
    ),
    ("--time 30", "a 30 s time budget"),
    (
        "--builtin cornell -o cornell.png",
        "the 512x512 Cornell box at 64 spp (a minute on a laptop, more here)",
    ),
    (
        "--elements 20000",
        "20000 hierarchical elements of the room (minutes)",
    ),
    (
        "scene.toml --integrator path --spp 256",
        "the 512x512 Cornell box at 256 spp (minutes)",
    ),
];

/// The repository's root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// (file:line, command) of every example.
fn examples() -> Vec<(String, String)> {
    let root = root();
    let mut files = vec![root.join("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .expect("docs/")
        .map(|e| e.expect("an entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    files.extend(docs);
    let mut out = Vec::new();
    for f in files {
        let text = std::fs::read_to_string(&f).expect("a markdown file");
        let name = f.strip_prefix(&root).unwrap_or(&f).display().to_string();
        let mut in_block = false;
        let mut pending: Option<(usize, String)> = None;
        for (i, line) in text.lines().enumerate() {
            if line.trim_start().starts_with("```") {
                in_block = !in_block;
                continue;
            }
            if !in_block {
                continue;
            }
            let line = line.trim();
            let (start, mut cmd) = match pending.take() {
                Some((s, c)) => (s, format!("{c} {line}")),
                None => {
                    let l = line.strip_prefix("$ ").unwrap_or(line);
                    if !(l.starts_with("irradia ")
                        || l == "irradia"
                        || l.starts_with("mpirun ")
                        || l.starts_with("cargo run"))
                    {
                        continue;
                    }
                    (i + 1, l.to_string())
                }
            };
            if let Some(c) = cmd.strip_suffix('\\') {
                pending = Some((start, c.trim_end().to_string()));
                continue;
            }
            if let Some(k) = cmd.find(" #") {
                cmd.truncate(k);
            }
            out.push((format!("{name}:{start}"), cmd.trim().to_string()));
        }
    }
    out
}

fn skip_reason(cmd: &str) -> Option<&'static str> {
    SKIP.iter().find(|(p, _)| cmd.contains(p)).map(|(_, r)| *r)
}

/// Runs `cmd` through sh in `dir`; its process group is killed at [`LIMIT`].
fn run(cmd: &str, dir: &Path, bin_dir: &Path) -> Result<Duration, String> {
    use std::os::unix::process::CommandExt;
    let path = format!(
        "{}:{}",
        bin_dir.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let t = Instant::now();
    let mut child = Command::new("sh")
        .args(["-c", cmd])
        .current_dir(dir)
        .env("PATH", path)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .process_group(0)
        .spawn()
        .map_err(|e| format!("sh: {e}"))?;
    loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            let mut err = String::new();
            if let Some(mut s) = child.stderr.take() {
                use std::io::Read;
                let _ = s.read_to_string(&mut err);
            }
            return if status.success() {
                Ok(t.elapsed())
            } else {
                Err(format!("{status}: {}", err.trim()))
            };
        }
        if t.elapsed() > LIMIT {
            let _ = Command::new("kill")
                .args(["-KILL", &format!("-{}", child.id())])
                .status();
            let _ = child.wait();
            return Err(format!(
                "took longer than {} s: make it quicker or list it in SKIP with a reason",
                LIMIT.as_secs()
            ));
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

#[test]
fn every_quick_documented_example_runs_as_written() {
    let all = examples();
    assert!(all.len() > 40, "found only {} examples", all.len());
    for (pattern, reason) in SKIP {
        assert!(
            all.iter().any(|(_, c)| c.contains(pattern)),
            "SKIP entry {pattern:?} ({reason}) matches no documented command"
        );
    }
    let dir = tempfile::tempdir().unwrap();
    for name in ["docs", "crates", "tests"] {
        std::os::unix::fs::symlink(root().join(name), dir.path().join(name)).unwrap();
    }
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_irradia"));
    let bin_dir = bin.parent().unwrap();
    let mut failures = Vec::new();
    let mut skipped = 0;
    for (place, cmd) in &all {
        if let Some(reason) = skip_reason(cmd) {
            eprintln!("skip {place}: {cmd}\n     ({reason})");
            skipped += 1;
            continue;
        }
        match run(cmd, dir.path(), bin_dir) {
            Ok(t) => eprintln!("ok   {place} ({:.1} s): {cmd}", t.as_secs_f64()),
            Err(e) => failures.push(format!("{place}: {cmd}\n    {e}")),
        }
    }
    eprintln!("{} run, {skipped} skipped", all.len() - skipped);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn extraction_joins_continuations_and_drops_comments() {
    let all = examples();
    let readme = all
        .iter()
        .find(|(p, c)| p.starts_with("README.md") && c.contains("--object-shading forward"))
        .expect("README's forwarding example");
    assert!(!readme.1.contains('\\'), "{}", readme.1);
    let scenes = all
        .iter()
        .find(|(p, c)| p.starts_with("README.md") && c.starts_with("irradia scenes"))
        .expect("README's scenes example");
    assert_eq!(scenes.1, "irradia scenes");
}
