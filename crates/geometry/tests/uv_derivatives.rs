//! The `dp/du`, `dp/dv` every parameterised shape reports (`Instance::uv_derivatives`
//! of a hit) agree with its own uv: for
//! two hits a small step apart, `p₂ − p₁ ≈ dp/du (u₂ − u₁) + dp/dv (v₂ − v₁)` to first
//! order, and the derivatives lie in the tangent plane. Checked for the sphere, disk,
//! rectangle, cube, tube, polygon and a uv-mapped mesh, with and without an instance
//! transform (which must carry them as vectors).

use glam::{Affine3A, Vec2, Vec3};
use irradia_core::Ray;
use irradia_geometry::shapes::{Cube, Disk, Polygon, Rectangle, Sphere, Tube};
use irradia_geometry::{Instance, Shape, TriangleMesh};
use std::sync::Arc;

/// Rays from `eye` through points around `target` (a small square of side `h`), and
/// the first-order check on each pair of neighbouring hits.
fn check(name: &str, inst: &Instance, eye: Vec3, target: Vec3, h: f32) {
    let hit = |o: Vec3| {
        let d = (target + o - eye).normalize();
        inst.intersect(&Ray::new(eye, d), f32::INFINITY)
            .unwrap_or_else(|| panic!("{name}: no hit near {target}"))
    };
    let a = hit(Vec3::ZERO);
    let (dpdu, dpdv) = inst.uv_derivatives(&a);
    assert!(
        dpdu.length() > 0.0 && dpdv.length() > 0.0,
        "{name}: no derivatives"
    );
    for (what, d) in [("dp/du", dpdu), ("dp/dv", dpdv)] {
        assert!(
            d.normalize().dot(a.normal).abs() < 1e-3,
            "{name}: {what} {d} is not tangent to the normal {}",
            a.normal
        );
    }
    let side = if (eye - target).normalize().dot(Vec3::X).abs() < 0.9 {
        Vec3::X
    } else {
        Vec3::Y
    };
    let up = (eye - target).normalize().cross(side).normalize();
    for o in [side * h, up * h, (side + up) * h] {
        let b = hit(o);
        let du: Vec2 = b.uv - a.uv;
        if du.x.abs() > 0.5 || du.y.abs() > 0.5 {
            continue; // across a seam of the parameterisation
        }
        let predicted = dpdu * du.x + dpdv * du.y;
        let actual = b.point - a.point;
        let err = (predicted - actual).length();
        assert!(
            err <= 0.05 * actual.length() + 1e-6,
            "{name}: step {actual} but dp/du Δu + dp/dv Δv = {predicted} (uv {} -> {})",
            a.uv,
            b.uv
        );
    }
}

fn placed(shape: Arc<dyn Shape>) -> [Instance; 2] {
    let m = Affine3A::from_scale_rotation_translation(
        Vec3::new(1.5, 0.7, 1.1),
        glam::Quat::from_rotation_y(0.4) * glam::Quat::from_rotation_x(-0.3),
        Vec3::new(0.2, -0.1, 0.3),
    );
    [
        Instance::untransformed(shape.clone()),
        Instance::new(shape, m),
    ]
}

#[test]
fn every_parameterised_shape_reports_consistent_uv_derivatives() {
    let eye = Vec3::new(0.7, 0.9, 6.0);
    let mesh = TriangleMesh::new(
        vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.2),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, -0.2),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
        None,
        Some(vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(3.0, 0.5),
            Vec2::new(2.5, 2.0),
            Vec2::new(-0.5, 1.0),
        ]),
    )
    .unwrap();
    let shapes: Vec<(&str, Arc<dyn Shape>, Vec3)> = vec![
        (
            "sphere",
            Arc::new(Sphere::new(Vec3::ZERO, 1.0)),
            Vec3::new(0.3, 0.4, 0.8),
        ),
        (
            "disk",
            Arc::new(Disk::new(Vec3::ZERO, Vec3::new(0.1, 0.2, 1.0).normalize(), 1.0).unwrap()),
            Vec3::new(0.4, 0.2, 0.0),
        ),
        (
            "rectangle",
            Arc::new(Rectangle::new()),
            Vec3::new(0.3, -0.2, 0.0),
        ),
        ("cube", Arc::new(Cube::new(false)), Vec3::new(0.2, 0.3, 1.0)),
        (
            "tube",
            Arc::new(Tube::new(Vec3::new(0.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.2), 0.8).unwrap()),
            Vec3::new(0.0, 0.1, 0.8),
        ),
        (
            "polygon",
            Arc::new(
                Polygon::new(vec![
                    Vec3::new(-2.0, -1.0, 0.0),
                    Vec3::new(2.0, -1.3, 0.0),
                    Vec3::new(1.5, 1.0, 0.0),
                    Vec3::new(-1.0, 1.2, 0.0),
                ])
                .unwrap(),
            ),
            Vec3::new(0.2, 0.1, 0.0),
        ),
        ("uv mesh", Arc::new(mesh), Vec3::new(0.3, 0.2, 0.05)),
    ];
    for (name, shape, target) in shapes {
        let [plain, moved] = placed(shape);
        check(name, &plain, eye, target, 2e-3);
        let t = *moved.to_world();
        check(
            &format!("{name} (transformed)"),
            &moved,
            eye,
            t.transform_point3(target),
            2e-3,
        );
    }
}
