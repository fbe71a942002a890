//! Planar polygons, convex and not: inside/outside by the even-odd rule for a square,
//! an L shape, a ten-pointed concave star and a self-intersecting pentagram; facets
//! (ear clipping) cover the same area; degenerate input is an error.

use glam::{Vec2, Vec3};
use irradia_core::{Affine3A, Ray, Rng};
use irradia_geometry::shapes::{Polygon, ShapeError};
use irradia_geometry::Shape;

/// Even-odd membership in 2D, written independently (winding of crossings by angle
/// would be another rule; this is the same rule by a different computation: count the
/// edges a +x half-line crosses, using exact rational comparison of cross products).
fn even_odd(poly: &[Vec2], q: Vec2) -> bool {
    let mut crossings = 0;
    for i in 0..poly.len() {
        let (a, b) = (poly[i].as_dvec2(), poly[(i + 1) % poly.len()].as_dvec2());
        let q = q.as_dvec2();
        let (lo, hi) = if a.y < b.y { (a, b) } else { (b, a) };
        if q.y >= lo.y && q.y < hi.y {
            // The crossing is right of q iff q is left of the edge lo→hi.
            if (hi - lo).perp_dot(q - lo) > 0.0 {
                crossings += 1;
            }
        }
    }
    crossings % 2 == 1
}

fn star(points: usize, r_out: f32, r_in: f32) -> Vec<Vec2> {
    (0..2 * points)
        .map(|i| {
            let a = std::f32::consts::PI * i as f32 / points as f32;
            let r = if i % 2 == 0 { r_out } else { r_in };
            Vec2::new(r * a.cos(), r * a.sin())
        })
        .collect()
}

fn pentagram() -> Vec<Vec2> {
    (0..5)
        .map(|i| {
            let a = std::f32::consts::TAU * (2 * i) as f32 / 5.0 + 0.3;
            Vec2::new(2.0 * a.cos(), 2.0 * a.sin())
        })
        .collect()
}

fn l_shape() -> Vec<Vec2> {
    [
        (0.0, 0.0),
        (2.0, 0.0),
        (2.0, 1.0),
        (1.0, 1.0),
        (1.0, 2.0),
        (0.0, 2.0),
    ]
    .map(|(x, y)| Vec2::new(x, y))
    .to_vec()
}

fn shoelace(p: &[Vec2]) -> f32 {
    (0..p.len())
        .map(|i| p[i].perp_dot(p[(i + 1) % p.len()]))
        .sum::<f32>()
        / 2.0
}

/// Places the 2D outline in 3D by `m` and fires rays through grid points.
fn check_outline(name: &str, outline: &[Vec2], m: Affine3A) {
    let verts: Vec<Vec3> = outline
        .iter()
        .map(|p| m.transform_point3(p.extend(0.0)))
        .collect();
    let poly = Polygon::new(verts).unwrap();
    let normal = m.transform_vector3(Vec3::Z).normalize();
    assert!(poly.normal().dot(normal).abs() > 0.999, "{name}: normal");
    let (mut inside, mut outside) = (0, 0);
    let mut rng = Rng::new(11, 3);
    for _ in 0..3000 {
        let q = Vec2::new(rng.next_f32() * 5.0 - 2.5, rng.next_f32() * 5.0 - 2.5);
        // Skip points within 1e-4 of an edge (either answer is right there).
        let near_edge = (0..outline.len()).any(|i| {
            let (a, b) = (outline[i], outline[(i + 1) % outline.len()]);
            let t = ((q - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
            (a + (b - a) * t - q).length() < 1e-4
        });
        if near_edge {
            continue;
        }
        let expect = even_odd(outline, q);
        let p = m.transform_point3(q.extend(0.0));
        let dir = (normal + Vec3::new(0.1, -0.2, 0.05)).normalize();
        let ray = Ray::new(p - 3.0 * dir, dir);
        let hit = poly.intersect(&ray, f32::INFINITY);
        assert_eq!(hit.is_some(), expect, "{name}: point {q} inside={expect}");
        if let Some(h) = hit {
            assert!((h.point - p).length() < 1e-4, "{name}: hit point");
            inside += 1;
        } else {
            outside += 1;
        }
        // From the other side too (open surfaces are hit from both sides).
        let back = Ray::new(p + 3.0 * dir, -dir);
        assert_eq!(poly.intersect(&back, f32::INFINITY).is_some(), expect);
        assert_eq!(poly.occluded(&back, f32::INFINITY), expect);
    }
    assert!(
        inside > 100 && outside > 100,
        "{name}: {inside} in, {outside} out"
    );
    // Facets cover the outline's area (when it is simple).
    if let Some(f) = poly.facets(0) {
        let mut area = 0.0;
        for face in &f.faces {
            let v: Vec<Vec3> = face.iter().map(|&i| f.vertices[i as usize]).collect();
            for w in v[1..].windows(2) {
                area += (w[0] - v[0]).cross(w[1] - v[0]).dot(poly.normal()) / 2.0;
            }
        }
        let scale = m.matrix3.determinant().abs() / m.transform_vector3(Vec3::Z).length();
        let expect = shoelace(outline).abs() * scale;
        assert!(
            (area - expect).abs() < 1e-3 * expect,
            "{name}: facets area {area} vs {expect}"
        );
    }
}

#[test]
fn convex_and_non_convex_outlines_follow_even_odd() {
    let square = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(x, y)| Vec2::new(x, y));
    let placements = [
        Affine3A::IDENTITY,
        Affine3A::from_rotation_translation(
            glam::Quat::from_euler(glam::EulerRot::XYZ, 0.5, 1.1, -0.3),
            Vec3::new(3.0, -1.0, 2.0),
        ),
    ];
    for m in placements {
        check_outline("square", &square, m);
        check_outline("L shape", &l_shape(), m);
        check_outline("star", &star(5, 2.0, 0.8), m);
        check_outline("pentagram", &pentagram(), m);
    }
    let convex = |o: &[Vec2]| {
        Polygon::new(o.iter().map(|p| p.extend(0.0)).collect())
            .unwrap()
            .is_convex()
    };
    assert!(convex(&square));
    assert!(!convex(&l_shape()) && !convex(&star(5, 2.0, 0.8)) && !convex(&pentagram()));
    // The pentagram's centre is outside under even-odd (crossed twice).
    let p = Polygon::new(pentagram().iter().map(|p| p.extend(0.0)).collect()).unwrap();
    assert!(p
        .intersect(&Ray::new(Vec3::new(0.0, 0.0, 1.0), -Vec3::Z), 10.0)
        .is_none());
    assert!(
        p.facets(0).is_none(),
        "a self-intersecting outline has no triangulation"
    );
    // The L's notch is outside, its arms inside.
    let l = Polygon::new(l_shape().iter().map(|p| p.extend(0.0)).collect()).unwrap();
    let down = |x: f32, y: f32| Ray::new(Vec3::new(x, y, 1.0), -Vec3::Z);
    assert!(l.intersect(&down(1.5, 1.5), 10.0).is_none());
    assert!(
        l.intersect(&down(1.5, 0.5), 10.0).is_some()
            && l.intersect(&down(0.5, 1.5), 10.0).is_some()
    );
    assert!(!l.is_solid());
}

#[test]
fn degenerate_polygons_are_errors() {
    let v = |a: &[(f32, f32, f32)]| {
        a.iter()
            .map(|&(x, y, z)| Vec3::new(x, y, z))
            .collect::<Vec<_>>()
    };
    assert_eq!(
        Polygon::new(v(&[(0.0, 0.0, 0.0), (1.0, 0.0, 0.0)])).unwrap_err(),
        ShapeError::TooFewVertices { count: 2 }
    );
    assert!(matches!(
        Polygon::new(vec![]),
        Err(ShapeError::TooFewVertices { count: 0 })
    ));
    assert_eq!(
        Polygon::new(v(&[
            (0.0, 0.0, 0.0),
            (1.0, 1.0, 1.0),
            (2.0, 2.0, 2.0),
            (3.0, 3.0, 3.0)
        ]))
        .unwrap_err(),
        ShapeError::ZeroArea
    );
    assert_eq!(
        Polygon::new(v(&[(1.0, 2.0, 3.0); 3])).unwrap_err(),
        ShapeError::ZeroArea
    );
    assert!(matches!(
        Polygon::new(v(&[
            (0.0, 0.0, 0.0),
            (1.0, 0.0, 0.0),
            (1.0, 1.0, 0.1),
            (0.0, 1.0, 0.0)
        ])),
        Err(ShapeError::NotPlanar { vertex: _, .. })
    ));
    assert!(matches!(
        Polygon::new(v(&[(0.0, 0.0, 0.0), (f32::NAN, 0.0, 0.0), (0.0, 1.0, 0.0)])),
        Err(ShapeError::NotFinite { .. })
    ));
    assert!(matches!(
        Polygon::new(v(&[
            (0.0, 0.0, 0.0),
            (f32::INFINITY, 0.0, 0.0),
            (0.0, 1.0, 0.0)
        ])),
        Err(ShapeError::NotFinite { .. })
    ));
    // Messages are clear.
    let msg = Polygon::new(v(&[
        (0.0, 0.0, 0.0),
        (1.0, 0.0, 0.0),
        (1.0, 1.0, 0.1),
        (0.0, 1.0, 0.0),
    ]))
    .unwrap_err()
    .to_string();
    assert!(
        msg.contains("not planar") && msg.contains("vertex"),
        "{msg}"
    );
    // Planar within f32 rounding after a rotation: accepted.
    let m = Affine3A::from_rotation_translation(
        glam::Quat::from_euler(glam::EulerRot::XYZ, 0.3, 0.9, 1.7),
        Vec3::splat(1e3),
    );
    let verts = star(7, 1.0, 0.5)
        .iter()
        .map(|p| m.transform_point3(p.extend(0.0)))
        .collect();
    assert!(Polygon::new(verts).is_ok());
}
