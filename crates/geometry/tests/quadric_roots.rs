//! Ray-quadric roots against closed forms at scales from 1e-3 to 1e6.
//!
//! Each case places a named quadric at `scale` (size and offset from the origin both
//! grow with it) and fires a ray along a coordinate axis, for which the crossing points
//! have a closed form in the quadric's parameters. The closed form is evaluated in f64
//! from the same f32 inputs the shape received.
//!
//! Bounds, justified:
//! - The f64 roots (from `QuadricForm::inside_intervals`) must agree to `1e-11 · scale`.
//!   The roots are transversal (the rays cross at angles with |cos| ≥ 0.3 to the
//!   surface), so their condition number is O(10); forming the coefficients and one
//!   Newton step take O(30) roundings of `u = 1.1e-16` each relative to the largest
//!   term, which is at most `(10·scale)²`: about 1e-13 relative to `scale`. 1e-11 leaves
//!   a factor of 100.
//! - The f32 `Hit::t` must agree to `2⁻²³` relative (the f64 root rounded to f32 is
//!   within half an ulp, `2⁻²⁴`; the other half covers the f64 error above).

use glam::{DVec3, Vec3};
use irradia_core::{Affine3A, Ray};
use irradia_geometry::shapes::quadric::{HalfSpace, QuadricForm};
use irradia_geometry::shapes::{Quadric, ShapeError};
use irradia_geometry::Shape;

const SCALES: [f64; 7] = [1e-3, 1e-2, 1.0, 10.0, 1e3, 1e4, 1e6];

/// Compares the quadric's f64 crossings of `o + t d` and its first f32 hit with the
/// expected parameters (sorted, finite ones only).
fn check(q: &Quadric, o: Vec3, d: Vec3, expected: &[f64], scale: f64, what: &str) {
    let (od, dd) = (o.as_dvec3(), d.as_dvec3());
    // Both solvers: Newton-polished from the ray's origin, and the one intersection
    // uses (from the point nearest the bounds' centre when bounded).
    for iv in [q.form().inside_intervals(od, dd), q.line_intervals(od, dd)] {
        let mut got: Vec<f64> = iv
            .as_slice()
            .iter()
            .flat_map(|&(a, b)| [a, b])
            .filter(|t| t.is_finite())
            .collect();
        got.sort_by(f64::total_cmp);
        assert_eq!(
            got.len(),
            expected.len(),
            "{what} at scale {scale}: roots {got:?} vs {expected:?}"
        );
        for (g, e) in got.iter().zip(expected) {
            let err = (g - e).abs() / scale;
            assert!(
                err <= 1e-11,
                "{what} at scale {scale}: root {g} vs {e} (error {err:e} of scale)"
            );
        }
    }
    let first = expected.iter().copied().find(|&t| t > 0.0).unwrap();
    let hit = q
        .intersect(&Ray::new(o, d), f32::INFINITY)
        .unwrap_or_else(|| panic!("{what} at scale {scale}: no hit"));
    let rel = (hit.t as f64 - first).abs() / first;
    assert!(
        rel <= 2f64.powi(-23),
        "{what} at scale {scale}: t {} vs {first} (rel {rel:e})",
        hit.t
    );
    // The normal is the unit gradient, pointing out of Q ≤ 0.
    let g = q.form().gradient(hit.point.as_dvec3()).normalize();
    assert!(
        (hit.normal.as_dvec3() - g).length() < 1e-5,
        "{what}: normal"
    );
    assert!(
        hit.error >= 0.0 && (hit.error as f64) < 1e-5 * scale * 20.0,
        "{what}: error {}",
        hit.error
    );
}

fn f(v: f32) -> f64 {
    v as f64
}

#[test]
fn ellipsoid_matches_closed_form() {
    for s in SCALES {
        let c = (DVec3::new(3.0, -2.0, 1.5) * s).as_vec3();
        let r = (DVec3::new(2.0, 1.5, 1.0) * s).as_vec3();
        let q = Quadric::ellipsoid(c, r).unwrap();
        // Ray along +x at y = cy + 0.5 ry... offsets chosen as f32 values.
        let (y0, z0) = ((0.6 * s) as f32, (-0.3 * s) as f32);
        let o = Vec3::new(c.x - 10.0 * r.x, c.y + y0, c.z + z0);
        let (oy, oz) = (f(o.y) - f(c.y), f(o.z) - f(c.z));
        let k = (1.0 - (oy / f(r.y)).powi(2) - (oz / f(r.z)).powi(2)).sqrt() * f(r.x);
        let x0 = f(c.x) - f(o.x);
        check(&q, o, Vec3::X, &[x0 - k, x0 + k], s, "ellipsoid");
        // And along -y from above, through a point off the axis.
        let o = Vec3::new(c.x + (0.5 * s) as f32, c.y + 7.0 * r.y, c.z);
        let ox = f(o.x) - f(c.x);
        let k = (1.0 - (ox / f(r.x)).powi(2)).sqrt() * f(r.y);
        let y = f(o.y) - f(c.y);
        check(&q, o, -Vec3::Y, &[y - k, y + k], s, "ellipsoid (y)");
    }
}

#[test]
fn infinite_cylinder_cone_and_hyperboloids_match_closed_forms() {
    for s in SCALES {
        let sf = s as f32;
        let shift = Affine3A::from_translation(Vec3::new(2.0, 3.0, -1.0) * sf);
        let r = 1.5 * sf;
        let cyl = Quadric::cylinder(r).unwrap().transformed(&shift).unwrap();
        // Along +x at z offset z0 from the axis (the axis is at x = 2s, z = -s).
        let z0 = 0.5 * sf;
        let o = Vec3::new(-20.0 * sf, 0.0, -sf + z0);
        let k = (f(r).powi(2) - (f(o.z) + f(sf)).powi(2)).sqrt();
        let x = f(2.0 * sf) - f(o.x);
        check(&cyl, o, Vec3::X, &[x - k, x + k], s, "cylinder");

        let slope = 0.75f32;
        let cone = Quadric::cone(slope).unwrap().transformed(&shift).unwrap();
        // At height y0 above the apex the cone has radius slope·y0.
        let y0 = 2.0 * sf;
        let o = Vec3::new(-20.0 * sf, 3.0 * sf + y0, -sf);
        let k = f(slope) * (f(o.y) - f(3.0 * sf));
        check(&cone, o, Vec3::X, &[x - k, x + k], s, "cone");

        let (a, c) = (1.2 * sf, 0.8 * sf);
        let h1 = Quadric::hyperboloid_one_sheet(a, c)
            .unwrap()
            .transformed(&shift)
            .unwrap();
        let k = f(a) * (1.0 + ((f(o.y) - f(3.0 * sf)) / f(c)).powi(2)).sqrt();
        check(
            &h1,
            o,
            Vec3::X,
            &[x - k, x + k],
            s,
            "hyperboloid of one sheet",
        );

        let h2 = Quadric::hyperboloid_two_sheets(a, c)
            .unwrap()
            .transformed(&shift)
            .unwrap();
        // Along -y through (x0, z0) off the axis: y = ±c √(1 + ρ²/a²).
        let o = Vec3::new(2.0 * sf + 0.4 * sf, 3.0 * sf + 30.0 * sf, -sf);
        let rho2 = (f(o.x) - f(2.0 * sf)).powi(2);
        let k = f(c) * (1.0 + rho2 / f(a).powi(2)).sqrt();
        let y = f(o.y) - f(3.0 * sf);
        check(
            &h2,
            o,
            -Vec3::Y,
            &[y - k, y + k],
            s,
            "hyperboloid of two sheets",
        );

        let kpar = 0.5 / sf;
        let par = Quadric::paraboloid(kpar)
            .unwrap()
            .transformed(&shift)
            .unwrap();
        // Along +x at height y0 above the vertex: x = ±√(y0/k).
        let o = Vec3::new(-20.0 * sf, 3.0 * sf + 2.0 * sf, -sf);
        let k = ((f(o.y) - f(3.0 * sf)) / f(kpar)).sqrt();
        check(&par, o, Vec3::X, &[x - k, x + k], s, "paraboloid");
    }
}

#[test]
fn capped_cylinder_and_cone_hit_caps_and_sides() {
    for s in SCALES {
        let sf = s as f32;
        let a = Vec3::new(1.0, 1.0, 1.0) * sf;
        let b = Vec3::new(1.0, 4.0, 1.0) * sf;
        let cyl = Quadric::capped_cylinder(a, b, 0.5 * sf).unwrap();
        // Down the axis: the top cap then the bottom cap.
        let o = Vec3::new(sf, 10.0 * sf, sf);
        let hit = cyl
            .intersect(&Ray::new(o, -Vec3::Y), f32::INFINITY)
            .unwrap();
        let expect = f(o.y) - f(b.y);
        assert!(
            (hit.t as f64 - expect).abs() / expect <= 2f64.powi(-23),
            "cap at scale {s}"
        );
        assert!((hit.normal - Vec3::Y).length() < 1e-6);
        let mut spans = Vec::new();
        cyl.spans(&Ray::new(o, -Vec3::Y), &mut spans);
        assert_eq!(spans.len(), 1);
        let exit = f(o.y) - f(a.y);
        assert!((spans[0].exit.t as f64 - exit).abs() / exit <= 2f64.powi(-23));
        assert!((spans[0].exit.normal + Vec3::Y).length() < 1e-6);
        // Across the side at mid height.
        let o = Vec3::new(-10.0 * sf, 2.5 * sf, sf + 0.2 * sf);
        let k = (f(0.5 * sf).powi(2) - (f(o.z) - f(sf)).powi(2)).sqrt();
        let x = f(sf) - f(o.x);
        check(&cyl, o, Vec3::X, &[x - k, x + k], s, "capped cylinder side");
        // Above the top cap: the infinite cylinder is crossed, the capped one is not.
        let o = Vec3::new(-10.0 * sf, 5.0 * sf, sf);
        assert!(cyl
            .intersect(&Ray::new(o, Vec3::X), f32::INFINITY)
            .is_none());

        // A cone frustum from radius 1 at a to 0.5 at b: at mid height radius 0.75.
        let cone = Quadric::capped_cone(a, sf, b, 0.5 * sf).unwrap();
        let o = Vec3::new(-10.0 * sf, 2.5 * sf, sf);
        // Radius at height y: ra + (rb - ra)(y - ya)/(yb - ya), from the f32 inputs.
        let k = f(sf) + (f(0.5 * sf) - f(sf)) * (f(o.y) - f(a.y)) / (f(b.y) - f(a.y));
        check(&cone, o, Vec3::X, &[x - k, x + k], s, "capped cone side");
    }
}

#[test]
fn general_quadric_from_coefficients_equals_the_named_one() {
    // 4x² + y² + 9z² - 36 = 0 is the ellipsoid with radii 3, 6, 2.
    let q = Quadric::new([4.0, 1.0, 9.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -36.0]).unwrap();
    let e = Quadric::ellipsoid(Vec3::ZERO, Vec3::new(3.0, 6.0, 2.0)).unwrap();
    for (o, d) in [
        (Vec3::new(-10.0, 0.5, 0.3), Vec3::X),
        (Vec3::new(0.3, 10.0, -0.2), Vec3::new(0.1, -1.0, 0.05)),
    ] {
        let (a, b) = (
            q.intersect(&Ray::new(o, d), f32::INFINITY).unwrap(),
            e.intersect(&Ray::new(o, d), f32::INFINITY).unwrap(),
        );
        assert!((a.t - b.t).abs() <= 1e-6 * a.t);
        assert!((a.normal - b.normal).length() < 1e-6);
    }
    // The coefficient order round-trips, cross terms included.
    let k = [1.0, 2.0, 3.0, 0.5, -0.25, 0.75, 1.0, -2.0, 0.5, -4.0];
    assert_eq!(QuadricForm::from_coefficients(k).coefficients(), k);
    // A rotated ellipsoid: transforming the coefficients equals rotating the ray back.
    let rot = Affine3A::from_rotation_y(0.7) * Affine3A::from_rotation_x(-0.4);
    let moved = Affine3A::from_translation(Vec3::new(1.0, -2.0, 0.5)) * rot;
    let qt = e.transformed(&moved).unwrap();
    let ray = Ray::new(Vec3::new(-9.0, 1.0, 2.0), Vec3::new(1.0, -0.3, -0.2));
    let inv = moved.inverse();
    let local = Ray::new(
        inv.transform_point3(ray.origin),
        inv.transform_vector3(ray.dir),
    );
    let (a, b) = (
        qt.intersect(&ray, f32::INFINITY).unwrap(),
        e.intersect(&local, f32::INFINITY).unwrap(),
    );
    assert!((a.t - b.t).abs() <= 1e-5 * a.t, "{} vs {}", a.t, b.t);
}

#[test]
fn rays_parallel_to_the_axis_and_outside_the_solid() {
    let cyl = Quadric::cylinder(1.0).unwrap();
    let mut spans = Vec::new();
    // Inside and parallel to the axis: inside for ever.
    cyl.spans(&Ray::new(Vec3::new(0.2, 0.0, 0.1), Vec3::Y), &mut spans);
    assert_eq!(spans.len(), 1);
    assert!(spans[0].enter.t == f32::NEG_INFINITY && spans[0].exit.t == f32::INFINITY);
    spans.clear();
    cyl.spans(&Ray::new(Vec3::new(2.0, 0.0, 0.0), Vec3::Y), &mut spans);
    assert!(spans.is_empty());
    // A hyperboloid of one sheet crossed through its waist: one span, two roots.
    let h = Quadric::hyperboloid_one_sheet(1.0, 1.0).unwrap();
    spans.clear();
    h.spans(&Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X), &mut spans);
    assert_eq!(spans.len(), 1);
    // Along the axis: inside all the way (the whole line).
    spans.clear();
    h.spans(&Ray::new(Vec3::new(0.0, -5.0, 0.0), Vec3::Y), &mut spans);
    assert_eq!(spans.len(), 1);
    assert!(spans[0].enter.t.is_infinite() && spans[0].exit.t.is_infinite());
    // Across the two-sheet hyperboloid along its axis: two half-infinite spans.
    let h2 = Quadric::hyperboloid_two_sheets(1.0, 1.0).unwrap();
    spans.clear();
    h2.spans(&Ray::new(Vec3::new(0.0, -5.0, 0.0), Vec3::Y), &mut spans);
    assert_eq!(spans.len(), 2);
    assert!((spans[0].exit.t - 4.0).abs() < 1e-6 && (spans[1].enter.t - 6.0).abs() < 1e-6);
}

#[test]
fn clipping_caps_the_solid_and_open_keeps_only_the_surface() {
    let clipped = Quadric::cylinder(1.0)
        .unwrap()
        .clipped_by_box(Vec3::splat(-2.0), Vec3::splat(2.0))
        .unwrap();
    let b = clipped.bounds();
    assert!(
        b.min.cmple(Vec3::new(-1.0, -2.0, -1.0)).all()
            && b.max.cmpge(Vec3::new(1.0, 2.0, 1.0)).all()
    );
    assert!(b.max.y <= 2.0 + 1e-5 && b.max.x <= 1.0 + 1e-5, "{b:?}");
    let down = Ray::new(Vec3::new(0.0, 5.0, 0.0), -Vec3::Y);
    let h = clipped.intersect(&down, f32::INFINITY).unwrap();
    assert!((h.t - 3.0).abs() < 1e-6 && h.normal == Vec3::Y && h.prim > 0);
    let open = clipped.clone().open();
    assert!(!open.is_solid());
    assert!(open.intersect(&down, f32::INFINITY).is_none());
    let across = Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X);
    assert!((open.intersect(&across, f32::INFINITY).unwrap().t - 4.0).abs() < 1e-6);
    // A plane clip: keep y ≤ 1 of a sphere-like ellipsoid.
    let e = Quadric::ellipsoid(Vec3::ZERO, Vec3::splat(2.0))
        .unwrap()
        .clipped_by_plane(Vec3::Y, 1.0)
        .unwrap();
    let h = e.intersect(&down, f32::INFINITY).unwrap();
    assert!((h.t - 4.0).abs() < 1e-6 && h.normal == Vec3::Y);
    assert_eq!(HalfSpace::new(DVec3::ZERO, 1.0), None);
}

#[test]
fn degenerate_quadrics_are_errors() {
    assert!(matches!(
        Quadric::new([0.0; 10]),
        Err(ShapeError::NotASurface)
    ));
    let mut k = [0.0; 10];
    k[0] = f64::NAN;
    assert!(matches!(Quadric::new(k), Err(ShapeError::NotFinite { .. })));
    assert!(Quadric::ellipsoid(Vec3::ZERO, Vec3::new(1.0, 0.0, 1.0)).is_err());
    assert!(Quadric::ellipsoid(Vec3::new(f32::NAN, 0.0, 0.0), Vec3::ONE).is_err());
    assert!(Quadric::cylinder(-1.0).is_err());
    assert!(Quadric::cone(f32::INFINITY).is_err());
    assert!(matches!(
        Quadric::capped_cylinder(Vec3::ONE, Vec3::ONE, 1.0),
        Err(ShapeError::Coincident { .. })
    ));
    assert!(Quadric::capped_cylinder(Vec3::ZERO, Vec3::Y, 0.0).is_err());
    assert!(Quadric::capped_cone(Vec3::ZERO, 0.0, Vec3::Y, 0.0).is_err());
    assert!(Quadric::capped_cone(Vec3::ZERO, -1.0, Vec3::Y, 1.0).is_err());
    assert!(Quadric::capped_cone(Vec3::ZERO, 0.0, Vec3::Y, 1.0).is_ok());
    let c = Quadric::cylinder(1.0).unwrap();
    assert!(c.clone().clipped_by_plane(Vec3::ZERO, 1.0).is_err());
    assert!(c.clone().clipped_by_box(Vec3::ONE, Vec3::ZERO).is_err());
    assert!(c
        .transformed(&Affine3A::from_scale(Vec3::new(1.0, 0.0, 1.0)))
        .is_err());
    // Messages name the problem.
    let msg = Quadric::cylinder(0.0).unwrap_err().to_string();
    assert!(msg.contains("cylinder radius"), "{msg}");
}
