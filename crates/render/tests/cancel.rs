//! The cancel flag of `RenderOptions`: set before or during a render it stops the
//! render with `RenderError::Cancelled`; left unset it changes nothing.

use irradia_render::{render, RenderError, RenderOptions};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

fn scene() -> irradia_scene::Scene {
    let mut s = irradia_scene::builtin::load("whitted").unwrap();
    s.settings.width = 48;
    s.settings.height = 32;
    s
}

#[test]
fn a_set_flag_cancels_and_an_unset_one_changes_nothing() {
    let s = scene();
    let plain = render(&s, &RenderOptions::default()).unwrap();
    let flag = Arc::new(AtomicBool::new(false));
    let options = RenderOptions {
        cancel: Some(flag.clone()),
        tile_size: 8,
        ..RenderOptions::default()
    };
    let same = render(&s, &options).unwrap();
    assert_eq!(plain.image, same.image);
    flag.store(true, Ordering::Relaxed);
    assert!(matches!(render(&s, &options), Err(RenderError::Cancelled)));
}

#[test]
fn a_flag_set_from_the_progress_callback_stops_the_render() {
    let mut s = irradia_scene::builtin::load("cornell").unwrap();
    s.settings.width = 64;
    s.settings.height = 64;
    let flag = Arc::new(AtomicBool::new(false));
    let tiles = Arc::new(std::sync::atomic::AtomicU64::new(0));
    let (f, t) = (flag.clone(), tiles.clone());
    let options = RenderOptions {
        cancel: Some(flag),
        tile_size: 8,
        threads: Some(1),
        spp: Some(1 << 20),
        progress: Some(Arc::new(move |_p: &irradia_render::Progress| {
            if t.fetch_add(1, Ordering::Relaxed) == 3 {
                f.store(true, Ordering::Relaxed);
            }
        })),
        ..RenderOptions::default()
    };
    assert!(matches!(render(&s, &options), Err(RenderError::Cancelled)));
    // One thread: the tile that set the flag is the last rendered.
    assert_eq!(tiles.load(Ordering::Relaxed), 4);
}
