//! Ray trees come from the renderer's own code path.

mod common;

use irradia_render::{render, trace_pixel, RayKind, RenderOptions};

#[test]
fn trace_pixel_matches_the_rendered_pixel_and_lists_every_ray() {
    let scene = common::showcase(40, 30);
    let out = render(&scene, &RenderOptions::default()).unwrap();
    // A pixel on the mirror ball: reflected rays and shadow rays appear.
    let mut found_reflection = false;
    for (x, y) in [(26, 15), (25, 14), (27, 16), (20, 20), (10, 15)] {
        let (tree, c) = trace_pixel(&scene, x, y, 0).unwrap();
        assert_eq!(
            c,
            out.image.get(x, y),
            "same code, same radiance at ({x},{y})"
        );
        assert_eq!(tree.kind, RayKind::Camera);
        assert_eq!(tree.depth, 1);
        let sum: f32 = tree.contribution.iter().sum();
        assert!((sum - (c.r + c.g + c.b)).abs() < 1e-4);
        if tree.children.iter().any(|n| n.kind == RayKind::Reflected) {
            found_reflection = true;
            let json = serde_json::to_string(&tree).unwrap();
            let back: serde_json::Value = serde_json::from_str(&json).unwrap();
            assert_eq!(back["kind"], "camera");
            let dot = tree.to_dot();
            assert!(dot.starts_with("digraph raytree {") && dot.trim_end().ends_with('}'));
            assert_eq!(dot.matches("->").count(), tree.count() - 1);
            let text = tree.to_text();
            assert!(text.contains("reflected ray, depth 2"));
            assert!(text.contains("shadow ray"));
        }
    }
    assert!(found_reflection, "one of the pixels sees the mirror");
    assert!(trace_pixel(&scene, 40, 0, 0).is_err());
}
