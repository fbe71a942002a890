//! Tiny triangles drawn as fragments made in the geometry stage (`render_mesh` and
//! `render_triangles` on the interpolated-colour RGBA8 path) give, bit for bit, the
//! framebuffer of drawing the same screen triangles with `rasterize` (which never makes
//! fragments), for every depth test and in submission order: every triangle is drawn
//! twice, the second time in another colour, so a fragment drawn out of its place in
//! the order would show.

#[path = "common/scenes.rs"]
mod scenes;

use glam::Vec3;
use irradia_geometry::generators::random_triangles::SizeDistribution;
use irradia_raster::rasterizer::row_range;
use irradia_raster::{ColorFormat, DepthFunc, Framebuffer, Mesh, Pipeline, Rect, Shading};
use scenes::{pool, random_scene, Copies};

/// Mostly sub-pixel triangles (some large), each given twice with other colours.
fn scene() -> (Pipeline, Mesh) {
    random_scene(
        30_000,
        SizeDistribution::Exponential { mean: 0.002 },
        11,
        Vec3::new(0.3, 0.2, 2.5),
        Some(Copies {
            period: 97,
            alpha: 0.5,
        }),
    )
}

#[test]
fn most_screen_triangles_are_tiny() {
    let (p, mesh) = scene();
    let tris = p.transform_mesh(&mesh).unwrap();
    let tiny = tris
        .iter()
        .filter(|t| {
            let (x0, x1, y0, y1) = row_range(t);
            (x1 - x0 + 1) * (y1 - y0 + 1) <= 4
        })
        .count();
    assert!(tris.len() > 20_000, "{} screen triangles", tris.len());
    assert!(tiny * 2 > tris.len(), "{tiny} of {} tiny", tris.len());
    assert!(tiny < tris.len(), "some triangles are drawn as triangles");
}

#[test]
fn fragments_of_tiny_triangles_equal_drawing_the_triangles() {
    let (mut p, mesh) = scene();
    let soup = mesh.to_triangles();
    for shading in [Shading::Gouraud, Shading::Unlit] {
        for func in [DepthFunc::Less, DepthFunc::LessEqual, DepthFunc::Always] {
            p.shading = shading;
            p.depth_func = func;
            let tris = p.transform_mesh(&mesh).unwrap();
            let mut drawn = Framebuffer::new(p.width, p.height, ColorFormat::Rgba8).unwrap();
            p.rasterize(&tris, &mut drawn, None).unwrap();
            assert!(
                drawn.depth.iter().filter(|&&d| d < 1.0).count() > 3000,
                "the scene covers the screen"
            );
            let mut drawn_soup = Framebuffer::new(p.width, p.height, ColorFormat::Rgba8).unwrap();
            p.rasterize(&p.transform_and_light(&soup), &mut drawn_soup, None)
                .unwrap();
            for threads in [1, 2] {
                let mut fused = Framebuffer::new(p.width, p.height, ColorFormat::Rgba8).unwrap();
                pool(threads).install(|| p.render_mesh(&mesh, &mut fused).unwrap());
                assert!(
                    drawn == fused,
                    "render_mesh: {shading:?} {func:?} {threads} threads"
                );
                let mut fused = Framebuffer::new(p.width, p.height, ColorFormat::Rgba8).unwrap();
                pool(threads).install(|| p.render_triangles(&soup, &mut fused).unwrap());
                assert!(
                    drawn_soup == fused,
                    "render_triangles: {shading:?} {func:?} {threads} threads"
                );
            }
        }
    }
}

#[test]
fn a_region_of_tiny_triangles_equals_the_whole_screen_there() {
    // `rasterize` with a region (sort-first) against the fused whole-screen render.
    let (p, mesh) = scene();
    let tris = p.transform_mesh(&mesh).unwrap();
    let mut fused = Framebuffer::new(p.width, p.height, ColorFormat::Rgba8).unwrap();
    p.render_mesh(&mesh, &mut fused).unwrap();
    let mut parts = Framebuffer::new(p.width, p.height, ColorFormat::Rgba8).unwrap();
    for r in [
        Rect::new(0, 0, 45, 33),
        Rect::new(45, 0, 96, 33),
        Rect::new(0, 33, 96, 64),
    ] {
        p.rasterize(&tris, &mut parts, Some(r)).unwrap();
    }
    assert!(fused == parts);
}
