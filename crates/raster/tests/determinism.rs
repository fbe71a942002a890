//! The image does not depend on the number of threads, and drawing the screen region by
//! region (sort-first) gives the same framebuffer as drawing it whole.

#[path = "common/scenes.rs"]
mod scenes;

use glam::Vec3;
use irradia_geometry::generators::random_triangles::SizeDistribution;
use irradia_raster::{ColorFormat, DepthFunc, Framebuffer, Mesh, Pipeline, Rect, Shading};
use scenes::{pool, random_scene, Copies};

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

/// The fused paths make and draw the triangles a group of batches at a time, testing
/// each group against the depth snapshot the bands refreshed while drawing the last:
/// scenes of several groups (a group of a soup is at least eight batches of 8192
/// triangles, of the shared-vertex path two per thread) give
/// the one-thread image and the image of the unfused stages, for a soup (occlusion
/// culling on: many layers on a small screen) drawn twice, the same soup as
/// independent triangles, and a mesh of shared vertices (the gyroid), under `Less` and
/// `LessEqual` (the later copy shows).
#[test]
fn scenes_of_several_groups_give_the_one_thread_image() {
    // Every triangle twice, the copies in the last groups: which copy shows depends on
    // the order in which the groups are drawn.
    let (mut p, soup) = random_scene(
        80_000,
        SizeDistribution::Exponential { mean: 0.01 },
        5,
        Vec3::new(0.3, 0.2, 2.5),
        Some(Copies {
            period: 7,
            alpha: 1.0,
        }),
    );
    let gyroid = Mesh::from_mesh_data(irradia_geometry::generators::gyroid::gyroid_mesh(96));
    assert!(
        gyroid.positions.len() < gyroid.indices.len(),
        "shared vertices"
    );
    let triangles = soup.to_triangles();
    for (shading, format, func) in [
        (Shading::Gouraud, ColorFormat::Rgba8, DepthFunc::Less),
        (Shading::Gouraud, ColorFormat::Rgba8, DepthFunc::LessEqual),
        (Shading::Phong, ColorFormat::Rgba32F, DepthFunc::LessEqual),
    ] {
        p.shading = shading;
        p.depth_func = func;
        for (name, mesh, eye) in [
            ("soup", &soup, Vec3::new(0.3, 0.2, 2.5)),
            ("gyroid", &gyroid, Vec3::new(1.5, 1.1, 1.9)),
        ] {
            // More than two groups of batches.
            assert!(
                mesh.indices.len() > 2 * 8 * 8192,
                "{name}: {}",
                mesh.indices.len()
            );
            p.view.view = glam::Mat4::look_at_rh(eye, Vec3::ZERO, Vec3::Y);
            let one = render(1, &p, mesh, format);
            let unfused = {
                let tris = p.transform_mesh(mesh).unwrap();
                let mut fb = Framebuffer::new(p.width, p.height, format).unwrap();
                p.rasterize(&tris, &mut fb, None).unwrap();
                fb
            };
            assert!(
                one == unfused,
                "{name} {shading:?} {func:?}: fused and unfused"
            );
            for t in [2, 3] {
                let many = render(t, &p, mesh, format);
                assert!(one == many, "{name} {shading:?} {func:?}: {t} threads");
            }
        }
        p.view.view = glam::Mat4::look_at_rh(Vec3::new(0.3, 0.2, 2.5), Vec3::ZERO, Vec3::Y);
        let independent = |t: usize| {
            let mut fb = Framebuffer::new(p.width, p.height, format).unwrap();
            pool(t)
                .install(|| p.render_triangles(&triangles, &mut fb))
                .unwrap();
            fb
        };
        let one = independent(1);
        for t in [2, 3] {
            assert!(
                one == independent(t),
                "triangles {shading:?} {func:?}: {t} threads"
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
