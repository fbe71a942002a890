//! Every built-in scene renders small, finite and not black, and the same for any
//! thread count and tile size.

use irradia_render::{render, RenderOptions};
use irradia_scene::{builtin, Integrator};

#[test]
fn builtins_render_small_and_ignore_threads_and_tiles() {
    let names = builtin::names();
    assert!(names.iter().any(|(n, _)| *n == "default"));
    for (name, _) in names {
        let mut scene = builtin::load(name).unwrap_or_else(|e| panic!("{name}: {e}"));
        if scene.settings.integrator != Integrator::Whitted {
            continue; // the path tracer has its own tests
        }
        scene.settings.width = 80;
        scene.settings.height = 45;
        scene.settings.spp = scene.settings.spp.min(4);
        let a = render(
            &scene,
            &RenderOptions {
                threads: Some(1),
                tile_size: 32,
                ..RenderOptions::default()
            },
        )
        .unwrap();
        let b = render(
            &scene,
            &RenderOptions {
                threads: Some(2),
                tile_size: 9,
                ..RenderOptions::default()
            },
        )
        .unwrap();
        assert_eq!(a.image, b.image, "{name}: threads/tiles changed the image");
        assert!(
            a.image.pixels().iter().all(|p| p.is_finite()),
            "{name}: non-finite pixel"
        );
        let mean = a.image.mean();
        assert!(mean.max_component() > 0.02, "{name}: black image {mean:?}");
        assert!(a.stats.camera_rays >= 80 * 45, "{name}");
    }
}
