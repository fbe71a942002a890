//! The leaf kernel of meshes (SSE or, for two packets, AVX2 filter + scalar
//! watertight test) against the scalar watertight test run triangle by triangle:
//! the same triangle, `t` and barycentrics bit for bit, on random rays and on the
//! hard cases: rays through shared edges and vertices, and rays parallel to faces.

use glam::Vec3;
use irradia_core::{Ray, Rng};
use irradia_geometry::packet::watertight4::{intersect_leaf, occluded_leaf};
use irradia_geometry::packet::Triangle4;
use irradia_geometry::triangle::{TriangleHit, TriangleRay};

fn rand_vec(rng: &mut Rng, lo: f32, hi: f32) -> Vec3 {
    Vec3::new(
        lo + (hi - lo) * rng.next_f32(),
        lo + (hi - lo) * rng.next_f32(),
        lo + (hi - lo) * rng.next_f32(),
    )
}

fn pack(tris: &[[Vec3; 3]]) -> Vec<Triangle4> {
    tris.chunks(4).map(Triangle4::new).collect()
}

fn scalar(tris: &[[Vec3; 3]], ray: &TriangleRay, t_max: f32) -> Option<(usize, TriangleHit)> {
    let mut best = None;
    let mut t_max = t_max;
    for (i, [a, b, c]) in tris.iter().enumerate() {
        if let Some(h) = ray.intersect(*a, *b, *c, t_max) {
            t_max = h.t;
            best = Some((i, h));
        }
    }
    best
}

fn check(tris: &[[Vec3; 3]], ray: &Ray, t_max: f32) -> bool {
    let packets = pack(tris);
    let tray = TriangleRay::new(ray);
    let want = scalar(tris, &tray, t_max);
    let got = intersect_leaf(&packets, tris.len(), &tray, t_max);
    match (want, got) {
        (None, None) => {}
        (Some((i, a)), Some((j, b))) => {
            assert_eq!(i, j, "triangle, ray {ray:?}");
            for (x, y) in [(a.t, b.t), (a.b0, b.b0), (a.b1, b.b1), (a.b2, b.b2)] {
                assert_eq!(x.to_bits(), y.to_bits(), "ray {ray:?}");
            }
        }
        _ => panic!("scalar {want:?} leaf {got:?} ray {ray:?}"),
    }
    assert_eq!(
        occluded_leaf(&packets, tris.len(), &tray, t_max),
        want.is_some()
    );
    want.is_some()
}

/// A fan of up to eight triangles around a shared centre on a random plane: every
/// pair of neighbours shares an edge, all share the centre.
fn fan(rng: &mut Rng, n: usize) -> ([[Vec3; 3]; 8], Vec3, Vec3, Vec3) {
    let c = rand_vec(rng, -1.0, 1.0);
    let u = rand_vec(rng, -1.0, 1.0).normalize_or(Vec3::X);
    let v = u.any_orthonormal_vector();
    let rim = |k: usize| {
        let a = std::f32::consts::TAU * k as f32 / n as f32;
        c + u * a.cos() + v * a.sin()
    };
    let mut tris = [[Vec3::ZERO; 3]; 8];
    for (k, t) in tris.iter_mut().enumerate().take(n) {
        *t = [c, rim(k), rim(k + 1)];
    }
    (tris, c, u, v)
}

#[test]
fn leaf_kernel_equals_the_scalar_test() {
    let mut rng = Rng::new(14, 5);
    let mut hits = 0;
    for _ in 0..20_000 {
        let n = 1 + (rng.next_f32() * 8.0) as usize % 8;
        let case = rng.next_f32();
        if case < 0.4 {
            // Random triangles, random rays.
            let tris: Vec<[Vec3; 3]> = (0..n)
                .map(|_| {
                    let a = rand_vec(&mut rng, -1.0, 1.0);
                    [
                        a,
                        a + rand_vec(&mut rng, -0.7, 0.7),
                        a + rand_vec(&mut rng, -0.7, 0.7),
                    ]
                })
                .collect();
            let o = rand_vec(&mut rng, -2.0, 2.0);
            let d = rand_vec(&mut rng, -1.0, 1.0);
            let t_max = if rng.next_f32() < 0.5 {
                f32::INFINITY
            } else {
                3.0 * rng.next_f32()
            };
            hits += check(&tris, &Ray::new(o, d), t_max) as usize;
        } else {
            // A fan (shared edges and a shared vertex), hit through its centre, through
            // a rim vertex or an edge's midpoint, or by a ray in its plane.
            let m = n.max(3);
            let (tris, c, u, v) = fan(&mut rng, m);
            let tris = &tris[..m];
            let k = (rng.next_f32() * m as f32) as usize % m;
            let target = match (rng.next_f32() * 3.0) as u32 {
                0 => c,
                1 => tris[k][1],
                _ => 0.5 * (c + tris[k][1]),
            };
            let n_plane = u.cross(v);
            let d = if case < 0.55 {
                // In the plane (parallel to every face), from outside the fan.
                (u * rng.next_f32() + v * (rng.next_f32() - 0.5)).normalize_or(u)
            } else {
                (rand_vec(&mut rng, -0.5, 0.5) + n_plane).normalize()
            };
            let o = target - d * (0.5 + 2.0 * rng.next_f32());
            hits += check(tris, &Ray::new(o, d), f32::INFINITY) as usize;
        }
    }
    assert!(hits > 5_000, "too few hits to test anything: {hits}");
}
