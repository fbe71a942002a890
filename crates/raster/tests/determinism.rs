//! The image does not depend on the number of threads, and drawing the screen region by
//! region (sort-first) gives the same framebuffer as drawing it whole.

#[path = "common/scenes.rs"]
mod scenes;

use glam::Vec3;
use irradia_geometry::generators::random_triangles::SizeDistribution;
use irradia_raster::{ColorFormat, Framebuffer, Mesh, Pipeline, Rect, Shading};
use scenes::{pool, random_scene};

fn scene() -> (Pipeline, Mesh) {
    random_scene(
        20_000,
        SizeDistribution::Exponential { mean: 0.01 },
        3,
        Vec3::new(0.3, 0.2, 2.5),
        None,
    )
}

fn render(threads: usize, p: &Pipeline, mesh: &Mesh, format: ColorFormat) -> Framebuffer {
    let pool = pool(threads);
    let mut fb = Framebuffer::new(p.width, p.height, format).unwrap();
    pool.install(|| p.render_mesh(mesh, &mut fb)).unwrap();
    fb
}

#[test]
fn one_two_and_three_threads_give_identical_framebuffers() {
    let (mut p, mesh) = scene();
    for (shading, format) in [
        (Shading::Gouraud, ColorFormat::Rgba8),
        (Shading::Phong, ColorFormat::Rgba32F),
        (Shading::Unlit, ColorFormat::Id),
    ] {
        p.shading = shading;
        let one = render(1, &p, &mesh, format);
        assert!(
            one.depth.iter().filter(|&&d| d < 1.0).count() > 1000,
            "the scene covers the screen"
        );
        for t in [2, 3] {
            let many = render(t, &p, &mesh, format);
            assert!(
                one == many,
                "{shading:?} {format:?}: {t} threads differ from 1"
            );
        }
    }
}

#[test]
fn regions_drawn_separately_equal_the_whole_screen() {
    let (p, mesh) = scene();
    let tris = p.transform_mesh(&mesh).unwrap();
    let mut whole = Framebuffer::new(p.width, p.height, ColorFormat::Rgba32F).unwrap();
    p.rasterize(&tris, &mut whole, None).unwrap();
    let fused = render(2, &p, &mesh, ColorFormat::Rgba32F);
    assert!(
        whole == fused,
        "render_mesh equals transform_mesh + rasterize"
    );
    let mut parts = Framebuffer::new(p.width, p.height, ColorFormat::Rgba32F).unwrap();
    for r in [
        Rect::new(0, 0, 50, 37),
        Rect::new(50, 0, 96, 37),
        Rect::new(0, 37, 31, 64),
        Rect::new(31, 37, 96, 64),
    ] {
        p.rasterize(&tris, &mut parts, Some(r)).unwrap();
    }
    assert!(whole == parts);
    // And a region only touches its own pixels.
    let mut one = Framebuffer::new(p.width, p.height, ColorFormat::Rgba32F).unwrap();
    p.rasterize(&tris, &mut one, Some(Rect::new(10, 10, 20, 20)))
        .unwrap();
    for y in 0..p.height {
        for x in 0..p.width {
            let inside = (10..20).contains(&x) && (10..20).contains(&y);
            if !inside {
                assert_eq!(one.depth_at(x, y), 1.0);
            } else {
                assert_eq!(one.depth_at(x, y), whole.depth_at(x, y));
            }
        }
    }
}

#[test]
fn screen_triangles_survive_the_byte_encoding() {
    let (p, mesh) = scene();
    let tris = p.transform_mesh(&mesh).unwrap();
    let mut bytes = Vec::new();
    for t in &tris {
        t.write_bytes(&mut bytes);
    }
    let back: Vec<_> = bytes
        .chunks(irradia_raster::SCREEN_TRIANGLE_BYTES)
        .map(|c| irradia_raster::ScreenTriangle::read_bytes(c).unwrap())
        .collect();
    assert_eq!(back, tris);
}
