//! `trace_pixel` on path-traced scenes: the recorded sample is the sample the renderer
//! adds to the film (same stream, same estimator), and the tree accounts for it: the
//! weighted radiance added at the vertices sums to the sample, each segment returns
//! what it and the rest of the path add, and the path ends where the estimator says.

mod path_common;

use irradia_core::Rgb;
use irradia_render::driver::ProgressiveOptions;
use irradia_render::path::{self, Kernel, PathParams};
use irradia_render::raytree::{RayKind, RayNode};
use irradia_render::Film;
use irradia_scene::Scene;
use std::time::Duration;

fn rgb(a: [f32; 3]) -> Rgb {
    Rgb::from_array(a)
}

fn close(a: Rgb, b: Rgb, tol: f32) -> bool {
    let d = (a - b)
        .max_component()
        .abs()
        .max((b - a).max_component().abs());
    d <= tol * (1.0 + a.max_component().abs().max(b.max_component().abs()))
}

/// Sum over segments of weight x local (what each vertex adds to the pixel).
fn added(n: &RayNode) -> Rgb {
    let own = if n.kind == RayKind::Shadow || n.cut.is_some() {
        Rgb::BLACK
    } else {
        rgb(n.weight) * rgb(n.local)
    };
    n.children.iter().map(added).fold(own, |a, b| a + b)
}

/// Checks the shape of one path's tree; returns the number of segments.
fn check_shape(n: &RayNode, max_depth: u32) -> u32 {
    assert!(
        n.depth < max_depth,
        "segment at depth {} >= {max_depth}",
        n.depth
    );
    let segments: Vec<&RayNode> = n
        .children
        .iter()
        .filter(|c| c.kind != RayKind::Shadow && c.cut.is_none())
        .collect();
    let shadows = n
        .children
        .iter()
        .filter(|c| c.kind == RayKind::Shadow)
        .count();
    assert!(
        segments.len() <= 1 && shadows <= 1,
        "a path vertex has one continuation and one shadow ray at most"
    );
    // What a segment returns: its own addition plus what the next one returns.
    let rest = segments
        .first()
        .map_or(Rgb::BLACK, |c| rgb(c.weight) * rgb(c.radiance));
    let want = rgb(n.weight) * rgb(n.local) + rest;
    assert!(
        close(rgb(n.weight) * rgb(n.radiance), want, 1e-4),
        "segment at depth {}: returns {:?}, adds {:?} + rest {:?}",
        n.depth,
        n.radiance,
        n.local,
        rest
    );
    1 + segments.first().map_or(0, |c| check_shape(c, max_depth))
}

/// Film value of every pixel after sample 0 only, with the scalar estimator.
fn one_sample_film(scene: &Scene) -> irradia_core::Image {
    let s = &scene.settings;
    let params = PathParams {
        max_depth: s.max_depth,
        ..PathParams::default()
    };
    let options = ProgressiveOptions {
        spp: 1,
        checkpoint_interval: Duration::MAX,
        ..Default::default()
    };
    let film = Film::new(s.width, s.height).unwrap();
    path::path_integrator::render_with(scene, &params, &options, Kernel::Scalar, film, |_, _| {})
        .unwrap()
        .film
        .image()
}

fn check_scene(scene: &Scene) {
    let film = one_sample_film(scene);
    let (mut lit, mut long) = (0, 0);
    for y in 0..scene.settings.height {
        for x in 0..scene.settings.width {
            let (tree, l) = irradia_render::trace_pixel(scene, x, y, 0).unwrap();
            assert_eq!(tree.kind, RayKind::Camera);
            assert_eq!(
                l,
                film.get(x, y),
                "pixel ({x}, {y}): the traced sample differs from the rendered one"
            );
            assert!(
                close(rgb(tree.radiance), l, 1e-5),
                "root returns the sample"
            );
            assert!(
                close(added(&tree), l, 1e-4),
                "the vertices add up to the sample"
            );
            let segments = check_shape(&tree, scene.settings.max_depth);
            lit += (l.max_component() > 0.0) as u32;
            long += (segments >= 3) as u32;
        }
    }
    let n = scene.settings.width * scene.settings.height;
    assert!(
        lit * 2 > n && long > 0,
        "{lit} lit and {long} long paths of {n}"
    );
}

#[test]
fn traced_samples_are_the_rendered_samples_and_add_up() {
    check_scene(&path_common::small_room());
    check_scene(&path_common::soft_room());
    check_scene(
        &irradia_scene::builtin::load("cornell")
            .map(|mut s| {
                s.settings.width = 12;
                s.settings.height = 12;
                s
            })
            .unwrap(),
    );
}

#[test]
fn paths_end_at_the_depth_limit_with_a_cut() {
    let mut scene = path_common::soft_room();
    scene.settings.max_depth = 2;
    let mut cut_at_depth = 0;
    for x in 0..scene.settings.width {
        let (tree, _) = irradia_render::trace_pixel(&scene, x, 6, 0).unwrap();
        assert!(check_shape(&tree, 2) <= 2);
        let mut n = &tree;
        while let Some(next) = n
            .children
            .iter()
            .find(|c| c.kind != RayKind::Shadow && c.cut.is_none())
        {
            n = next;
        }
        if n.children.iter().any(|c| c.cut == Some("depth")) {
            assert_eq!(n.depth, 1, "the last segment of a depth-2 path");
            cut_at_depth += 1;
        }
    }
    assert!(cut_at_depth > 0, "no path reached the depth limit");
}
