//! Bézier patches and the Utah teapot: the data's shared boundaries, exact normals at the
//! collapsed poles, a flat patch against its plane, watertight seams, and spawned rays
//! that never re-hit at their origin.

#![allow(clippy::needless_range_loop)]

use glam::{DVec3, Vec3};
use irradia_core::{offset_ray_origin, Ray, Rng};
use irradia_geometry::shapes::bezier::{
    teapot_mesh, teapot_patches, tessellate, BezierPatch, BezierSurface, PatchTriangles,
    TEAPOT_INDICES,
};
use irradia_geometry::Shape;

type EdgeKey = [[u32; 3]; 4];

fn key(c: [Vec3; 4]) -> EdgeKey {
    c.map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
}

fn collapsed(c: &[Vec3; 4]) -> bool {
    c.iter().all(|p| *p == c[0])
}

/// Pairs (patch a, edge a, patch b, edge b, reversed) of patch edges with the same
/// control points (same positions, either direction).
fn shared_edges(ps: &[BezierPatch]) -> Vec<(usize, usize, usize, usize, bool)> {
    let mut out = Vec::new();
    for a in 0..ps.len() {
        for ea in 0..4 {
            let ca = ps[a].edge(ea);
            if collapsed(&ca) {
                continue;
            }
            for b in a + 1..ps.len() {
                for eb in 0..4 {
                    let cb = ps[b].edge(eb);
                    let mut rb = cb;
                    rb.reverse();
                    if key(ca) == key(cb) || key(ca) == key(rb) {
                        out.push((a, ea, b, eb, key(ca) != key(cb)));
                    }
                }
            }
        }
    }
    out
}

/// The parameters of edge `e` at position `s` along it.
fn edge_uv(e: usize, s: f64) -> (f64, f64) {
    match e {
        0 => (0.0, s),
        1 => (1.0, s),
        2 => (s, 0.0),
        _ => (s, 1.0),
    }
}

#[test]
fn teapot_data_shares_boundary_control_points() {
    assert_eq!(TEAPOT_INDICES.len(), 32);
    let ps = teapot_patches();
    assert_eq!(ps.len(), 32);
    // The rings of four patches around the axis close up, by index in the table: patch
    // k's last column is patch k+1's first (rim, bodies, lid, bottom).
    for ring in [0, 4, 8, 20, 24, 28] {
        for k in 0..4 {
            let (a, b) = (ring + k, ring + (k + 1) % 4);
            let last_col: Vec<u16> = (0..4).map(|i| TEAPOT_INDICES[a][4 * i + 3]).collect();
            let first_col: Vec<u16> = (0..4).map(|i| TEAPOT_INDICES[b][4 * i]).collect();
            assert_eq!(last_col, first_col, "patches {a} and {b}");
        }
    }
    // Rim -> upper body -> lower body, stacked by index.
    for k in 0..4 {
        assert_eq!(TEAPOT_INDICES[k][12..16], TEAPOT_INDICES[4 + k][0..4]);
        assert_eq!(TEAPOT_INDICES[4 + k][12..16], TEAPOT_INDICES[8 + k][0..4]);
    }
    // By position: every shared edge is traversed consistently (neighbouring normals
    // agree), and there are many of them (the body and bottom alone give 4 rings + the
    // body-bottom seam).
    let shared = shared_edges(&ps);
    assert!(shared.len() >= 40, "{} shared edges", shared.len());
    for &(a, ea, b, eb, rev) in &shared {
        for s in [0.1, 0.5, 0.9] {
            let (ua, va) = edge_uv(ea, s);
            let (ub, vb) = edge_uv(eb, if rev { 1.0 - s } else { s });
            let (pa, pb) = (ps[a].eval(ua, va), ps[b].eval(ub, vb));
            assert!((pa - pb).length() < 1e-6, "{a}.{ea} vs {b}.{eb}");
            let d = ps[a].normal(ua, va).dot(ps[b].normal(ub, vb));
            assert!(d > 0.99, "normals disagree across {a}.{ea} / {b}.{eb}: {d}");
        }
    }
}

#[test]
fn teapot_normals_point_out_and_are_exact_at_the_poles() {
    let ps = teapot_patches();
    // Body patches 4..12: outward = away from the y axis.
    for p in &ps[4..12] {
        for (u, v) in [(0.2, 0.3), (0.5, 0.5), (0.8, 0.9)] {
            let q = p.eval(u, v);
            let radial = DVec3::new(q.x, 0.0, q.z).normalize();
            assert!(p.normal_f64(u, v).dot(radial) > 0.3);
        }
    }
    // Bottom (28..32) and lid top (20..24) collapse one edge into the pole on the y
    // axis; the normal there is exactly -y and +y, from every direction of approach.
    for (range, want) in [(28..32, -DVec3::Y), (20..24, DVec3::Y)] {
        for p in &ps[range] {
            let pole = (0..4)
                .map(|e| p.edge(e))
                .position(|c| collapsed(&c))
                .expect("a collapsed edge");
            for s in [0.0, 0.3, 0.5, 1.0] {
                let (u, v) = edge_uv(pole, s);
                let n = p.normal_f64(u, v);
                assert!((n - want).length() < 1e-9, "{n:?}");
            }
            // Approaching the pole, the plain cross product converges to the same normal.
            let (u, v) = edge_uv(pole, 0.4);
            let (u2, v2) = (u + (0.5 - u) * 1e-3, v + (0.5 - v) * 1e-3);
            let d = p.derivatives(u2, v2);
            assert!((d.du.cross(d.dv).normalize() - want).length() < 1e-2);
        }
    }
    // Everywhere: finite unit normals that match finite differences away from poles.
    for (k, p) in ps.iter().enumerate() {
        for i in 0..=10 {
            for j in 0..=10 {
                let (u, v) = (i as f64 / 10.0, j as f64 / 10.0);
                let n = p.normal_f64(u, v);
                assert!(
                    n.is_finite() && (n.length() - 1.0).abs() < 1e-9,
                    "patch {k}"
                );
                let h = 1e-6;
                let (uc, vc) = (u.clamp(h, 1.0 - h), v.clamp(h, 1.0 - h));
                let du = p.eval(uc + h, vc) - p.eval(uc - h, vc);
                let dv = p.eval(uc, vc + h) - p.eval(uc, vc - h);
                let fd = du.cross(dv);
                if fd.length() > 1e-9 && (uc, vc) == (u, v) {
                    assert!((fd.normalize() - n).length() < 1e-4, "patch {k} at {u},{v}");
                }
            }
        }
    }
}

/// A planar, non-rectangular bilinear patch inside the plane z = 0.3 x - 0.2 y + 1.
fn flat_patch() -> (BezierPatch, Vec3, f32) {
    let plane = |x: f32, y: f32| Vec3::new(x, y, 0.3 * x - 0.2 * y + 1.0);
    let corners = [
        plane(-1.0, -1.0),
        plane(1.5, -0.8),
        plane(-0.7, 1.2),
        plane(1.0, 1.0),
    ];
    let pts = std::array::from_fn(|k| {
        let (s, t) = ((k / 4) as f32 / 3.0, (k % 4) as f32 / 3.0);
        corners[0] * (1.0 - s) * (1.0 - t)
            + corners[1] * s * (1.0 - t)
            + corners[2] * (1.0 - s) * t
            + corners[3] * s * t
    });
    let n = Vec3::new(-0.3, 0.2, 1.0).normalize();
    (
        BezierPatch::new(pts),
        n,
        1.0 / Vec3::new(-0.3, 0.2, 1.0).length(),
    )
}

#[test]
fn a_flat_bilinear_patch_is_hit_where_its_plane_is() {
    let (patch, n, d) = flat_patch();
    for level in [1, 3, 8] {
        let surf = BezierSurface::new(vec![patch], level).unwrap();
        let mut rng = Rng::new(4, 0);
        let mut hits = 0;
        for _ in 0..500 {
            let o = Vec3::new(rng.next_f32() * 4.0 - 2.0, rng.next_f32() * 4.0 - 2.0, 5.0);
            let target = Vec3::new(rng.next_f32() * 3.0 - 1.2, rng.next_f32() * 3.0 - 1.2, 0.0);
            let ray = Ray::new(o, target - o);
            // The plane n·p = d hit analytically.
            let t_plane = (d - n.dot(o)) / n.dot(ray.dir);
            let p = ray.at(t_plane);
            // Inside the patch? Invert the bilinear map in the xy projection by Newton.
            let inside = {
                let (mut s, mut t) = (0.5f64, 0.5f64);
                for _ in 0..30 {
                    let q = patch.eval(s, t);
                    let dd = patch.derivatives(s, t);
                    let r = glam::DVec2::new(q.x - p.x as f64, q.y - p.y as f64);
                    let j = glam::DMat2::from_cols(dd.du.truncate(), dd.dv.truncate());
                    let step = j.inverse() * r;
                    s -= step.x;
                    t -= step.y;
                }
                (s, t)
            };
            let (s, t) = inside;
            let margin = 1e-4;
            let h = surf.intersect(&ray, f32::INFINITY);
            if s > margin && s < 1.0 - margin && t > margin && t < 1.0 - margin {
                let h = h.expect("hit inside the patch");
                hits += 1;
                assert!(
                    (h.t - t_plane).abs() < 1e-5 * t_plane,
                    "{} vs {t_plane}",
                    h.t
                );
                assert!((h.normal - n).length() < 1e-5);
                assert!((h.shading_normal - n).length() < 1e-5);
                assert!((h.uv.x as f64 - s).abs() < 1e-4 && (h.uv.y as f64 - t).abs() < 1e-4);
            } else if s < -margin || s > 1.0 + margin || t < -margin || t > 1.0 + margin {
                assert!(h.is_none(), "hit outside the patch at ({s}, {t})");
            }
        }
        assert!(hits > 100);
    }
}

/// Unit normals of the triangles that have all of `points` as corners (exact positions).
fn triangle_normals_touching(tris: &PatchTriangles, points: &[Vec3]) -> Vec<Vec3> {
    tris.indices
        .iter()
        .map(|t| t.map(|i| tris.positions[i as usize]))
        .filter(|c| points.iter().all(|p| c.contains(p)))
        .map(|[a, b, c]| (b - a).cross(c - a).normalize())
        .collect()
}

/// Rays aimed exactly at points of the tessellated seams between patches and at patch
/// corners, from both sides and at slants, all hit (at or before the aimed point). A ray
/// through a shared edge or vertex must hit one of the triangles there unless it is a
/// silhouette ray (it crosses some of their planes from the other side), so only rays
/// that cross every triangle at the point from the same side are cast.
#[test]
fn teapot_seams_are_watertight() {
    let ps = teapot_patches();
    let shared = shared_edges(&ps);
    for level in [3u32, 4, 7] {
        let surf = BezierSurface::teapot(level).unwrap();
        let tris = tessellate(&ps, level);
        let n = level as usize;
        let vertex = |patch: usize, e: usize, k: usize| {
            let (i, j) = match e {
                0 => (0, k),
                1 => (n, k),
                2 => (k, 0),
                _ => (k, n),
            };
            tris.positions[patch * (n + 1) * (n + 1) + i * (n + 1) + j]
        };
        let mut cast = 0;
        let mut shoot = |q: Vec3, dir: Vec3, normals: &[Vec3], what: &str| {
            let dn = dir.normalize();
            if normals.iter().any(|m| m.dot(dn).abs() < 0.05)
                || !(normals.iter().all(|m| m.dot(dn) > 0.0)
                    || normals.iter().all(|m| m.dot(dn) < 0.0))
            {
                return; // a silhouette ray: missing is allowed
            }
            let o = q - dir * 0.5;
            let ray = Ray::new(o, q - o);
            cast += 1;
            let h = surf
                .intersect(&ray, f32::INFINITY)
                .unwrap_or_else(|| panic!("level {level}: ray through the {what} at {q:?} missed"));
            assert!(
                h.t <= 1.0 + 1e-4,
                "level {level}: went past the {what} at {q:?}: t = {}",
                h.t
            );
            assert!(surf.occluded(&ray, 1.0 + 1e-3));
        };
        for &(a, ea, b, eb, rev) in &shared {
            // The two patches' tessellations have bit-identical seam vertices.
            for k in 0..=n {
                let kb = if rev { n - k } else { k };
                assert_eq!(
                    vertex(a, ea, k),
                    vertex(b, eb, kb),
                    "{a}.{ea}/{b}.{eb} k={k}"
                );
            }
            for k in 0..n {
                let (p0, p1) = (vertex(a, ea, k), vertex(a, ea, k + 1));
                let normals = triangle_normals_touching(&tris, &[p0, p1]);
                assert_eq!(normals.len(), 2, "seam segment {a}/{b} k={k}");
                let avg = (normals[0] + normals[1]).normalize();
                let along = (p1 - p0).normalize();
                let across = avg.cross(along).normalize();
                for s in [0.25f32, 0.5, 0.77] {
                    let q = p0 + (p1 - p0) * s;
                    for side in [1.0f32, -1.0] {
                        for tilt in [0.0f32, 0.4, -0.4] {
                            let dir = (avg + across * tilt + along * 0.2 * tilt) * side;
                            shoot(q, dir, &normals, "seam");
                        }
                    }
                }
                // Interior seam vertices.
                if k > 0 {
                    let fan = triangle_normals_touching(&tris, &[p0]);
                    let avg = fan.iter().copied().sum::<Vec3>().normalize();
                    shoot(p0, avg, &fan, "seam vertex");
                    shoot(p0, -avg, &fan, "seam vertex");
                }
            }
        }
        // Patch corners where four or more patches meet (and the poles).
        let mut corners: std::collections::HashMap<[u32; 3], (Vec3, usize)> = Default::default();
        for p in &ps {
            for c in [0, 3, 12, 15] {
                let q = p.points[c];
                corners
                    .entry([q.x.to_bits(), q.y.to_bits(), q.z.to_bits()])
                    .or_insert((q, 0))
                    .1 += 1;
            }
        }
        let mut tested = 0;
        for (q, count) in corners.into_values() {
            if count < 4 {
                continue;
            }
            tested += 1;
            let fan = triangle_normals_touching(&tris, &[q]);
            let avg = fan.iter().copied().sum::<Vec3>().normalize();
            let across = avg.any_orthonormal_vector();
            for tilt in [0.0f32, 0.2, -0.2] {
                shoot(q, avg + across * tilt, &fan, "corner");
                shoot(q, -(avg + across * tilt), &fan, "corner");
            }
        }
        assert!(tested >= 20, "{tested} corners");
        assert!(cast > 1000, "{cast} rays");
    }
}

#[test]
fn spawned_rays_never_rehit_at_their_origin() {
    let surf = BezierSurface::teapot(6).unwrap();
    let mut rng = Rng::new(17, 0);
    let mut hits = 0;
    for _ in 0..1500 {
        let o = rng.next_centered_vec3().normalize() * 8.0 + Vec3::new(0.0, 1.5, 0.0);
        let target = Vec3::new(
            rng.next_f32() * 6.0 - 3.0,
            rng.next_f32() * 3.2,
            rng.next_f32() * 4.0 - 2.0,
        );
        let ray = Ray::new(o, target - o);
        let Some(h) = surf.intersect(&ray, f32::INFINITY) else {
            continue;
        };
        hits += 1;
        let n = h.normal;
        let refl = ray.dir - 2.0 * ray.dir.dot(n) * n;
        let side = if ray.dir.dot(n) < 0.0 { n } else { -n };
        for (off, dir) in [(side, refl), (-side, ray.dir)] {
            let spawned = Ray::new(offset_ray_origin(h.point, off, h.error), dir);
            if let Some(h2) = surf.intersect(&spawned, f32::INFINITY) {
                assert!(h2.t * dir.length() > 1e-4, "re-hit at t = {}", h2.t);
            }
        }
    }
    assert!(hits > 300, "{hits}");
}

#[test]
fn teapot_mesh_at_any_level_and_deviation_shrinks() {
    for level in [1u32, 2, 5, 10] {
        let m = teapot_mesh(level);
        let full = 32 * 2 * (level * level) as usize;
        // Only triangles at the 8 collapsed pole edges are dropped: one per cell there.
        assert_eq!(
            m.triangle_count(),
            full - 8 * level as usize,
            "level {level}"
        );
        let b = m.bounds();
        assert!(
            (b.min.y - 0.0).abs() < 1e-6 && (b.max.y - 3.15).abs() < 1e-5,
            "{b:?}"
        );
    }
    let (d4, d8, d16) = (
        BezierSurface::teapot(4).unwrap().max_deviation(),
        BezierSurface::teapot(8).unwrap().max_deviation(),
        BezierSurface::teapot(16).unwrap().max_deviation(),
    );
    // Second-order convergence: halving the cells divides the deviation by about 4.
    assert!(d8 < d4 / 3.0 && d16 < d8 / 3.0, "{d4} {d8} {d16}");
    assert!(d16 < 1e-2, "{d4} {d8} {d16}");
}

#[test]
fn bad_patch_input_is_reported() {
    assert!(BezierSurface::new(vec![], 4).is_err());
    let (mut p, _, _) = flat_patch();
    assert!(BezierSurface::new(vec![p], 0).is_err());
    p.points[5].x = f32::NAN;
    let e = BezierSurface::new(vec![p], 4).unwrap_err();
    assert!(e.to_string().contains("control point 5"), "{e}");
}
