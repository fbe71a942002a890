//! Renders a scene file or built-in with the Whitted/path integrator and prints the
//! render time, without the CLI (for profiling the integrator alone):
//! `cargo run --release -p irradia-render --example render_file -- SCENE|builtin:NAME OUT.png [THREADS]`

use irradia_render::{render, RenderOptions};
use std::path::Path;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() < 3 {
        eprintln!("usage: render_file SCENE|builtin:NAME OUT.png [THREADS]");
        std::process::exit(2);
    }
    let scene = match args[1].strip_prefix("builtin:") {
        Some(name) => irradia_scene::builtin::load(name),
        None => irradia_scene::load_file(Path::new(&args[1])),
    }
    .unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(2)
    });
    let threads = args.get(3).and_then(|t| t.parse().ok());
    let out = render(
        &scene,
        &RenderOptions {
            threads,
            ..RenderOptions::default()
        },
    )
    .expect("render");
    irradia_core::io::save(&out.image, Path::new(&args[2])).expect("save");
    eprintln!(
        "{:.3} s, {} rays, {:.2} Mrays/s",
        out.elapsed.as_secs_f64(),
        out.stats.total_rays(),
        out.stats.total_rays() as f64 / out.elapsed.as_secs_f64() / 1e6
    );
}
