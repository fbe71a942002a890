//! Convex polyhedra (entry at the furthest front-facing plane, exit at the nearest
//! back-facing one, miss when entry is beyond exit), boxes, degenerate input, and the
//! facets of every bounded shape (closed, counter-clockwise seen from outside, volume
//! close to the analytic one).

use glam::{DVec3, Vec2, Vec3};
use irradia_core::sampling::uniform_sphere;
use irradia_core::{Ray, Rng};
use irradia_geometry::shapes::{Cuboid, Disk, Polyhedron, Quadric, ShapeError, Sphere};
use irradia_geometry::{Facets, Shape};

#[test]
fn octahedron_entry_exit_and_misses() {
    // platonic(8): |x| + |y| + |z| ≤ √3 (inradius 1).
    let p = Polyhedron::platonic(8).unwrap();
    let s3 = 3f32.sqrt();
    let ray = Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X);
    let mut spans = Vec::new();
    p.spans(&ray, &mut spans);
    assert_eq!(spans.len(), 1);
    assert!((spans[0].enter.t - (5.0 - s3)).abs() < 1e-6);
    assert!((spans[0].exit.t - (5.0 + s3)).abs() < 1e-6);
    // Entry is on a front-facing plane, exit on a back-facing one.
    assert!(spans[0].enter.normal.dot(ray.dir) < 0.0 && spans[0].exit.normal.dot(ray.dir) > 0.0);
    let h = p.intersect(&ray, f32::INFINITY).unwrap();
    assert_eq!(h.t, spans[0].enter.t);
    assert!((h.normal.length() - 1.0).abs() < 1e-6 && h.normal.x < 0.0);
    // From inside: the exit.
    let h = p
        .intersect(&Ray::new(Vec3::ZERO, Vec3::Y), f32::INFINITY)
        .unwrap();
    assert!((h.t - s3).abs() < 1e-6);
    // t_max cuts the hit off.
    assert!(p.intersect(&ray, 5.0 - s3 - 1e-3).is_none());
    // A ray past a vertex: it crosses front plane x+y+z=√3... but entry > exit.
    let miss = Ray::new(Vec3::new(-5.0, 1.2, 1.2), Vec3::X);
    assert!(p.intersect(&miss, f32::INFINITY).is_none());
    spans.clear();
    p.spans(&miss, &mut spans);
    assert!(spans.is_empty());
    // Parallel to a face pair and outside: miss.
    assert!(p
        .intersect(&Ray::new(Vec3::new(0.0, 5.0, 0.0), Vec3::X), f32::INFINITY)
        .is_none());
    // Pointing away.
    assert!(p
        .intersect(
            &Ray::new(Vec3::new(-5.0, 0.0, 0.0), -Vec3::X),
            f32::INFINITY
        )
        .is_none());
}

/// Membership by the half-spaces directly.
fn inside(p: &Polyhedron, q: Vec3) -> bool {
    p.planes()
        .iter()
        .all(|h| h.normal.dot(q.as_dvec3()) <= h.offset)
}

#[test]
fn random_rays_agree_with_point_membership() {
    let mut rng = Rng::new(3, 1);
    for faces in [4, 6, 8, 12, 20] {
        let p = Polyhedron::platonic(faces).unwrap();
        let mut hits = 0;
        for _ in 0..2000 {
            let d = uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
            let target = (Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5) * 5.0;
            let ray = Ray::new(target - 6.0 * d, d);
            let mut spans = Vec::new();
            p.spans(&ray, &mut spans);
            match spans.first() {
                Some(s) => {
                    hits += 1;
                    let (a, b) = (s.enter.t, s.exit.t);
                    assert!(a <= b);
                    if b - a > 1e-3 {
                        assert!(
                            inside(&p, ray.at(0.5 * (a + b))),
                            "{faces}: middle of span outside"
                        );
                    }
                    assert!(!inside(&p, ray.at(a - 1e-3)) && !inside(&p, ray.at(b + 1e-3)));
                }
                None => {
                    // Along the whole ray no sample point is inside.
                    for k in 0..200 {
                        assert!(
                            !inside(&p, ray.at(12.0 * k as f32 / 200.0)),
                            "{faces}: missed an inside point"
                        );
                    }
                }
            }
        }
        assert!(hits > 200, "{faces}: {hits} hits");
    }
}

#[test]
fn cube_as_polyhedron_equals_the_box() {
    let cube = Polyhedron::platonic(6).unwrap();
    let b = Cuboid::new(Vec3::splat(1.0), Vec3::splat(-1.0)).unwrap();
    let mut rng = Rng::new(5, 2);
    for _ in 0..2000 {
        let d = uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
        let o = (Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5) * 6.0;
        let ray = Ray::new(o, d);
        match (
            cube.intersect(&ray, f32::INFINITY),
            b.intersect(&ray, f32::INFINITY),
        ) {
            (Some(x), Some(y)) => {
                assert!((x.t - y.t).abs() <= 1e-5 * x.t.max(1.0));
                if (x.normal - y.normal).length() > 1e-5 {
                    // Different faces only at an edge: two coordinates at ±1.
                    let mut e = (x.point.abs() - Vec3::ONE).abs().to_array();
                    e.sort_by(f32::total_cmp);
                    assert!(e[1] < 1e-4, "normals differ away from an edge: {x:?} {y:?}");
                }
            }
            (None, None) => {}
            (x, y) => {
                // Only rays grazing an edge may disagree.
                let h = x.or(y).unwrap();
                let edge = (h.point.abs() - Vec3::ONE).abs();
                let mut e = edge.to_array();
                e.sort_by(f32::total_cmp);
                assert!(e[1] < 1e-4, "disagreement away from an edge: {h:?}");
            }
        }
    }
}

#[test]
fn degenerate_half_spaces_are_errors() {
    // Three planes: open towards (-1,-1,-1).
    let three = [(Vec3::X, 1.0), (Vec3::Y, 1.0), (Vec3::Z, 1.0)];
    assert!(matches!(
        Polyhedron::new(&three),
        Err(ShapeError::UnboundedPolyhedron { .. })
    ));
    // A slab along x, y, z missing one side: unbounded.
    let open = [
        (Vec3::X, 1.0),
        (-Vec3::X, 1.0),
        (Vec3::Y, 1.0),
        (-Vec3::Y, 1.0),
        (Vec3::Z, 1.0),
    ];
    assert!(matches!(
        Polyhedron::new(&open),
        Err(ShapeError::UnboundedPolyhedron { .. })
    ));
    // Normals all in one plane: an infinite prism.
    let prism = [
        (Vec3::X, 1.0),
        (-Vec3::X, 1.0),
        (Vec3::Y, 1.0),
        (-Vec3::Y, 1.0),
    ];
    assert!(matches!(
        Polyhedron::new(&prism),
        Err(ShapeError::UnboundedPolyhedron { .. })
    ));
    // Contradictory: x ≤ -1 and x ≥ 1.
    let mut empty: Vec<(Vec3, f32)> = Polyhedron::platonic(6)
        .unwrap()
        .planes()
        .iter()
        .map(|h| (h.normal.as_vec3(), h.offset as f32))
        .collect();
    empty.push((Vec3::X, -2.0));
    assert!(matches!(
        Polyhedron::new(&empty),
        Err(ShapeError::EmptyPolyhedron)
    ));
    // Flat: x ≤ 0 and x ≥ 0.
    let flat = [
        (Vec3::X, 0.0),
        (-Vec3::X, 0.0),
        (Vec3::Y, 1.0),
        (-Vec3::Y, 1.0),
        (Vec3::Z, 1.0),
        (-Vec3::Z, 1.0),
    ];
    assert!(matches!(
        Polyhedron::new(&flat),
        Err(ShapeError::EmptyPolyhedron)
    ));
    assert!(matches!(
        Polyhedron::new(&[(Vec3::ZERO, 1.0); 4]),
        Err(ShapeError::ZeroVector { .. })
    ));
    assert!(matches!(
        Polyhedron::new(&[(Vec3::new(f32::NAN, 0.0, 0.0), 1.0); 4]),
        Err(ShapeError::NotFinite { .. })
    ));
    assert!(Polyhedron::platonic(7).is_err());
    // Boxes: flat or NaN.
    assert!(Cuboid::new(Vec3::ZERO, Vec3::new(1.0, 0.0, 1.0)).is_err());
    assert!(Cuboid::new(Vec3::ZERO, Vec3::new(1.0, f32::NAN, 1.0)).is_err());
}

/// Checks faces wind counter-clockwise seen from outside a solid that is star-shaped
/// around `centre`, and returns the enclosed volume (divergence theorem).
fn closed_volume(name: &str, f: &Facets, centre: Vec3) -> f64 {
    let mut volume = 0.0;
    for face in &f.faces {
        assert!(face.len() >= 3, "{name}: face with {} vertices", face.len());
        let v: Vec<DVec3> = face
            .iter()
            .map(|&i| f.vertices[i as usize].as_dvec3())
            .collect();
        let c = v.iter().sum::<DVec3>() / v.len() as f64;
        let mut newell = DVec3::ZERO;
        for (i, a) in v.iter().enumerate() {
            newell += (*a - c).cross(v[(i + 1) % v.len()] - c);
        }
        if newell.length() > 1e-12 {
            assert!(
                newell.dot(c - centre.as_dvec3()) > 0.0,
                "{name}: a face winds clockwise"
            );
        }
        for w in v[1..].windows(2) {
            volume += v[0].dot(w[0].cross(w[1])) / 6.0;
        }
    }
    if !f.normals.is_empty() {
        assert_eq!(
            f.normals.len(),
            f.vertices.len(),
            "{name}: normals per vertex"
        );
    }
    volume
}

#[test]
fn facets_are_closed_outward_and_enclose_the_right_volume() {
    use std::f64::consts::PI;
    let c = Vec3::new(0.5, -0.25, 1.0);
    type Case = (&'static str, Box<dyn Shape>, Vec3, f64, f64);
    let cases: Vec<Case> = vec![
        (
            "box",
            Box::new(Cuboid::new(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0)).unwrap()),
            Vec3::new(0.5, 1.0, 1.5),
            6.0,
            1e-9,
        ),
        (
            "sphere",
            Box::new(Sphere::new(c, 2.0)),
            c,
            4.0 / 3.0 * PI * 8.0,
            0.01,
        ),
        (
            "ellipsoid",
            Box::new(Quadric::ellipsoid(c, Vec3::new(1.0, 2.0, 0.5)).unwrap()),
            c,
            4.0 / 3.0 * PI,
            0.01,
        ),
        (
            "cylinder",
            Box::new(
                Quadric::capped_cylinder(Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 3.0), 0.5)
                    .unwrap(),
            ),
            Vec3::new(1.0, 0.0, 1.5),
            PI * 0.25 * 3.0,
            0.01,
        ),
        (
            "cone",
            Box::new(Quadric::capped_cone(Vec3::ZERO, 1.0, Vec3::new(0.0, 2.0, 0.0), 0.0).unwrap()),
            Vec3::new(0.0, 0.5, 0.0),
            PI * 2.0 / 3.0,
            0.01,
        ),
        (
            "frustum",
            Box::new(Quadric::capped_cone(Vec3::ZERO, 1.0, Vec3::new(2.0, 0.0, 0.0), 0.5).unwrap()),
            Vec3::new(1.0, 0.0, 0.0),
            PI * 2.0 / 3.0 * (1.0 + 0.5 + 0.25),
            0.01,
        ),
        (
            "tetrahedron",
            Box::new(Polyhedron::platonic(4).unwrap()),
            Vec3::ZERO,
            8.0 * 3f64.sqrt(),
            1e-6,
        ),
        (
            "cube",
            Box::new(Polyhedron::platonic(6).unwrap()),
            Vec3::ZERO,
            8.0,
            1e-6,
        ),
        (
            "octahedron",
            Box::new(Polyhedron::platonic(8).unwrap()),
            Vec3::ZERO,
            4.0 * 3f64.sqrt(),
            1e-6,
        ),
        // Inradius 1: dodecahedron V = 10 √((65 + 29√5)/50)... use V = (1/3)·A·r with A the area.
    ];
    for (name, shape, centre, expect, tol) in cases {
        let f = shape.facets(256).unwrap();
        let v = closed_volume(name, &f, centre);
        assert!(
            (v - expect).abs() <= tol * expect,
            "{name}: volume {v} vs {expect}"
        );
        let b = shape.bounds();
        for p in &f.vertices {
            assert!(
                b.contains(*p) || (p.clamp(b.min, b.max) - *p).length() < 1e-5,
                "{name}: vertex outside bounds"
            );
        }
    }
    // Dodecahedron and icosahedron: V = A·r/3 with inradius r = 1, and the Euler
    // characteristic V - E + F = 2.
    for (faces, verts) in [(12usize, 20usize), (20, 12), (4, 4), (6, 8), (8, 6)] {
        let p = Polyhedron::platonic(faces as u32).unwrap();
        let f = p.facets(0).unwrap();
        assert_eq!(f.faces.len(), faces);
        assert_eq!(f.vertices.len(), verts);
        let edges: usize = f.faces.iter().map(|x| x.len()).sum::<usize>() / 2;
        assert_eq!(verts + faces - edges, 2);
        let mut area = 0.0;
        for face in &f.faces {
            let v: Vec<DVec3> = face
                .iter()
                .map(|&i| f.vertices[i as usize].as_dvec3())
                .collect();
            for w in v[1..].windows(2) {
                area += (w[0] - v[0]).cross(w[1] - v[0]).length() / 2.0;
            }
        }
        let v = closed_volume("platonic", &f, Vec3::ZERO);
        assert!((v - area / 3.0).abs() < 1e-5 * v);
    }
    // Disks face their normal.
    let d = Disk::new(Vec3::ZERO, Vec3::Y, 1.0)
        .unwrap()
        .facets(32)
        .unwrap();
    assert_eq!(d.faces.len(), 1);
    let v: Vec<Vec3> = d.faces[0].iter().map(|&i| d.vertices[i as usize]).collect();
    assert!((v[1] - v[0]).cross(v[2] - v[1]).y > 0.0);
}
