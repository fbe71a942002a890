//! Coverage of pbrt-v4 files: `cargo run -p irradia-import --example pbrt_coverage --
//! FILE.pbrt ...` parses each file without loading anything it references and prints,
//! per directive and per shape, material, light, texture, camera, ... type, how often
//! it occurs and how it was treated (docs/importers.md's table comes from this).

use irradia_import::pbrt::{coverage_str, Coverage, Status};
use std::path::Path;

fn main() {
    let mut all = Coverage::default();
    let mut files = 0;
    for arg in std::env::args().skip(1) {
        let path = Path::new(&arg);
        let Ok(text) = std::fs::read_to_string(path) else {
            eprintln!("cannot read {arg}");
            continue;
        };
        let c = coverage_str(&text, path);
        for e in &c.errors {
            eprintln!("{e}");
        }
        all.merge(&c);
        files += 1;
    }
    println!("{files} files\n");
    println!("| kind | name | uses | supported | warned | refused |");
    println!("|---|---|---|---|---|---|");
    for ((cat, name), m) in &all.counts {
        let n = |s: Status| m.get(&s).copied().unwrap_or(0);
        let total: usize = m.values().sum();
        println!(
            "| {cat} | `{name}` | {total} | {} | {} | {} |",
            n(Status::Supported),
            n(Status::Warned),
            n(Status::Refused)
        );
    }
}
