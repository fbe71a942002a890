//! Mitsuba 3's shapes against closed forms: rectangle, cube, tube (Mitsuba's open
//! cylinder), sphere and disk uv and normals at known points by Mitsuba's formulas, and
//! the sdfgrid of a sphere's distance field against the analytic sphere to within the
//! grid's interpolation error. Placed by instance transforms at scales 1e-3 .. 1e3.

use glam::{Affine3A, Vec2, Vec3};
use irradia_core::Ray;
use irradia_geometry::shapes::{
    Cube, Cuboid, Disk, Rectangle, SdfGrid, SdfNormals, ShapeError, Sphere, Tube,
};
use irradia_geometry::{Instance, Shape};
use std::f32::consts::TAU;
use std::sync::Arc;

const SCALES: [f32; 5] = [1e-3, 0.1, 1.0, 10.0, 1e3];

fn close(a: f32, b: f32, tol: f32) -> bool {
    (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
}

fn close_uv(a: Vec2, b: Vec2, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol
}

#[test]
fn rectangle_hits_where_the_plane_crossing_is_and_reports_mitsubas_uv() {
    for s in SCALES {
        let shift = Vec3::new(3.0, -2.0, 5.0) * s;
        let inst = Instance::new(
            Arc::new(Rectangle::new()),
            Affine3A::from_translation(shift) * Affine3A::from_scale(Vec3::splat(s)),
        );
        for (x, y) in [(0.0, 0.0), (0.5, -0.25), (-0.9, 0.9), (0.99, -0.99)] {
            let target = shift + Vec3::new(x, y, 0.0) * s;
            let origin = target + Vec3::new(0.3, -0.2, 4.0) * s;
            let ray = Ray::new(origin, target - origin);
            let h = inst.intersect(&ray, f32::INFINITY).expect("a hit");
            assert!(close(h.t, 1.0, 1e-5), "scale {s}: t {}", h.t);
            assert!((h.normal - Vec3::Z).length() < 1e-5);
            let uv = Vec2::new((x + 1.0) / 2.0, (y + 1.0) / 2.0);
            assert!(close_uv(h.uv, uv, 1e-5), "{} vs {uv}", h.uv);
            assert!(inst.occluded(&ray, 1.01));
            assert!(!inst.occluded(&ray, 0.99));
        }
        // Outside the square, and parallel to it: no hit.
        let miss = Ray::new(shift + Vec3::new(1.01, 0.0, 1.0) * s, -Vec3::Z);
        assert!(inst.intersect(&miss, f32::INFINITY).is_none());
        let parallel = Ray::new(shift + Vec3::new(-2.0, 0.0, 0.0) * s, Vec3::X);
        assert!(inst.intersect(&parallel, f32::INFINITY).is_none());
    }
    let flipped = Rectangle::flipped(true);
    let h = flipped
        .intersect(&Ray::new(Vec3::new(0.2, 0.4, -1.0), Vec3::Z), 10.0)
        .unwrap();
    assert_eq!(h.normal, -Vec3::Z);
    assert!(close_uv(h.uv, Vec2::new(0.6, 0.7), 1e-6));
    assert!(!flipped.is_solid());
    assert_eq!(flipped.area(), Some(4.0));
}

/// Mitsuba's cube mesh (src/shapes/cube.cpp): per face its outward normal and four
/// (position, uv) vertices, triangles (0, 1, 2) and (3, 0, 2).
fn mitsuba_cube_faces() -> Vec<(Vec3, [(Vec3, Vec2); 4])> {
    let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    let uv = [
        Vec2::new(0.0, 1.0),
        Vec2::new(1.0, 1.0),
        Vec2::new(1.0, 0.0),
        Vec2::new(0.0, 0.0),
    ];
    let faces = [
        (
            -Vec3::Y,
            [
                v(1., -1., -1.),
                v(1., -1., 1.),
                v(-1., -1., 1.),
                v(-1., -1., -1.),
            ],
        ),
        (
            Vec3::Y,
            [
                v(1., 1., -1.),
                v(-1., 1., -1.),
                v(-1., 1., 1.),
                v(1., 1., 1.),
            ],
        ),
        (
            Vec3::X,
            [
                v(1., -1., -1.),
                v(1., 1., -1.),
                v(1., 1., 1.),
                v(1., -1., 1.),
            ],
        ),
        (
            Vec3::Z,
            [
                v(1., -1., 1.),
                v(1., 1., 1.),
                v(-1., 1., 1.),
                v(-1., -1., 1.),
            ],
        ),
        (
            -Vec3::X,
            [
                v(-1., -1., 1.),
                v(-1., 1., 1.),
                v(-1., 1., -1.),
                v(-1., -1., -1.),
            ],
        ),
        (
            -Vec3::Z,
            [
                v(1., 1., -1.),
                v(1., -1., -1.),
                v(-1., -1., -1.),
                v(-1., 1., -1.),
            ],
        ),
    ];
    faces
        .iter()
        .map(|(n, p)| (*n, std::array::from_fn(|k| (p[k], uv[k]))))
        .collect()
}

/// The uv Mitsuba's mesh interpolates at `p` on the face: barycentrics in whichever of
/// the face's two triangles holds `p`.
fn mesh_uv(face: &[(Vec3, Vec2); 4], p: Vec3) -> Option<Vec2> {
    for tri in [[0, 1, 2], [3, 0, 2]] {
        let [a, b, c] = tri.map(|k| face[k]);
        let (e1, e2, w) = (b.0 - a.0, c.0 - a.0, p - a.0);
        let n = e1.cross(e2);
        let b1 = w.cross(e2).dot(n) / n.length_squared();
        let b2 = e1.cross(w).dot(n) / n.length_squared();
        if b1 >= -1e-6 && b2 >= -1e-6 && b1 + b2 <= 1.0 + 1e-6 {
            return Some(a.1 * (1.0 - b1 - b2) + b.1 * b1 + c.1 * b2);
        }
    }
    None
}

#[test]
fn cube_uv_is_mitsubas_mesh_uv_on_every_face() {
    let cube = Cube::default();
    let faces = mitsuba_cube_faces();
    for (n, face) in &faces {
        for (a, b) in [
            (0.0, 0.0),
            (0.5, -0.3),
            (-0.8, 0.7),
            (0.95, 0.95),
            (-0.6, -0.9),
        ] {
            // A point on the face from two in-face coordinates.
            let axis = if n.x != 0.0 {
                0
            } else if n.y != 0.0 {
                1
            } else {
                2
            };
            let mut p = *n;
            p[(axis + 1) % 3] = a;
            p[(axis + 2) % 3] = b;
            let ray = Ray::new(p + *n * 3.0 + Vec3::new(0.0, 0.0, 0.0), -*n);
            let h = cube.intersect(&ray, f32::INFINITY).expect("a hit");
            assert!(close(h.t, 3.0, 1e-6));
            assert_eq!(h.normal, *n);
            let want = mesh_uv(face, p).expect("on the face");
            assert!(close_uv(h.uv, want, 1e-6), "face {n}: {} vs {want}", h.uv);
        }
    }
}

#[test]
fn cube_is_the_box_at_every_scale_with_spans() {
    for s in SCALES {
        let m = Affine3A::from_scale(Vec3::splat(s)) * Affine3A::from_rotation_y(0.3);
        let cube = Instance::new(Arc::new(Cube::default()), m);
        let bx = Instance::new(Arc::new(Cuboid::new(-Vec3::ONE, Vec3::ONE).unwrap()), m);
        for (o, d) in [
            (Vec3::new(5.0, 0.2, 0.3), Vec3::new(-1.0, 0.01, 0.02)),
            (Vec3::new(0.1, -4.0, 0.5), Vec3::new(0.05, 1.0, -0.1)),
            (Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.3, 0.2, 1.0)),
        ] {
            let ray = Ray::new(o * s, d);
            let (a, b) = (
                cube.intersect(&ray, f32::INFINITY).unwrap(),
                bx.intersect(&ray, f32::INFINITY).unwrap(),
            );
            assert_eq!(a.t, b.t);
            assert_eq!(a.normal, b.normal);
            let (mut sa, mut sb) = (Vec::new(), Vec::new());
            cube.spans(&ray, &mut sa);
            bx.spans(&ray, &mut sb);
            assert_eq!(sa.len(), 1);
            assert_eq!((sa[0].enter.t, sa[0].exit.t), (sb[0].enter.t, sb[0].exit.t));
        }
    }
    let flipped = Cube::new(true);
    assert!(!flipped.is_solid());
    let h = flipped
        .intersect(&Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z), 100.0)
        .unwrap();
    assert_eq!(h.normal, -Vec3::Z);
}

#[test]
fn tube_hits_the_side_only_with_mitsubas_uv() {
    for s in SCALES {
        let (p0, p1, r) = (
            Vec3::new(1.0, 2.0, 3.0) * s,
            Vec3::new(1.0, 2.0, 7.0) * s,
            0.5 * s,
        );
        let tube = Tube::new(p0, p1, r).unwrap();
        // Axis +z: Mitsuba's frame is (+x, +y). Rays towards the axis at height z.
        for (phi, z) in [
            (0.0f32, 1.0f32),
            (0.25 * TAU, 2.0),
            (0.6 * TAU, 3.5),
            (0.9 * TAU, 0.2),
        ] {
            let radial = Vec3::new(phi.cos(), phi.sin(), 0.0);
            let target = p0 + radial * r + Vec3::Z * (z * s);
            let origin = target + radial * (3.0 * s);
            let h = tube
                .intersect(&Ray::new(origin, -radial), f32::INFINITY)
                .expect("a hit");
            assert!(close(h.t, 3.0 * s, 1e-5), "scale {s}: t {}", h.t);
            assert!((h.normal - radial).length() < 1e-5);
            let want = Vec2::new(phi / TAU, z / 4.0);
            assert!(close_uv(h.uv, want, 1e-5), "{} vs {want}", h.uv);
            // From inside the tube the far wall is hit, its normal still outward.
            let h = tube
                .intersect(&Ray::new(p0 + Vec3::Z * (z * s), radial), f32::INFINITY)
                .unwrap();
            assert!(close(h.t, r, 1e-5));
            assert!((h.normal - radial).length() < 1e-5);
        }
        // Open ends: a ray along the axis passes through; beyond the ends, no hit.
        let axial = Ray::new(p0 - Vec3::Z * s, Vec3::Z);
        assert!(tube.intersect(&axial, f32::INFINITY).is_none());
        let above = Ray::new(p1 + Vec3::new(3.0, 0.0, 0.1) * s, -Vec3::X);
        assert!(!tube.occluded(&above, f32::INFINITY));
        assert!(!tube.is_solid());
        let area = tube.area().unwrap();
        assert!(close(area, TAU * r * 4.0 * s, 1e-5));
    }
    // A tilted tube: the hit point lies on the cylinder and v = z / L.
    let (p0, p1) = (Vec3::new(-1.0, 0.5, 0.2), Vec3::new(2.0, -1.0, 1.0));
    let tube = Tube::new(p0, p1, 0.7).unwrap().with_flipped_normals(true);
    let axis = (p1 - p0).normalize();
    let ray = Ray::new(Vec3::new(0.5, 3.0, 0.4), Vec3::new(0.05, -1.0, 0.1));
    let h = tube.intersect(&ray, f32::INFINITY).unwrap();
    let rel = h.point - p0;
    let along = rel.dot(axis);
    let radial = rel - axis * along;
    assert!(close(radial.length(), 0.7, 1e-5));
    assert!(close(h.uv.y, along / (p1 - p0).length(), 1e-5));
    assert!(
        (h.normal + radial.normalize()).length() < 1e-5,
        "flipped: inward"
    );
}

#[test]
fn tube_refuses_bad_input() {
    assert!(matches!(
        Tube::new(Vec3::ONE, Vec3::ONE, 1.0),
        Err(ShapeError::Coincident { .. })
    ));
    assert!(matches!(
        Tube::new(Vec3::ZERO, Vec3::Z, 0.0),
        Err(ShapeError::NotPositive { .. })
    ));
    assert!(matches!(
        Tube::new(Vec3::ZERO, Vec3::new(f32::NAN, 0.0, 1.0), 1.0),
        Err(ShapeError::NotFinite { .. })
    ));
}

/// Mitsuba's sphere uv of a direction (x, y, z): (atan2(y, x) / 2π in [0, 1), acos(z) / π).
fn sphere_uv(d: Vec3) -> Vec2 {
    let mut u = d.y.atan2(d.x) / TAU;
    if u < 0.0 {
        u += 1.0;
    }
    Vec2::new(u, d.z.clamp(-1.0, 1.0).acos() / std::f32::consts::PI)
}

#[test]
fn sphere_uv_and_normals_are_mitsubas() {
    for s in SCALES {
        let c = Vec3::new(1.0, -2.0, 0.5) * s;
        let sphere = Sphere::new(c, 2.0 * s);
        for d in [
            Vec3::X,
            Vec3::Y,
            -Vec3::X,
            Vec3::new(0.0, -1.0, 0.0),
            Vec3::new(0.3, 0.4, 0.866),
            Vec3::new(-0.5, -0.2, -0.8),
        ] {
            let d = d.normalize();
            let ray = Ray::new(c + d * (5.0 * s), -d);
            let h = sphere.intersect(&ray, f32::INFINITY).unwrap();
            assert!(close(h.t, 3.0 * s, 1e-5));
            assert!((h.normal - d).length() < 1e-5);
            assert!(
                close_uv(h.uv, sphere_uv(d), 1e-4),
                "{d}: {} vs {}",
                h.uv,
                sphere_uv(d)
            );
        }
    }
    // The known points: +x at u = 0, +y a quarter turn, v = 0 at the +z pole.
    let sphere = Sphere::new(Vec3::ZERO, 1.0);
    let uv = |d: Vec3| sphere.intersect(&Ray::new(d * 3.0, -d), 10.0).unwrap().uv;
    assert!(close_uv(uv(Vec3::X), Vec2::new(0.0, 0.5), 1e-4));
    assert!(close_uv(uv(Vec3::Y), Vec2::new(0.25, 0.5), 1e-4));
    assert!(close_uv(uv(-Vec3::Y), Vec2::new(0.75, 0.5), 1e-4));
    assert!(uv(Vec3::Z).y < 1e-4 && uv(-Vec3::Z).y > 1.0 - 1e-4);
    // flip_normals: inward normals, no longer a solid.
    let flipped = Sphere::new(Vec3::ZERO, 1.0).with_flipped_normals(true);
    let h = flipped
        .intersect(&Ray::new(Vec3::ZERO, Vec3::X), 10.0)
        .unwrap();
    assert!((h.normal + Vec3::X).length() < 1e-6);
    assert!(!flipped.is_solid());
}

#[test]
fn disk_uv_is_mitsubas_radius_and_turn() {
    for s in SCALES {
        let c = Vec3::new(0.5, 0.5, -1.0) * s;
        let disk = Disk::new(c, Vec3::Z, 2.0 * s).unwrap();
        for (r, phi) in [(0.5f32, 0.0f32), (1.0, 0.25), (1.9, 0.6), (0.1, 0.99)] {
            let a = phi * TAU;
            let p = c + Vec3::new(a.cos(), a.sin(), 0.0) * (r * s);
            let h = disk
                .intersect(
                    &Ray::new(
                        p + Vec3::new(0.1, 0.0, 2.0) * s,
                        -Vec3::new(0.1, 0.0, 2.0) * s,
                    ),
                    2.0,
                )
                .unwrap();
            assert!(close(h.t, 1.0, 1e-5));
            assert_eq!(h.normal, Vec3::Z);
            let want = Vec2::new(r / 2.0, phi);
            assert!(close_uv(h.uv, want, 1e-4), "{} vs {want}", h.uv);
        }
    }
    let flipped = Disk::new(Vec3::ZERO, Vec3::Z, 1.0)
        .unwrap()
        .with_flipped_normals(true);
    let h = flipped
        .intersect(&Ray::new(Vec3::new(0.0, 0.5, 1.0), -Vec3::Z), 10.0)
        .unwrap();
    assert_eq!(h.normal, -Vec3::Z);
    assert!(
        close_uv(h.uv, Vec2::new(0.5, 0.25), 1e-6),
        "uv kept: {}",
        h.uv
    );
}

/// The distance field of the sphere of `radius` around the grid's centre, on n³ values.
fn sphere_grid(n: usize, radius: f32, normals: SdfNormals) -> SdfGrid {
    let c = Vec3::splat(0.5);
    let mut v = Vec::with_capacity(n * n * n);
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let p = Vec3::new(x as f32, y as f32, z as f32) / (n - 1) as f32;
                v.push((p - c).length() - radius);
            }
        }
    }
    SdfGrid::new([n, n, n], v, normals).unwrap()
}

#[test]
fn sdfgrid_of_a_sphere_agrees_with_the_sphere() {
    let radius = 0.3;
    let sphere = Sphere::new(Vec3::splat(0.5), radius);
    for n in [16usize, 48] {
        let grid = sphere_grid(n, radius, SdfNormals::Smooth);
        assert!(grid.is_solid());
        // Trilinear interpolation of a distance field whose Hessian is at most 1/R
        // per axis errs by at most 3 h² / (8 R) in value on cells of side h, hence by
        // as much in distance along the normal (|∇f| = 1), and by that over the
        // cosine of incidence along the ray.
        let h = 1.0 / (n - 1) as f32;
        let tol_n = h * h / (2.0 * radius);
        let mut rng = 12345u32;
        let mut next = || {
            rng ^= rng << 13;
            rng ^= rng >> 17;
            rng ^= rng << 5;
            rng as f32 / u32::MAX as f32
        };
        for _ in 0..300 {
            let dir = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize();
            let aim = Vec3::splat(0.5) + Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5) * 0.4;
            let ray = Ray::new(aim - dir * 2.0, dir);
            let want = sphere.intersect(&ray, f32::INFINITY);
            let got = grid.intersect(&ray, f32::INFINITY);
            match (want, got) {
                (Some(w), Some(g)) => {
                    let r = (g.point - Vec3::splat(0.5)).length();
                    assert!((r - radius).abs() < tol_n, "n {n}: radius {r}");
                    let cos = w.normal.dot(dir).abs();
                    if cos < 0.3 {
                        continue; // grazing: t is ill-conditioned
                    }
                    let tol = tol_n / cos;
                    assert!((w.t - g.t).abs() < tol, "n {n}: t {} vs {}", g.t, w.t);
                    assert!(
                        w.normal.dot(g.normal) > 0.98,
                        "{} vs {}",
                        g.normal,
                        w.normal
                    );
                    assert!(w.normal.dot(g.shading_normal) > 0.995);
                    assert_eq!(g.uv, Vec2::ZERO);
                    let mut sp = Vec::new();
                    grid.spans(&ray, &mut sp);
                    assert_eq!(sp.len(), 1);
                    let (mut ws, mut wsp) = (Vec::new(), Vec::new());
                    sphere.spans(&ray, &mut ws);
                    wsp.extend(ws);
                    assert!((sp[0].enter.t - wsp[0].enter.t).abs() < tol);
                    assert!((sp[0].exit.t - wsp[0].exit.t).abs() < tol);
                    // From inside, the exit is found.
                    let mid = 0.5 * (sp[0].enter.t + sp[0].exit.t);
                    let inner = Ray::new(ray.at(mid), dir);
                    let e = grid.intersect(&inner, f32::INFINITY).unwrap();
                    assert!((e.t - (sp[0].exit.t - mid)).abs() < tol);
                    assert!(grid.occluded(&ray, f32::INFINITY));
                    assert!(!grid.occluded(&ray, g.t * 0.99));
                }
                (None, None) => {}
                // Grazing rays may differ by the interpolation error.
                (w, g) => {
                    let d = (ray.origin - Vec3::splat(0.5)).cross(dir).length();
                    assert!((d - radius).abs() < tol_n, "{w:?} vs {g:?} at distance {d}");
                }
            }
        }
    }
}

#[test]
fn sdfgrid_normals_and_placement() {
    // A plane field f = z - 0.4: exact under trilinear interpolation.
    let n = 5;
    let mut v = Vec::new();
    for z in 0..n {
        for _y in 0..n {
            for _x in 0..n {
                v.push(z as f32 / (n - 1) as f32 - 0.4);
            }
        }
    }
    let grid = SdfGrid::new([n, n, n], v, SdfNormals::Analytic).unwrap();
    // The field is negative on the bottom face: not closed, so not a solid.
    assert!(!grid.is_solid());
    for s in SCALES {
        let inst = Instance::new(Arc::new(grid.clone()), Affine3A::from_scale(Vec3::splat(s)));
        let ray = Ray::new(Vec3::new(0.3, 0.6, 2.0) * s, -Vec3::Z * s);
        let h = inst.intersect(&ray, f32::INFINITY).unwrap();
        assert!(close(h.t, 1.6, 1e-5), "scale {s}: {}", h.t);
        assert!((h.normal - Vec3::Z).length() < 1e-5);
        assert!((h.shading_normal - Vec3::Z).length() < 1e-5);
    }
}

#[test]
fn sdfgrid_refuses_bad_grids() {
    let err = |n: [usize; 3], v: Vec<f32>| SdfGrid::new(n, v, SdfNormals::Smooth).unwrap_err();
    assert!(err([1, 2, 2], vec![1.0; 4])
        .to_string()
        .contains("at least 2"));
    assert!(err([2, 2, 2], vec![1.0; 7])
        .to_string()
        .contains("nx · ny · nz"));
    assert!(err([2, 2, 2], vec![1.0; 8])
        .to_string()
        .contains("no surface"));
    let mut v = vec![1.0; 8];
    v[3] = f32::NAN;
    assert!(matches!(err([2, 2, 2], v), ShapeError::NotFinite { .. }));
}
