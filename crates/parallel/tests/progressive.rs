//! One image on several ranks (`irradia_parallel::progressive`): every integrator, on
//! 1 to 5 ranks (threads of this process), equals the one-process render bit for bit,
//! AOVs and ray counts included; a resumed checkpoint too; a rank that dies ends the
//! job with an error naming it.

use irradia_parallel::comm::{run_local, LocalOptions};
use irradia_parallel::progressive::render_distributed;
use irradia_render::{render, Aov, RenderOptions, RenderOutput};
use irradia_scene::{Integrator, Scene};
use std::time::Duration;

fn scene(name: &str, w: u32, h: u32, spp: u32) -> Scene {
    let mut s = irradia_scene::builtin::load(name).unwrap();
    s.settings.width = w;
    s.settings.height = h;
    s.settings.spp = spp;
    s
}

fn options() -> RenderOptions {
    RenderOptions {
        threads: Some(1),
        tile_size: 16,
        aovs: vec![Aov::Depth, Aov::ObjectId],
        ..RenderOptions::default()
    }
}

fn on_ranks(n: usize, scene: &Scene, options: &RenderOptions) -> RenderOutput {
    let local = LocalOptions {
        timeout: Duration::from_secs(60),
        delay: None,
    };
    let mut outs = run_local(n, local, |c| {
        irradia_render::pool::with_threads(Some(1), || render_distributed(c, scene, options))
            .and_then(|r| r)
    });
    for (r, o) in outs.iter().enumerate().skip(1) {
        assert!(matches!(o, Ok(Ok(None))), "rank {r}: {o:?}");
    }
    outs.swap_remove(0).unwrap().unwrap().unwrap()
}

fn assert_same(a: &RenderOutput, b: &RenderOutput, what: &str) {
    assert_eq!(a.image.pixels(), b.image.pixels(), "{what}: image");
    assert_eq!(a.aovs.len(), b.aovs.len());
    for ((ka, ia), (kb, ib)) in a.aovs.iter().zip(&b.aovs) {
        assert_eq!(ka, kb);
        assert_eq!(ia.pixels(), ib.pixels(), "{what}: aov {}", ka.name());
    }
    assert_eq!(a.samples, b.samples, "{what}: samples");
    assert_eq!(a.stats.total_rays(), b.stats.total_rays(), "{what}: rays");
    assert_eq!(a.stats.samples, b.stats.samples, "{what}: samples counted");
}

#[test]
fn the_path_tracer_on_any_number_of_ranks_equals_one_process() {
    // 70x50 in 16-pixel tiles: edge tiles of other sizes; 13 spp: passes 1, 2, 4, 6.
    let s = scene("cornell", 70, 50, 13);
    assert!(matches!(s.settings.integrator, Integrator::Path));
    let serial = render(&s, &options()).unwrap();
    for n in 1..=5 {
        assert_same(&on_ranks(n, &s, &options()), &serial, &format!("{n} ranks"));
    }
}

#[test]
fn the_whitted_tracer_on_ranks_equals_one_process() {
    for name in ["whitted", "csg"] {
        let s = scene(name, 64, 36, 4);
        let serial = render(&s, &options()).unwrap();
        for n in [2, 3] {
            assert_same(
                &on_ranks(n, &s, &options()),
                &serial,
                &format!("{name}, {n} ranks"),
            );
        }
    }
}

#[test]
fn adaptive_supersampling_on_ranks_equals_one_process() {
    let mut s = scene("whitted", 64, 36, 4);
    s.settings.adaptive_threshold = Some(0.1);
    let serial = render(&s, &options()).unwrap();
    assert!(serial.stats.refined_pixels > 0);
    assert_same(&on_ranks(3, &s, &options()), &serial, "adaptive");
}

#[test]
fn a_resumed_checkpoint_on_ranks_equals_one_process() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene("cornell", 40, 30, 12);
    let serial = render(&s, &options()).unwrap();
    // 5 spp on 3 ranks, checkpointed; then resumed to 12 on 2 ranks.
    let ck = dir.path().join("c.film");
    let first = RenderOptions {
        spp: Some(5),
        checkpoint: Some(ck.clone()),
        ..options()
    };
    assert_eq!(on_ranks(3, &s, &first).samples, 5);
    let resumed = RenderOptions {
        resume: Some(ck),
        ..options()
    };
    let out = on_ranks(2, &s, &resumed);
    assert_eq!(out.image.pixels(), serial.image.pixels());
    assert_eq!(out.samples, 12);
}

#[test]
fn a_rank_that_dies_ends_the_job_with_an_error_naming_it() {
    let s = scene("cornell", 64, 64, 64);
    let local = LocalOptions {
        timeout: Duration::from_secs(20),
        delay: None,
    };
    let t = std::time::Instant::now();
    let outs = run_local(3, local, |c| {
        if irradia_parallel::comm::Comm::rank(c) == 2 {
            panic!("killed");
        }
        render_distributed(c, &s, &options())
    });
    let msg = match &outs[0] {
        Ok(Err(e)) => e.to_string(),
        Err(e) => e.to_string(),
        Ok(Ok(_)) => panic!("rank 0 finished although rank 2 died"),
    };
    assert!(msg.contains("rank 2"), "{msg}");
    assert!(
        t.elapsed() < Duration::from_secs(15),
        "took {:?}",
        t.elapsed()
    );
}
