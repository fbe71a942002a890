//! Path-traces a built-in scene: `cargo run --release -p irradia-render --example
//! path_builtin -- NAME OUT.png [SPP] [WIDTH]` (a developer's check; the CLI is the
//! user's way).
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let name = args.get(1).map(String::as_str).unwrap_or("cornell");
    let out = args.get(2).map(String::as_str).unwrap_or("cornell.png");
    let mut scene = irradia_scene::builtin::load(name).unwrap_or_else(|e| panic!("{e}"));
    if let Some(spp) = args.get(3) {
        scene.settings.spp = spp.parse().unwrap();
    }
    if let Some(w) = args.get(4) {
        let w: u32 = w.parse().unwrap();
        scene.settings.height = scene.settings.height * w / scene.settings.width;
        scene.settings.width = w;
    }
    scene.settings.integrator = irradia_scene::Integrator::Path;
    let t = std::time::Instant::now();
    let o = irradia_render::render(&scene, &irradia_render::RenderOptions::default()).unwrap();
    let secs = t.elapsed().as_secs_f64();
    println!(
        "{name}: {}x{} {} spp in {secs:.2} s: {:.2} Msamples/s",
        scene.settings.width,
        scene.settings.height,
        scene.settings.spp,
        o.stats.samples as f64 / secs / 1e6
    );
    irradia_core::io::save(&o.image, std::path::Path::new(out)).unwrap();
}
