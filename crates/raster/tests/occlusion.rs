//! Occlusion culling in the fused paths (`render_mesh` on a soup, `render_triangles`):
//! after each group of batches the geometry stage tests the next group's triangles
//! against a snapshot of the depth buffer's tile bounds and drops, unlit, those that
//! cannot pass the depth test anywhere. The framebuffer must be, bit for bit, that of
//! `rasterize` on the same screen triangles (which never culls by depth), for `Less`,
//! `LessEqual` and `Always`. The scene is many layers deep (most triangles end up
//! hidden), more than one group long, and every triangle is given a second time, in
//! another colour, a group or more later: at equal depth `LessEqual` must draw the
//! copy and `Less` must not, so a test that rejects a triangle at equal depth under
//! `LessEqual` (or keeps the first copy's colour) shows.

#[path = "common/scenes.rs"]
mod scenes;

use glam::Vec3;
use irradia_geometry::generators::random_triangles::SizeDistribution;
use irradia_raster::{ColorFormat, DepthFunc, Framebuffer, Mesh, Pipeline, Shading, ViewParams};
use scenes::{pool, random_scene, Copies};

/// 80,000 triangles of about 40 pixels each on a 96 x 64 screen (about 500 layers),
/// then the same triangles again with other colours: more than two groups of batches
/// (a group is at least 65,536 triangles).
fn scene() -> (Pipeline, Mesh) {
    random_scene(
        80_000,
        SizeDistribution::Constant(0.02),
        5,
        Vec3::new(0.2, 0.3, 2.2),
        Some(Copies {
            period: 89,
            alpha: 1.0,
        }),
    )
}

#[test]
fn culling_hidden_triangles_before_lighting_changes_no_pixel() {
    let (mut p, mesh) = scene();
    let soup = mesh.to_triangles();
    for shading in [Shading::Gouraud, Shading::Phong] {
        for func in [DepthFunc::Less, DepthFunc::LessEqual, DepthFunc::Always] {
            p.shading = shading;
            p.depth_func = func;
            let tris = p.transform_mesh(&mesh).unwrap();
            assert!(tris.len() > 40_000, "{} screen triangles", tris.len());
            let mut drawn = Framebuffer::new(p.width, p.height, ColorFormat::Rgba8).unwrap();
            p.rasterize(&tris, &mut drawn, None).unwrap();
            let covered = drawn.depth.iter().filter(|&&d| d < 1.0).count();
            assert!(
                covered * 10 > drawn.depth.len() * 9,
                "the scene covers the screen: {covered} pixels"
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

/// A quad facing the camera (one depth at every pixel), 70,000 small triangles behind
/// it, then the quad again in another colour, groups later: under `LessEqual` the copy
/// passes everywhere at exactly the stored depth, which the tile bounds then equal, so
/// a test that took "not nearer than every stored depth" for hidden would drop it.
#[test]
fn a_copy_at_equal_depth_is_drawn_under_less_equal() {
    let mut positions = Vec::new();
    let mut colors = Vec::new();
    let mut indices = Vec::new();
    let mut add = |p: [Vec3; 3], c: [f32; 4]| {
        let n = positions.len() as u32;
        positions.extend_from_slice(&p);
        colors.extend_from_slice(&[c; 3]);
        indices.push([n, n + 1, n + 2]);
    };
    let quad = |add: &mut dyn FnMut([Vec3; 3], [f32; 4]), c: [f32; 4]| {
        let (a, b) = (Vec3::new(-2.0, -1.5, 0.0), Vec3::new(2.0, 1.5, 0.0));
        add([a, Vec3::new(b.x, a.y, 0.0), b], c);
        add([a, b, Vec3::new(a.x, b.y, 0.0)], c);
    };
    quad(&mut add, [0.9, 0.2, 0.1, 1.0]);
    for i in 0..70_000 {
        let x = (i % 100) as f32 * 0.03 - 1.5;
        let y = (i / 100 % 100) as f32 * 0.02 - 1.0;
        let p = Vec3::new(x, y, -0.5);
        add(
            [
                p,
                p + Vec3::new(0.1, 0.0, 0.0),
                p + Vec3::new(0.0, 0.1, 0.0),
            ],
            [0.1, 0.9, 0.1, 1.0],
        );
    }
    quad(&mut add, [0.1, 0.2, 0.9, 1.0]);
    let mut mesh = Mesh::new(positions, indices);
    mesh.colors = colors;
    mesh.compute_vertex_normals();
    let mut p = Pipeline::new(96, 64);
    p.view = ViewParams::look_at_perspective(
        Vec3::new(0.0, 0.0, 2.0),
        Vec3::ZERO,
        Vec3::Y,
        60.0,
        1.5,
        0.5,
        10.0,
    );
    p.shading = Shading::Unlit;
    for func in [DepthFunc::Less, DepthFunc::LessEqual] {
        p.depth_func = func;
        let mut drawn = Framebuffer::new(p.width, p.height, ColorFormat::Rgba8).unwrap();
        p.rasterize(&p.transform_mesh(&mesh).unwrap(), &mut drawn, None)
            .unwrap();
        let blue = drawn
            .to_rgba8_bytes()
            .chunks(4)
            .filter(|c| c[2] > 200)
            .count();
        match func {
            DepthFunc::LessEqual => assert_eq!(blue, 96 * 64, "the copy covers the screen"),
            _ => assert_eq!(blue, 0, "the copy is not nearer"),
        }
        let mut fused = Framebuffer::new(p.width, p.height, ColorFormat::Rgba8).unwrap();
        pool(1).install(|| p.render_mesh(&mesh, &mut fused).unwrap());
        assert!(drawn == fused, "render_mesh: {func:?}");
    }
}
