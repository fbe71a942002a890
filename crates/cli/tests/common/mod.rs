//! Helpers shared by the CLI's end-to-end tests: run the built `irradia` binary and read
//! what it printed.
#![allow(dead_code)] // each test binary uses its own subset

use std::path::Path;
use std::process::{Command, Output};

/// Runs `irradia ARGS` in `dir` and returns its exit status and output.
pub fn irradia(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_irradia"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the irradia binary runs")
}

/// What the run printed on standard error.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Sum of r + g + b over the pixels where the mirror sphere of the specular Cornell box
/// lies in a 32x32 image (lower left): near 0 where it is a black stand-in (Gouraud),
/// bright where it is traced as a mirror (two-pass).
pub fn mirror_sphere_sum(im: &irradia_core::Image) -> f32 {
    let mut s = 0.0;
    for y in 19..24 {
        for x in 13..19 {
            let p = im.get(x, y);
            s += p.r + p.g + p.b;
        }
    }
    s
}
