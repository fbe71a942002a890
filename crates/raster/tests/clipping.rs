//! Clipping: triangles crossing the near plane and the screen edges render as the
//! geometric truth (a ray cast through every pixel centre) says they should.

mod common;

use common::{pixel_ray, ray_triangle};
use glam::Vec3;
use irradia_raster::{ColorFormat, Framebuffer, Mesh, Pipeline, Shading, ViewParams, NO_ID};

/// Renders `tris` into an ID buffer and compares every pixel with a ray cast that
/// keeps hits between the near and far planes; returns the number of disagreeing
/// pixels and the number of covered ones.
fn compare(view: ViewParams, near: f32, far: f32, tris: &[[Vec3; 3]]) -> (usize, usize) {
    let (w, h) = (64, 48);
    let mut p = Pipeline::new(w, h);
    p.view = view;
    p.shading = Shading::Unlit;
    let positions: Vec<Vec3> = tris.iter().flatten().copied().collect();
    let indices = (0..tris.len() as u32)
        .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    let mut fb = Framebuffer::new(w, h, ColorFormat::Id).unwrap();
    p.render_mesh(&Mesh::new(positions, indices), &mut fb)
        .unwrap();
    let forward = -view.view.inverse().z_axis.truncate().as_dvec3().normalize();
    let (mut bad, mut covered) = (0, 0);
    for y in 0..h {
        for x in 0..w {
            let (_, d) = pixel_ray(&view, w, h, x, y);
            let eye = common::eye(&view);
            let mut best = (f64::INFINITY, NO_ID);
            for (i, t) in tris.iter().enumerate() {
                if let Some((s, _, _)) = ray_triangle(eye, d, t[0], t[1], t[2]) {
                    let depth = s * d.dot(forward);
                    if depth >= near as f64 && depth <= far as f64 && s < best.0 {
                        best = (s, i as u32);
                    }
                }
            }
            covered += (best.1 != NO_ID) as usize;
            if fb.id_at(x, y) != Some(best.1) {
                bad += 1;
            }
        }
    }
    (bad, covered)
}

#[test]
fn triangles_through_the_near_plane_match_the_ray_cast() {
    let (near, far) = (0.5, 50.0);
    let view = ViewParams::look_at_perspective(
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, -1.0),
        Vec3::Y,
        60.0,
        64.0 / 48.0,
        near,
        far,
    );
    // Floor and wall triangles running from behind the eye to far in front of it,
    // plus one crossing the near plane at a slant, plus one entirely behind the eye.
    let tris = [
        [
            Vec3::new(-3.0, -1.0, 5.0),
            Vec3::new(3.0, -1.0, 5.0),
            Vec3::new(0.0, -1.0, -20.0),
        ],
        [
            Vec3::new(1.0, -2.0, 3.0),
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(1.0, 0.0, -10.0),
        ],
        [
            Vec3::new(-2.0, 0.5, 1.0),
            Vec3::new(-0.2, 1.5, -0.2),
            Vec3::new(-1.0, -0.5, -3.0),
        ],
        [
            Vec3::new(-1.0, -1.0, 2.0),
            Vec3::new(1.0, -1.0, 2.0),
            Vec3::new(0.0, 1.0, 2.0),
        ],
    ];
    let (bad, covered) = compare(view, near, far, &tris);
    assert!(
        covered > 600,
        "the triangles cover much of the screen: {covered}"
    );
    // Only pixels whose centres lie within float error of an edge may disagree.
    assert!(
        bad <= covered / 50,
        "{bad} of {covered} pixels disagree with the ray cast"
    );
}

#[test]
fn triangles_far_beyond_the_screen_edges_match_the_ray_cast() {
    let (near, far) = (0.1, 100.0);
    let view = ViewParams::look_at_perspective(
        Vec3::new(0.0, 0.0, 5.0),
        Vec3::ZERO,
        Vec3::Y,
        40.0,
        64.0 / 48.0,
        near,
        far,
    );
    // Huge triangles reaching thousands of screen widths past the edges (beyond the
    // guard band, so they are clipped at the x/y planes) and one crossing the far
    // plane.
    let tris = [
        [
            Vec3::new(-1.0e4, -0.3, -2.0),
            Vec3::new(1.0e4, -0.2, -2.0),
            Vec3::new(0.0, 1.0e4, -3.0),
        ],
        [
            Vec3::new(-0.5, -0.5, 0.5),
            Vec3::new(0.4, -1.0e3, 0.0),
            Vec3::new(1.0e3, 0.2, 0.3),
        ],
        [
            Vec3::new(-0.9, 0.8, 1.0),
            Vec3::new(-0.2, 0.9, -200.0),
            Vec3::new(-0.4, -0.2, 1.0),
        ],
    ];
    let (bad, covered) = compare(view, near, far, &tris);
    assert!(covered > 1500, "{covered}");
    assert!(
        bad <= covered / 50,
        "{bad} of {covered} pixels disagree with the ray cast"
    );
}

/// A triangle cut by the near plane keeps its vertex colours: the clipped polygon's
/// new vertices interpolate the attributes of the vertex outside too (not zeros), so a
/// triangle of one colour stays that colour everywhere, through `render_mesh` (shared
/// vertices and triangle by triangle) and `render_triangles`.
#[test]
fn clipped_triangles_keep_their_vertex_colours() {
    use irradia_raster::framebuffer::to_rgba8;
    use irradia_raster::Triangle;
    let (w, h) = (64, 48);
    let mut p = Pipeline::new(w, h);
    p.view = ViewParams::look_at_perspective(
        Vec3::ZERO,
        Vec3::new(0.0, 0.0, -1.0),
        Vec3::Y,
        60.0,
        64.0 / 48.0,
        0.5,
        50.0,
    );
    p.shading = Shading::Unlit;
    let colour = [0.9, 0.5, 0.25, 1.0];
    // One vertex behind the eye, two in front: clipped by the near plane.
    let positions = vec![
        Vec3::new(-2.0, -1.0, -3.0),
        Vec3::new(2.0, -1.0, -3.0),
        Vec3::new(0.0, 0.5, 2.0),
    ];
    let expected = to_rgba8(colour);
    let check = |fb: &Framebuffer, what: &str| {
        let mut covered = 0;
        let c = fb.to_rgba8_bytes();
        for y in 0..h {
            for x in 0..w {
                if fb.depth_at(x, y) < 1.0 {
                    covered += 1;
                    let i = 4 * (y * w + x) as usize;
                    // One level for the rounding of the perspective-correct
                    // weights (they sum to one only up to rounding).
                    let off = (0..4).map(|k| c[i + k].abs_diff(expected[k])).max();
                    assert!(
                        off <= Some(1),
                        "{what}: pixel ({x}, {y}) is {:?}, expected {expected:?}",
                        &c[i..i + 4]
                    );
                }
            }
        }
        assert!(covered > 100, "{what}: only {covered} pixels covered");
    };
    // Shared vertices (the per-vertex pass), and unshared (triangle by triangle).
    for soup in [false, true] {
        let mut mesh = Mesh::new(positions.clone(), vec![[0, 1, 2]]);
        mesh.colors = vec![colour; 3];
        if !soup {
            // A second, hidden triangle sharing the vertices keeps the mesh indexed.
            mesh.indices.push([0, 2, 1]);
        }
        mesh.compute_vertex_normals();
        let mut fb = Framebuffer::new(w, h, ColorFormat::Rgba8).unwrap();
        p.render_mesh(&mesh, &mut fb).unwrap();
        check(
            &fb,
            if soup {
                "render_mesh, soup"
            } else {
                "render_mesh"
            },
        );
    }
    let tris = vec![Triangle::flat(
        [positions[0], positions[1], positions[2]],
        colour,
        0,
    )];
    let mut fb = Framebuffer::new(w, h, ColorFormat::Rgba8).unwrap();
    p.render_triangles(&tris, &mut fb).unwrap();
    check(&fb, "render_triangles");
}
