//! TriangleMesh: validation errors, watertightness at shared edges and vertices,
//! interpolated normals and uvs.

use irradia_core::{Ray, Rng, Vec2, Vec3};
use irradia_geometry::{MeshError, Shape, TriangleMesh};

/// An icosphere of radius 1 subdivided `levels` times: closed, with vertices at
/// irrational coordinates so edges are not axis-aligned.
fn icosphere(levels: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut v: Vec<Vec3> = [
        (-1., t, 0.),
        (1., t, 0.),
        (-1., -t, 0.),
        (1., -t, 0.),
        (0., -1., t),
        (0., 1., t),
        (0., -1., -t),
        (0., 1., -t),
        (t, 0., -1.),
        (t, 0., 1.),
        (-t, 0., -1.),
        (-t, 0., 1.),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut mid = std::collections::HashMap::new();
        let mut nf = Vec::new();
        let mut m = |a: u32, b: u32, v: &mut Vec<Vec3>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                v.push(((v[a as usize] + v[b as usize]) * 0.5).normalize());
                v.len() as u32 - 1
            })
        };
        for [a, b, c] in f {
            let (ab, bc, ca) = (m(a, b, &mut v), m(b, c, &mut v), m(c, a, &mut v));
            nf.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = nf;
    }
    (v, f)
}

#[test]
fn rays_at_shared_edges_and_vertices_never_leak() {
    let (v, f) = icosphere(3);
    let mesh = TriangleMesh::new(v.clone(), f.clone(), None, None).unwrap();
    let mut rng = Rng::new(1, 2);
    let mut targets = Vec::new();
    for t in &f {
        for k in 0..3 {
            let (a, b) = (v[t[k] as usize], v[t[(k + 1) % 3] as usize]);
            targets.push(a);
            for s in [0.5f32, 0.25, 1.0 / 3.0, rng.next_f32()] {
                targets.push(a + (b - a) * s);
            }
        }
    }
    let mut rays = 0;
    for p in &targets {
        // From inside (several origins: every ray from inside a closed mesh must hit)
        // and from outside roughly along the normal, aimed exactly at the point.
        // (Outside origins that see the point on the silhouette may rightly miss.)
        let jitter = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5;
        let origins = [
            Vec3::ZERO,
            Vec3::new(0.1, -0.2, 0.05),
            jitter * 0.5,
            *p * 3.0 + Vec3::new(0.3, 0.1, -0.2),
            *p * 2.0 + jitter * 0.5,
        ];
        for o in origins {
            let ray = Ray::new(o, *p - o);
            rays += 1;
            let h = mesh.intersect(&ray, f32::INFINITY);
            assert!(h.is_some(), "leak: ray from {o} to {p}");
            assert!(
                mesh.occluded(&ray, f32::INFINITY),
                "any-hit leak: {o} to {p}"
            );
            // Inside the unit sphere the first hit is at most at the target.
            assert!(h.unwrap().t <= 1.0 + 1e-5);
        }
    }
    assert!(rays > 10_000);
}

#[test]
fn validation_errors() {
    let v = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
    assert_eq!(
        TriangleMesh::new(v.clone(), vec![], None, None).unwrap_err(),
        MeshError::Empty
    );
    assert_eq!(
        TriangleMesh::new(v.clone(), vec![[0, 1, 3]], None, None).unwrap_err(),
        MeshError::IndexOutOfRange {
            triangle: 0,
            index: 3,
            vertices: 3
        }
    );
    let mut bad = v.clone();
    bad[1].y = f32::NAN;
    assert!(matches!(
        TriangleMesh::new(bad, vec![[0, 1, 2]], None, None).unwrap_err(),
        MeshError::NonFinitePosition { vertex: 1, .. }
    ));
    assert!(matches!(
        TriangleMesh::new(v.clone(), vec![[0, 1, 2]], Some(vec![Vec3::Z; 2]), None).unwrap_err(),
        MeshError::CountMismatch {
            what: "normals",
            got: 2,
            expected: 3
        }
    ));
    assert!(matches!(
        TriangleMesh::new(v.clone(), vec![[0, 1, 2]], None, Some(vec![Vec2::ZERO; 4])).unwrap_err(),
        MeshError::CountMismatch {
            what: "uvs",
            got: 4,
            expected: 3
        }
    ));
    let e = TriangleMesh::new(
        v,
        vec![[0, 1, 2]],
        Some(vec![Vec3::Z, Vec3::INFINITY, Vec3::Z]),
        None,
    )
    .unwrap_err();
    assert!(e.to_string().contains("vertex 1: normal"), "{e}");
}

#[test]
fn degenerate_triangles_are_kept_but_never_hit() {
    let v = vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0, Vec3::Y];
    let mesh = TriangleMesh::new(v, vec![[0, 1, 2], [0, 1, 3]], None, None).unwrap();
    assert_eq!(mesh.triangle_count(), 2);
    let h = mesh
        .intersect(&Ray::new(Vec3::new(0.5, 0.0, 1.0), -Vec3::Z), f32::INFINITY)
        .unwrap();
    assert_eq!(h.prim, 1);
    assert!(mesh
        .intersect(&Ray::new(Vec3::new(1.5, 0.0, 1.0), -Vec3::Z), f32::INFINITY)
        .is_none());
}

#[test]
fn smooth_normals_and_hit_record() {
    let (v, f) = icosphere(2);
    let mesh = TriangleMesh::new(v, f, None, None).unwrap();
    let mut rng = Rng::new(4, 4);
    for _ in 0..500 {
        let d = rng.next_centered_vec3();
        let h = mesh
            .intersect(&Ray::new(Vec3::ZERO, d), f32::INFINITY)
            .unwrap();
        // Area-weighted vertex normals of a sphere are close to the radial direction,
        // closer than the flat face normal.
        let radial = h.point.normalize();
        assert!(h.shading_normal.dot(radial) > 0.999);
        assert!(h.normal.dot(radial) > 0.98);
        assert!(h.shading_normal.dot(radial) >= h.normal.dot(radial) - 1e-4);
        assert!((h.point - d * h.t).length() <= 1e-5 + h.error * 4.0);
        assert!(h.error > 0.0 && h.error < 1e-5);
        assert!((h.prim as usize) < mesh.triangle_count());
    }
    let facets = mesh.facets(0).unwrap();
    assert_eq!(facets.faces.len(), mesh.triangle_count());
}

#[test]
fn closed_meshes_are_solids_with_spans() {
    let (v, f) = icosphere(3);
    let mesh = TriangleMesh::new(v.clone(), f.clone(), None, None).unwrap();
    assert!(mesh.is_solid());
    assert_eq!(mesh.orientation(), 1);
    // The same sphere wound inside out is still a solid, and its spans are the same.
    let flipped: Vec<[u32; 3]> = f.iter().map(|t| [t[0], t[2], t[1]]).collect();
    let inverted = TriangleMesh::new(v.clone(), flipped, None, None).unwrap();
    assert_eq!(inverted.orientation(), -1);
    let mut rng = Rng::new(8, 8);
    let mut targets: Vec<Vec3> = v.clone();
    for t in &f {
        targets.push((v[t[0] as usize] + v[t[1] as usize]) * 0.5);
    }
    for _ in 0..200 {
        targets.push(rng.next_centered_vec3());
    }
    for p in targets {
        // From a point inside, through vertices, edges and random directions: one
        // span around t = 0, its ends on the unit sphere (to the mesh's accuracy).
        let o = Vec3::new(0.05, -0.1, 0.02);
        let ray = Ray::new(o, p - o);
        for m in [&mesh, &inverted] {
            let mut spans = Vec::new();
            m.spans(&ray, &mut spans);
            assert_eq!(spans.len(), 1, "towards {p}: {spans:?}");
            let s = spans[0];
            assert!(s.enter.t < 0.0 && s.exit.t > 0.0);
            for b in [s.enter, s.exit] {
                let q = ray.at(b.t);
                assert!((q.length() - 1.0).abs() < 0.01, "{q}");
                // Outward normals.
                assert!(b.normal.dot(q) > 0.9);
            }
            assert!(s.enter.normal.dot(ray.dir) < 0.0 && s.exit.normal.dot(ray.dir) > 0.0);
        }
        // From outside: the whole span lies ahead.
        let ray = Ray::new(p.normalize_or(Vec3::X) * 4.0, -p.normalize_or(Vec3::X));
        let mut spans = Vec::new();
        mesh.spans(&ray, &mut spans);
        assert_eq!(
            spans.len(),
            1,
            "from {} {:?} hit {:?}",
            ray.origin,
            spans,
            mesh.intersect(&ray, f32::INFINITY).map(|h| h.t)
        );
        assert!((spans[0].enter.t - 3.0).abs() < 0.02 && (spans[0].exit.t - 5.0).abs() < 0.02);
    }
    // Remove one triangle: open, so no solid and no spans.
    let open = TriangleMesh::new(v, f[1..].to_vec(), None, None).unwrap();
    assert!(!open.is_solid());
    let mut spans = Vec::new();
    open.spans(&Ray::new(Vec3::ZERO, Vec3::X), &mut spans);
    assert!(spans.is_empty());
}

/// `Shape::intersect_cast` (the mesh answering from the leaf it hit) reports exactly
/// what `intersect`'s whole hit says: without normals (the leaf path) and with given
/// normals that turn the geometric ones (the whole-hit path).
#[test]
fn cast_hits_equal_whole_hits() {
    use irradia_geometry::CastHit;
    let (v, f) = icosphere(3);
    let inward: Vec<Vec3> = v.iter().map(|p| -*p).collect();
    let plain = TriangleMesh::new(v.clone(), f.clone(), None, None).unwrap();
    let turned = TriangleMesh::new(v, f, Some(inward), None).unwrap();
    let mut rng = Rng::new(3, 4);
    let mut hits = 0;
    for _ in 0..20_000 {
        let o = (Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5) * 6.0;
        let d = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5;
        let ray = Ray::new(o, d);
        for m in [&plain, &turned] {
            let whole = m.intersect(&ray, f32::INFINITY).map(|h| CastHit::from(&h));
            assert_eq!(m.intersect_cast(&ray, f32::INFINITY), whole, "ray {o} {d}");
            hits += usize::from(whole.is_some());
        }
    }
    assert!(hits > 2_000, "{hits}");
}
