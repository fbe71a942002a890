//! The Whitted tracer's pictures of every built-in scene stay the same through
//! refactoring: each is compared with the 8-bit sRGB image stored in
//! `tests/data/whitted_golden/` (rendered before the renderer was restructured, issue
//! 12). A pixel may differ by rounding only: at most 1/255 per channel, on under 0.1% of
//! the pixels. Regenerate deliberately with `IRRADIA_BLESS=1 cargo test -p irradia-render
//! --test whitted_golden` (and say why in the commit).

use irradia_render::{render, RenderOptions};
use irradia_scene::{builtin, Integrator};
use std::path::PathBuf;

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;

fn golden_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/whitted_golden")
        .join(format!("{name}.png"))
}

/// The built-in `name` traced by the Whitted tracer at the golden size, as sRGB bytes.
fn whitted_bytes(name: &str) -> Vec<u8> {
    let mut scene = builtin::load(name).unwrap_or_else(|e| panic!("{name}: {e}"));
    scene.settings.integrator = Integrator::Whitted;
    scene.settings.width = WIDTH;
    scene.settings.height = HEIGHT;
    scene.settings.spp = scene.settings.spp.clamp(1, 4);
    let out = render(&scene, &RenderOptions::default()).unwrap();
    out.image.to_srgb8()
}

#[test]
fn whitted_images_of_every_builtin_match_the_stored_ones() {
    let bless = std::env::var_os("IRRADIA_BLESS").is_some();
    let mut failures = Vec::new();
    for (name, _) in builtin::names() {
        let bytes = whitted_bytes(name);
        let path = golden_path(name);
        if bless {
            image::save_buffer(&path, &bytes, WIDTH, HEIGHT, image::ColorType::Rgb8).unwrap();
            continue;
        }
        let stored = image::open(&path)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
            .to_rgb8();
        assert_eq!(stored.dimensions(), (WIDTH, HEIGHT), "{name}");
        let stored = stored.into_raw();
        let mut off_by_one = 0usize;
        let mut worst = 0u8;
        for (p, q) in bytes.chunks_exact(3).zip(stored.chunks_exact(3)) {
            let d = p.iter().zip(q).map(|(a, b)| a.abs_diff(*b)).max().unwrap();
            worst = worst.max(d);
            off_by_one += usize::from(d > 0);
        }
        let pixels = (WIDTH * HEIGHT) as usize;
        // Under 0.1% of the pixels may differ, and those by one step only.
        if worst > 1 || off_by_one * 1000 >= pixels {
            failures.push(format!(
                "{name}: {off_by_one} of {pixels} pixels differ, by up to {worst}/255"
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn a_changed_pixel_is_caught() {
    // The comparison itself must be able to fail: the default scene with one brighter
    // material differs from its stored image by more than rounding.
    let mut scene = builtin::load("default").unwrap();
    scene.settings.integrator = Integrator::Whitted;
    scene.settings.width = WIDTH;
    scene.settings.height = HEIGHT;
    scene.settings.spp = scene.settings.spp.clamp(1, 4);
    scene.settings.max_depth = scene.settings.max_depth.saturating_sub(2).max(1);
    let bytes = render(&scene, &RenderOptions::default())
        .unwrap()
        .image
        .to_srgb8();
    let stored = image::open(golden_path("default"))
        .unwrap()
        .to_rgb8()
        .into_raw();
    let differing = bytes
        .chunks_exact(3)
        .zip(stored.chunks_exact(3))
        .filter(|(p, q)| p.iter().zip(q.iter()).any(|(a, b)| a.abs_diff(*b) > 1))
        .count();
    assert!(differing * 1000 >= (WIDTH * HEIGHT) as usize, "{differing}");
}
