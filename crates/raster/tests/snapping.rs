//! The geometry stage snaps each vertex to the rasterizer's fixed-point grid once (a
//! shared vertex of an indexed mesh in the per-vertex pass, not once per triangle
//! around it) and hands triangles on with their positions on that grid. These tests
//! check the screen triangles against a projection done here, independently of the
//! stage: every vertex lies on the grid, at the snapped projection of its mesh vertex
//! (so the rasterizer, which snaps again, covers the same pixels as before the change),
//! through the shared-vertex path and the per-corner path (a soup), with and without
//! near-plane clipping.

use glam::Vec3;
use irradia_geometry::generators::gyroid::gyroid_mesh;
use irradia_raster::rasterizer::{snap, SUBPIXEL_BITS};
use irradia_raster::screen::ScreenTriangle;
use irradia_raster::{Mesh, Pipeline, Shading, ViewParams};

fn pipeline(eye: Vec3) -> Pipeline {
    let mut p = Pipeline::new(160, 120);
    p.shading = Shading::Gouraud;
    p.view =
        ViewParams::look_at_perspective(eye, Vec3::ZERO, Vec3::Y, 60.0, 160.0 / 120.0, 0.05, 10.0);
    p
}

/// The pixel position of `v` when it is well inside the view volume (no clipping),
/// with the stage's arithmetic: `(proj * view) * p`, divide, viewport, y down.
fn projected(p: &Pipeline, v: Vec3) -> Option<(f32, f32)> {
    let c = (p.view.proj * p.view.view) * v.extend(1.0);
    let m = 0.98 * c.w;
    if !(c.w > 0.0 && c.x.abs() < m && c.y.abs() < m && c.z > 0.0 && c.z < 0.999 * c.w) {
        return None;
    }
    let inv_w = 1.0 / c.w;
    Some((
        (c.x * inv_w * 0.5 + 0.5) * p.width as f32,
        (0.5 - c.y * inv_w * 0.5) * p.height as f32,
    ))
}

fn on_grid(x: f32) -> bool {
    (x * (1 << SUBPIXEL_BITS) as f32).fract() == 0.0
}

/// Checks `tris` (made from `mesh`, ids = triangle numbers) and returns how many
/// triangles were checked against the projection and how many were clipped.
fn check(p: &Pipeline, mesh: &Mesh, tris: &[ScreenTriangle]) -> (usize, usize) {
    let (mut inside, mut clipped) = (0, 0);
    for t in tris {
        for v in &t.v {
            assert!(on_grid(v.x) && on_grid(v.y), "off the grid: {v:?}");
        }
        let idx = mesh.indices[t.id as usize];
        let hand: Vec<_> = idx
            .iter()
            .filter_map(|&i| projected(p, mesh.positions[i as usize]))
            .collect();
        if hand.len() < 3 {
            clipped += 1;
            continue;
        }
        inside += 1;
        for (v, (x, y)) in t.v.iter().zip(&hand) {
            assert_eq!(
                (snap(v.x), snap(v.y)),
                (snap(*x), snap(*y)),
                "triangle {}",
                t.id
            );
        }
    }
    (inside, clipped)
}

#[test]
fn screen_triangles_are_the_snapped_projection_of_their_vertices() {
    let mesh = Mesh::from_mesh_data(gyroid_mesh(24));
    assert!(
        mesh.positions.len() * 3 < mesh.indices.len() * 2,
        "shared vertices"
    );
    // From afar (nothing clipped) and from inside the cube (the near plane cuts).
    for (eye, want_clipped) in [
        (Vec3::new(1.5, 1.2, 3.5), false),
        (Vec3::new(0.1, 0.2, 0.6), true),
    ] {
        let p = pipeline(eye);
        let shared = p.transform_mesh(&mesh).unwrap();
        let (inside, clipped) = check(&p, &mesh, &shared);
        assert!(inside > 1000, "{inside} triangles checked");
        assert_eq!(clipped > 0, want_clipped, "{clipped} clipped");
        // The soup path snaps per corner: the same screen triangles.
        let soup = p.transform_and_light(&mesh.to_triangles());
        assert_eq!(soup.len(), shared.len());
        for (a, b) in soup.iter().zip(&shared) {
            assert_eq!(a.id, b.id);
            for (u, v) in a.v.iter().zip(&b.v) {
                assert_eq!((u.x, u.y, u.z, u.inv_w), (v.x, v.y, v.z, v.inv_w));
            }
        }
    }
}
