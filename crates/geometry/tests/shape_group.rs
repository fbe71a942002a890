//! A shape group placed by an instance answers every ray as its members placed
//! directly with the composed transforms do: the same hit (t, point, normals, uv), the
//! member's leaf numbered after the members before it, the same tangent frame
//! (`uv_derivatives`), and the same shadow-ray answer. Its facets are the members'
//! facets, placed.

use glam::{Affine3A, Quat, Vec3};
use irradia_core::Ray;
use irradia_geometry::shapes::{Rectangle, Sphere};
use irradia_geometry::{Csg, CsgOperand, Instance, Shape, ShapeGroup};
use std::sync::Arc;

fn members() -> Vec<(Arc<dyn Shape>, Affine3A, u32)> {
    let sphere: Arc<dyn Shape> = Arc::new(Sphere::new(Vec3::ZERO, 0.7));
    let rect: Arc<dyn Shape> = Arc::new(Rectangle::flipped(false));
    let csg = Csg::difference(vec![
        CsgOperand::shape(
            Arc::new(Sphere::new(Vec3::ZERO, 0.5)) as Arc<dyn Shape>,
            Affine3A::IDENTITY,
        ),
        CsgOperand::shape(
            Arc::new(Sphere::new(Vec3::new(0.3, 0.0, 0.3), 0.3)) as Arc<dyn Shape>,
            Affine3A::IDENTITY,
        ),
    ])
    .unwrap();
    let leaves = csg.leaf_count();
    vec![
        (
            sphere,
            Affine3A::from_translation(Vec3::new(-1.5, 0.0, 0.0)),
            1,
        ),
        (
            rect,
            Affine3A::from_scale_rotation_translation(
                Vec3::new(2.0, 1.0, 1.0),
                Quat::from_rotation_x(-1.2),
                Vec3::new(0.0, -0.8, 0.0),
            ),
            1,
        ),
        (
            Arc::new(csg),
            Affine3A::from_translation(Vec3::new(1.4, 0.2, 0.1)),
            leaves,
        ),
    ]
}

#[test]
fn a_placed_group_answers_as_its_members_placed_directly() {
    let place = Affine3A::from_scale_rotation_translation(
        Vec3::new(1.3, 0.8, 1.1),
        Quat::from_rotation_y(0.7) * Quat::from_rotation_z(0.2),
        Vec3::new(0.5, 1.0, -2.0),
    );
    let group = ShapeGroup::new(
        members()
            .into_iter()
            .map(|(s, t, n)| (Instance::new(s, t), n))
            .collect(),
    );
    assert_eq!(group.leaf_count(), 4);
    let placed = Instance::new(Arc::new(group), place);
    let direct: Vec<Instance> = members()
        .into_iter()
        .map(|(s, t, _)| Instance::new(s, place * t))
        .collect();
    let first_leaf = [0u32, 1, 2];

    let mut hits = [0usize; 3];
    let eye = Vec3::new(0.3, 2.5, 6.0);
    for i in 0..60 {
        for j in 0..40 {
            let target = Vec3::new(-3.5 + i as f32 * 0.12, -1.5 + j as f32 * 0.12, -2.0);
            let ray = Ray::new(eye, (target - eye).normalize());
            let want = direct
                .iter()
                .enumerate()
                .filter_map(|(m, inst)| inst.intersect(&ray, f32::INFINITY).map(|h| (m, h)))
                .min_by(|a, b| a.1.t.total_cmp(&b.1.t));
            let got = placed.intersect(&ray, f32::INFINITY);
            assert_eq!(
                placed.occluded(&ray, f32::INFINITY),
                want.is_some(),
                "ray {i},{j}: shadow answer"
            );
            let Some((m, w)) = want else {
                assert!(
                    got.is_none(),
                    "ray {i},{j}: a hit where the members have none"
                );
                continue;
            };
            let g = got.unwrap_or_else(|| panic!("ray {i},{j}: member {m} missed"));
            hits[m] += 1;
            assert!(
                (g.t - w.t).abs() <= 1e-4 * w.t,
                "ray {i},{j}: t {} vs {}",
                g.t,
                w.t
            );
            assert!(g.normal.dot(w.normal) > 0.9999, "ray {i},{j}: normal");
            assert!(
                (g.uv - w.uv).length() < 1e-4,
                "ray {i},{j}: uv {} vs {}",
                g.uv,
                w.uv
            );
            assert_eq!(g.leaf, first_leaf[m] + w.leaf, "ray {i},{j}: leaf");
            let (gu, gv) = placed.uv_derivatives(&g);
            let (wu, wv) = direct[m].uv_derivatives(&w);
            for (a, b) in [(gu, wu), (gv, wv)] {
                assert!(
                    (a - b).length() <= 1e-3 * (1.0 + b.length()),
                    "ray {i},{j}: member {m} frame {a} vs {b}"
                );
            }
        }
    }
    assert!(
        hits.iter().all(|&n| n > 30),
        "every member is hit: {hits:?}"
    );
}

#[test]
fn a_group_is_faceted_as_its_members_placed() {
    let group = ShapeGroup::new(
        members()
            .into_iter()
            .take(2)
            .map(|(s, t, n)| (Instance::new(s, t), n))
            .collect(),
    );
    let f = group.facets(16).expect("spheres and rectangles facet");
    let mut want = 0;
    for (s, _, _) in members().into_iter().take(2) {
        want += s.facets(16).unwrap().faces.len();
    }
    assert_eq!(f.faces.len(), want);
    let bounds = group.bounds();
    assert!(f.vertices.iter().all(|&v| {
        let e = 1e-4 * (1.0 + v.length());
        v.cmpge(bounds.min - e).all() && v.cmple(bounds.max + e).all()
    }));
}
