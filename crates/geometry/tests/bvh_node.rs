//! The 8-wide node's box test: the AVX2 path, the SSE path and the scalar reference
//! agree bit for bit (mask and entry distances) on random boxes and rays, including
//! rays parallel to box faces and rays starting on a face, and the test is
//! conservative (a ray through a box's interior always enters it).

use glam::Vec3;
use irradia_core::{Aabb, Rng};
use irradia_geometry::bvh::node::{NodeRay, WideNode, WIDTH};
use irradia_geometry::bvh::ChildRef;

fn rand_vec(rng: &mut Rng, lo: f32, hi: f32) -> Vec3 {
    Vec3::new(
        lo + (hi - lo) * rng.next_f32(),
        lo + (hi - lo) * rng.next_f32(),
        lo + (hi - lo) * rng.next_f32(),
    )
}

/// A node with `n` random boxes (some flat, some sharing faces on the grid).
fn random_node(rng: &mut Rng, n: usize) -> WideNode {
    let mut node = WideNode::EMPTY;
    for i in 0..n {
        let a = rand_vec(rng, -2.0, 2.0);
        let mut b = a + rand_vec(rng, 0.0, 1.5);
        if rng.next_f32() < 0.2 {
            b.y = a.y; // flat box
        }
        let snap = |v: Vec3| (v * 4.0).round() / 4.0;
        let (a, b) = if rng.next_f32() < 0.3 {
            (snap(a), snap(b))
        } else {
            (a, b)
        };
        node.set(
            i,
            Aabb::new(a.min(b), a.max(b)),
            ChildRef {
                index: i as u32,
                count: 1,
            },
        );
    }
    node
}

/// Random rays, a share with zero direction components (parallel to faces) and
/// origins on the 0.25 grid (in face planes).
fn random_ray(rng: &mut Rng) -> (Vec3, Vec3) {
    let mut o = rand_vec(rng, -3.0, 3.0);
    if rng.next_f32() < 0.3 {
        o = (o * 4.0).round() / 4.0;
    }
    let mut d = rand_vec(rng, -1.0, 1.0);
    for k in 0..3 {
        if rng.next_f32() < 0.2 {
            d[k] = 0.0;
        }
    }
    if d == Vec3::ZERO {
        d = Vec3::X;
    }
    (o, d)
}

#[test]
fn simd_box_tests_equal_the_scalar_reference() {
    let mut rng = Rng::new(14, 2);
    let avx2 = irradia_geometry::packet::has_avx2();
    for _ in 0..4000 {
        let n = 1 + (rng.next_f32() * WIDTH as f32) as usize % WIDTH;
        let node = random_node(&mut rng, n);
        for _ in 0..8 {
            let (o, d) = random_ray(&mut rng);
            let t_max = if rng.next_f32() < 0.5 {
                f32::INFINITY
            } else {
                6.0 * rng.next_f32()
            };
            let mut ray = NodeRay::new(o, d);
            let (m_ref, t_ref) = node.intersect_scalar(&ray, t_max);
            ray.avx2 = false;
            let (m_sse, t_sse) = node.intersect(&ray, t_max);
            assert_eq!(m_sse, m_ref, "sse mask, o {o:?} d {d:?}");
            for i in 0..WIDTH {
                if m_ref >> i & 1 == 1 {
                    assert_eq!(t_sse[i].to_bits(), t_ref[i].to_bits(), "sse t, lane {i}");
                }
            }
            if avx2 {
                ray.avx2 = true;
                let (m_avx, t_avx) = node.intersect(&ray, t_max);
                assert_eq!(m_avx, m_ref, "avx2 mask, o {o:?} d {d:?}");
                for i in 0..WIDTH {
                    if m_ref >> i & 1 == 1 {
                        assert_eq!(t_avx[i].to_bits(), t_ref[i].to_bits(), "avx2 t, lane {i}");
                    }
                }
            }
        }
    }
}

#[test]
fn rays_through_a_box_always_enter_it() {
    let mut rng = Rng::new(14, 3);
    for _ in 0..4000 {
        let node = random_node(&mut rng, WIDTH);
        let i = (rng.next_f32() * WIDTH as f32) as usize % WIDTH;
        let b = node.child_bounds(i);
        let e = b.max - b.min;
        if (e.cmpeq(Vec3::ZERO).bitmask()).count_ones() > 1 {
            continue; // a segment or a point: a rounded ray origin passes it by
        }
        // A point well inside the box (on its face for flat boxes) and a ray through
        // it from outside, possibly parallel to two axes.
        let p = b.min + e * rand_vec(&mut rng, 0.1, 0.9);
        let (_, mut d) = random_ray(&mut rng);
        if rng.next_f32() < 0.3 {
            d = [Vec3::X, Vec3::NEG_Y, Vec3::Z][i % 3];
        }
        let o = p - d * (1.0 + 3.0 * rng.next_f32());
        let ray = NodeRay::new(o, d);
        let (mask, _) = node.intersect(&ray, f32::INFINITY);
        assert!(mask >> i & 1 == 1, "box {b:?} missed by o {o:?} d {d:?}");
    }
}
