//! `TriangleMesh::intersect_triangles` and `intersect_cast_hits` (coherent groups of
//! eight rays traced as packets) answer every ray bit for bit as the single-ray
//! queries do: the same triangle, t and barycentrics, the same misses, with and
//! without a finite `t_max`, on coherent (camera) and incoherent ray sets.

use irradia_core::{Ray, Rng, Vec3};
use irradia_geometry::bvh::packet_traverse::{PacketRay, PACKET};
use irradia_geometry::generators::gyroid_mesh;
use irradia_geometry::triangle::TriangleHit;
use irradia_geometry::TriangleMesh;

fn gyroid() -> TriangleMesh {
    let m = gyroid_mesh(40);
    TriangleMesh::new(m.positions, m.indices, None, None).unwrap()
}

/// A pinhole camera's rays, rows top to bottom, as the triangles bench makes them.
fn camera(eye: Vec3, target: Vec3, w: usize, h: usize, fov_deg: f32) -> Vec<Ray> {
    let forward = (target - eye).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward);
    let tan = (fov_deg.to_radians() * 0.5).tan();
    let aspect = w as f32 / h as f32;
    let mut rays = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            let sx = (2.0 * (x as f32 + 0.5) / w as f32 - 1.0) * tan * aspect;
            let sy = (1.0 - 2.0 * (y as f32 + 0.5) / h as f32) * tan;
            rays.push(Ray::new(eye, (forward + sx * right + sy * up).normalize()));
        }
    }
    rays
}

fn incoherent(n: usize, seed: u64) -> Vec<Ray> {
    let mut rng = Rng::new(seed, 5);
    let mut u = || 2.0 * rng.next_f32() - 1.0;
    (0..n)
        .map(|_| Ray::new(Vec3::new(u(), u(), u()), Vec3::new(u(), u(), u())))
        .collect()
}

fn bits(h: &Option<(u32, TriangleHit)>) -> Option<(u32, [u32; 4])> {
    h.map(|(id, h)| (id, [h.t, h.b0, h.b1, h.b2].map(f32::to_bits)))
}

/// Compares both paths ray by ray; returns (hits, groups traced as packets).
fn check(mesh: &TriangleMesh, rays: &[Ray], t_max: f32) -> (usize, usize) {
    let mut batch = vec![None; rays.len()];
    mesh.intersect_triangles(rays, t_max, &mut batch);
    let mut casts = vec![None; rays.len()];
    mesh.intersect_cast_hits(rays, t_max, &mut casts);
    let mut hits = 0;
    for (i, r) in rays.iter().enumerate() {
        let single = mesh.intersect_triangle(r, t_max);
        assert_eq!(
            bits(&batch[i]),
            bits(&single),
            "ray {i} {r:?} t_max {t_max}"
        );
        assert_eq!(casts[i], mesh.intersect_cast_hit(r, t_max), "cast ray {i}");
        hits += single.is_some() as usize;
    }
    let packets = rays
        .chunks(PACKET)
        .filter(|g| g.len() > 1 && PacketRay::new(g).is_some())
        .count();
    (hits, packets)
}

#[test]
fn coherent_rays_agree_with_single_rays_hit_by_hit() {
    let mesh = gyroid();
    let views = [
        (Vec3::new(1.5, 1.1, 1.9), Vec3::ZERO),
        (Vec3::new(-2.0, 0.3, 0.7), Vec3::new(0.1, 0.0, -0.2)),
        // From inside the gyroid's box, rays in every octant.
        (Vec3::new(0.05, -0.1, 0.2), Vec3::new(1.0, 0.2, -0.3)),
    ];
    for (eye, target) in views {
        let rays = camera(eye, target, 96, 64, 60.0);
        let (hits, packets) = check(&mesh, &rays, f32::INFINITY);
        assert!(hits > rays.len() / 10, "the view must see the gyroid");
        assert!(
            packets > rays.len() / PACKET / 2,
            "most groups must be packets"
        );
        // A finite t_max cuts some hits: the bound is honoured lane by lane.
        let mut ts: Vec<f32> = {
            let mut out = vec![None; rays.len()];
            mesh.intersect_triangles(&rays, f32::INFINITY, &mut out);
            out.iter().flatten().map(|(_, h)| h.t).collect()
        };
        ts.sort_by(f32::total_cmp);
        let median = ts[ts.len() / 2];
        let (cut, _) = check(&mesh, &rays, median);
        assert!(cut < hits && cut > 0);
        // Exactly a hit's t: that hit (t < t_max fails) is left out by both paths.
        check(&mesh, &rays, ts[0]);
    }
}

#[test]
fn incoherent_and_mixed_rays_agree_with_single_rays() {
    let mesh = gyroid();
    let rays = incoherent(4000, 9);
    check(&mesh, &rays, f32::INFINITY);
    check(&mesh, &rays, 0.5);
    // Coherent groups with some rays turned around (not a packet) and odd lengths.
    let mut mixed = camera(Vec3::new(1.5, 1.1, 1.9), Vec3::ZERO, 37, 29, 45.0);
    for (i, r) in mixed.iter_mut().enumerate() {
        if i % 53 == 0 {
            r.dir = -r.dir;
        }
    }
    for len in [1, 2, 7, 9, 100, mixed.len()] {
        check(&mesh, &mixed[..len], f32::INFINITY);
    }
    // Rays along the axes (zero direction components: infinite reciprocals).
    let axis: Vec<Ray> = (0..64)
        .map(|i| {
            let o = Vec3::new(
                -1.5,
                (i % 8) as f32 * 0.11 - 0.4,
                (i / 8) as f32 * 0.11 - 0.4,
            );
            Ray::new(o, Vec3::X)
        })
        .collect();
    check(&mesh, &axis, f32::INFINITY);
}

#[test]
fn packets_need_a_common_octant() {
    let a = Ray::new(Vec3::ZERO, Vec3::new(1.0, 0.5, 0.2));
    let b = Ray::new(Vec3::ONE, Vec3::new(0.3, 0.1, 0.9));
    assert!(PacketRay::new(&[a, b]).is_some());
    assert!(PacketRay::new(&[a, Ray::new(Vec3::ZERO, Vec3::new(1.0, -0.5, 0.2))]).is_none());
    assert!(PacketRay::new(&[]).is_none());
    assert!(PacketRay::new(&[a; PACKET + 1]).is_none());
    assert_eq!(PacketRay::new(&[a, b, a]).unwrap().lanes(), 0b111);
}
