//! The BVH against brute force: same nearest hit, and any-hit agrees with closest-hit.

use irradia_core::{Aabb, Ray, Rng, Vec3};
use irradia_geometry::bvh::Bvh;
use irradia_geometry::triangle::TriangleRay;
use irradia_geometry::{Shape, TriangleMesh};

fn rand_vec(rng: &mut Rng, lo: f32, hi: f32) -> Vec3 {
    Vec3::new(
        lo + (hi - lo) * rng.next_f32(),
        lo + (hi - lo) * rng.next_f32(),
        lo + (hi - lo) * rng.next_f32(),
    )
}

fn rand_dir(rng: &mut Rng) -> Vec3 {
    loop {
        let v = rand_vec(rng, -1.0, 1.0);
        if v.length_squared() > 1e-4 && v.length_squared() <= 1.0 {
            return v;
        }
    }
}

/// `n` random triangles: small ones spread through the box, with a few long thin ones.
fn random_triangles(rng: &mut Rng, n: usize) -> Vec<[Vec3; 3]> {
    (0..n)
        .map(|i| {
            let c = rand_vec(rng, -1.0, 1.0);
            let size = if i % 17 == 0 { 0.8 } else { 0.08 };
            [
                c + rand_vec(rng, -size, size),
                c + rand_vec(rng, -size, size),
                c + rand_vec(rng, -size, size),
            ]
        })
        .collect()
}

fn brute_force(tris: &[[Vec3; 3]], ray: &Ray, t_max: f32) -> Option<(usize, f32)> {
    let tr = TriangleRay::new(ray);
    let mut best = None;
    let mut t_max = t_max;
    for (i, t) in tris.iter().enumerate() {
        if let Some(h) = tr.intersect(t[0], t[1], t[2], t_max) {
            t_max = h.t;
            best = Some((i, h.t));
        }
    }
    best
}

#[test]
fn closest_hit_equals_brute_force_on_random_scenes() {
    let mut rng = Rng::new(7, 1);
    for (scene, &n) in [1usize, 2, 5, 9, 40, 300, 3000].iter().enumerate() {
        let tris = random_triangles(&mut rng, n);
        let boxes: Vec<Aabb> = tris
            .iter()
            .map(|t| Aabb::from_points(t.iter().copied()))
            .collect();
        let bvh = Bvh::build(&boxes);
        let stats = bvh.stats();
        assert_eq!(stats.primitives, n);
        assert!(stats.max_leaf_size <= 8);
        let mut hits = 0;
        for k in 0..2000 {
            let origin = rand_vec(&mut rng, -1.5, 1.5);
            // Some rays point at a triangle so that hits are frequent.
            let dir = if k % 2 == 0 {
                let t = &tris[rng.below(n as u32) as usize];
                (t[0] + t[1] + t[2]) / 3.0 - origin
            } else {
                rand_dir(&mut rng)
            };
            let ray = Ray::new(origin, dir);
            let t_max = if k % 5 == 0 { 0.7 } else { f32::INFINITY };
            let expect = brute_force(&tris, &ray, t_max);
            let tr = TriangleRay::new(&ray);
            let mut got_index = None;
            let got_t = bvh.closest_hit(&ray, t_max, |slot, t_max| {
                let t = &tris[bvh.order()[slot as usize] as usize];
                let h = tr.intersect(t[0], t[1], t[2], t_max)?;
                got_index = Some(bvh.order()[slot as usize] as usize);
                Some(h.t)
            });
            match expect {
                None => assert!(
                    got_t.is_none(),
                    "scene {scene} ray {k}: BVH hit, brute force missed"
                ),
                Some((i, t)) => {
                    hits += 1;
                    assert_eq!(got_t, Some(t), "scene {scene} ray {k}");
                    // Ties in t may pick either triangle; the t must agree exactly.
                    let gi = got_index.unwrap();
                    assert!(
                        gi == i || {
                            let g = &tris[gi];
                            tr.intersect(g[0], g[1], g[2], f32::INFINITY).map(|h| h.t) == Some(t)
                        }
                    );
                }
            }
            let any = bvh.any_hit(&ray, t_max, |slot, t_max| {
                let t = &tris[bvh.order()[slot as usize] as usize];
                tr.intersect(t[0], t[1], t[2], t_max).is_some()
            });
            assert_eq!(
                any,
                expect.is_some(),
                "scene {scene} ray {k}: any-hit disagrees"
            );
        }
        assert!(
            hits > 200,
            "scene {scene}: too few hits ({hits}) to test anything"
        );
    }
}

#[test]
fn mesh_hit_equals_brute_force_and_reports_the_triangle() {
    let mut rng = Rng::new(11, 3);
    let tris = random_triangles(&mut rng, 2000);
    let positions: Vec<Vec3> = tris.iter().flatten().copied().collect();
    let indices: Vec<[u32; 3]> = (0..tris.len() as u32)
        .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    let mesh = TriangleMesh::new(positions, indices, None, None).unwrap();
    for _ in 0..3000 {
        let ray = Ray::new(rand_vec(&mut rng, -1.5, 1.5), rand_dir(&mut rng));
        let expect = brute_force(&tris, &ray, f32::INFINITY);
        let got = mesh.intersect(&ray, f32::INFINITY);
        assert_eq!(got.map(|h| h.t), expect.map(|e| e.1));
        if let (Some(h), Some((i, _))) = (got, expect) {
            let t = &tris[h.prim as usize];
            assert!(
                h.prim as usize == i || {
                    TriangleRay::new(&ray)
                        .intersect(t[0], t[1], t[2], f32::INFINITY)
                        .map(|x| x.t)
                        == Some(h.t)
                }
            );
            // The point lies on the ray and in the triangle's plane.
            assert!((h.point - ray.at(h.t)).length() < 1e-4);
            assert!((h.point - t[0]).dot(h.normal).abs() < 1e-4);
        }
        assert_eq!(mesh.occluded(&ray, f32::INFINITY), expect.is_some());
    }
}

#[test]
fn boxes_that_are_empty_or_infinite_are_left_out() {
    let boxes = vec![
        Aabb::new(Vec3::ZERO, Vec3::ONE),
        Aabb::EMPTY,
        Aabb::INFINITE,
        Aabb::new(Vec3::splat(2.0), Vec3::splat(3.0)),
    ];
    let bvh = Bvh::build(&boxes);
    let mut order = bvh.order().to_vec();
    order.sort();
    assert_eq!(order, vec![0, 3]);
    assert_eq!(bvh.bounds(), Aabb::new(Vec3::ZERO, Vec3::splat(3.0)));
    // An empty hierarchy is hit by nothing.
    let empty = Bvh::build(&[]);
    let ray = Ray::new(Vec3::ZERO, Vec3::X);
    assert!(empty
        .closest_hit(&ray, f32::INFINITY, |_, _| Some(1.0))
        .is_none());
    assert!(!empty.any_hit(&ray, f32::INFINITY, |_, _| true));
}

#[test]
fn many_coincident_boxes_build_a_bounded_tree() {
    // Identical centroids defeat binning: the builder falls back to median splits.
    let boxes = vec![Aabb::new(Vec3::ZERO, Vec3::ONE); 10_000];
    let bvh = Bvh::build(&boxes);
    let s = bvh.stats();
    assert_eq!(s.primitives, 10_000);
    assert!(s.max_leaf_size <= 8 && s.max_depth < 40, "{s:?}");
    let ray = Ray::new(Vec3::new(0.5, 0.5, -1.0), Vec3::Z);
    let mut visited = 0;
    bvh.closest_hit(&ray, f32::INFINITY, |_, _| {
        visited += 1;
        None
    });
    assert_eq!(visited, 10_000);
}

/// An unbounded test shape: the plane `y = height`, hit from either side.
#[derive(Debug)]
struct Floor {
    height: f32,
}

impl Shape for Floor {
    fn kind(&self) -> &'static str {
        "floor"
    }
    fn bounds(&self) -> Aabb {
        Aabb::INFINITE
    }
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<irradia_geometry::Hit> {
        let t = (self.height - ray.origin.y) / ray.dir.y;
        (t > 0.0 && t < t_max)
            .then(|| irradia_geometry::Hit::new(t, ray.at(t), Vec3::Y, irradia_core::Vec2::ZERO))
    }
    fn is_solid(&self) -> bool {
        false
    }
    fn spans(&self, _: &Ray, _: &mut Vec<irradia_geometry::Span>) {}
}

#[test]
fn accel_equals_brute_force_over_instances() {
    use irradia_core::Affine3A;
    use irradia_geometry::shapes::Sphere;
    use irradia_geometry::{Accel, Instance};
    use std::sync::Arc;
    let mut rng = Rng::new(21, 4);
    let mut instances = vec![Instance::untransformed(Arc::new(Floor { height: -3.0 }))];
    let tris = random_triangles(&mut rng, 50);
    let positions: Vec<Vec3> = tris.iter().flatten().copied().collect();
    let indices: Vec<[u32; 3]> = (0..50u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
    let mesh: Arc<dyn Shape> = Arc::new(TriangleMesh::new(positions, indices, None, None).unwrap());
    for i in 0..300 {
        let at = rand_vec(&mut rng, -2.5, 2.5);
        let inst = if i % 10 == 0 {
            // Meshes placed with rotation and scale: the second level.
            Instance::new(
                mesh.clone(),
                Affine3A::from_scale_rotation_translation(
                    Vec3::splat(0.3 + rng.next_f32()),
                    glam::Quat::from_axis_angle(
                        Vec3::new(1.0, 2.0, 0.5).normalize(),
                        rng.next_f32() * 6.0,
                    ),
                    at,
                ),
            )
        } else {
            Instance::new(
                Arc::new(Sphere::new(Vec3::ZERO, 0.05 + 0.2 * rng.next_f32())),
                Affine3A::from_translation(at),
            )
        };
        instances.push(inst);
    }
    let brute: Vec<Instance> = instances.clone();
    let accel = Accel::build(instances);
    let mut hits = 0;
    for k in 0..3000 {
        let ray = Ray::new(rand_vec(&mut rng, -3.0, 3.0), rand_dir(&mut rng));
        let t_max = if k % 4 == 0 { 2.0 } else { f32::INFINITY };
        let mut expect: Option<(usize, f32)> = None;
        let mut tm = t_max;
        for (i, inst) in brute.iter().enumerate() {
            if let Some(h) = inst.intersect(&ray, tm) {
                tm = h.t;
                expect = Some((i, h.t));
            }
        }
        let got = accel.intersect(&ray, t_max);
        assert_eq!(got.map(|h| h.hit.t), expect.map(|e| e.1), "ray {k}");
        if let (Some(g), Some(e)) = (got, expect) {
            hits += 1;
            assert!(
                g.instance as usize == e.0
                    || brute[g.instance as usize]
                        .intersect(&ray, f32::INFINITY)
                        .map(|h| h.t)
                        == Some(e.1)
            );
        }
        assert_eq!(accel.occluded(&ray, t_max), expect.is_some(), "ray {k}");
    }
    assert!(hits > 1000);
}

#[test]
fn building_from_a_box_function_equals_building_from_a_box_list() {
    let mut rng = Rng::new(11, 3);
    let mut boxes: Vec<Aabb> = random_triangles(&mut rng, 5000)
        .iter()
        .map(|t| Aabb::from_points(*t))
        .collect();
    // Boxes left out: empty and not finite.
    boxes[17] = Aabb::EMPTY;
    boxes[4000] = Aabb::new(Vec3::ZERO, Vec3::splat(f32::INFINITY));
    for block in [1, 8] {
        let a = Bvh::build_blocked(&boxes, block);
        let b = Bvh::build_blocked_by(boxes.len(), |i| boxes[i], block);
        assert_eq!(a.order(), b.order());
        assert!(!a.order().contains(&17) && !a.order().contains(&4000));
        assert_eq!(a.nodes().len(), b.nodes().len());
        // Subtrees built in parallel number their nodes in whatever order the threads
        // run, so the trees are compared by walking both from the root.
        let mut stack = vec![(0u32, 0u32)];
        while let Some((i, j)) = stack.pop() {
            let (x, y) = (&a.nodes()[i as usize], &b.nodes()[j as usize]);
            assert_eq!(x.bounds, y.bounds);
            for k in 0..8 {
                let (cx, cy) = (x.child_ref(k), y.child_ref(k));
                if cx.is_leaf() || cx.is_empty() {
                    assert_eq!(cx, cy);
                } else {
                    assert!(!cy.is_leaf() && !cy.is_empty());
                    stack.push((cx.index, cy.index));
                }
            }
        }
        assert_eq!(a.stats(), b.stats());
    }
}

#[test]
fn leaf_primitives_are_the_slots_of_each_leaf() {
    let mut rng = Rng::new(11, 4);
    let boxes: Vec<Aabb> = random_triangles(&mut rng, 3000)
        .iter()
        .map(|t| Aabb::from_points(*t))
        .collect();
    let bvh = Bvh::build_blocked(&boxes, 8);
    let mut by_slots = Vec::new();
    let mut a = bvh.clone();
    a.map_leaves(|start, count| {
        by_slots.push(bvh.order()[start as usize..(start + count) as usize].to_vec());
        by_slots.len() as u32 - 1
    });
    let mut by_prims = Vec::new();
    let mut b = bvh.clone();
    b.map_leaf_primitives(|prims| {
        by_prims.push(prims.to_vec());
        by_prims.len() as u32 - 1
    });
    assert_eq!(by_slots, by_prims);
    assert_eq!(by_prims.iter().map(Vec::len).sum::<usize>(), boxes.len());
    for (x, y) in a.nodes().iter().zip(b.nodes()) {
        assert_eq!((x.child, x.count), (y.child, y.count));
    }
}
