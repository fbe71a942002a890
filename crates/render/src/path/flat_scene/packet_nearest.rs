//! Coherent rays of the flat scene traced together: up to eight rays that share a
//! direction octant (a pixel's camera rays) walk the hierarchy as one packet
//! (geometry's `bvh::packet_traverse`; Wald, Slusallek, Benthin, Wagner, "Interactive
//! Rendering with Coherent Ray Tracing", EG 2001), each testing the leaves' triangle
//! packets alone.
//!
//! Each answer must be the single ray's ([`FlatScene::nearest_triangles`]) bit for bit.
//! A triangle's hit (t, barycentrics) is computed by the same test whatever the walk,
//! so only the choice among equally near hits depends on the order of the leaves, which
//! the packet does not share with the single ray. As geometry's `mesh/stream.rs` does,
//! each ray records besides its nearest hit the nearest *other* hit it met (its leaf
//! tests run against a bound a few ulps beyond its nearest hit): when that lies within
//! [`TIE_ULPS`] of the nearest, the ray is left unanswered and the caller traces it
//! alone. Otherwise the nearest hit is separated from every other by more than the
//! rounding of the packet test's range checks (`t < t_max |den|`, then `t < t_max`),
//! so any visit order accepts it and rejects the rest.

use super::{Baked, FlatScene};
use irradia_core::Ray;
use irradia_geometry::bvh::packet_traverse::{Lanes8, PacketRay, PACKET};
use irradia_geometry::mesh::TIE_ULPS;
use irradia_geometry::packet::{has_avx2, PacketHit, LANES};

/// How far beyond its nearest hit a packet ray keeps testing (in `f32::EPSILON`), so
/// that every hit within [`TIE_ULPS`] of the nearest is met.
const LOOSE_ULPS: f32 = 32.0;

/// A ray's nearest hit so far (packet index, hit) and the nearest other hit's `t`.
type Nearest = (Option<(usize, PacketHit)>, f32);

impl FlatScene {
    /// The nearest baked triangle along each of `rays` (1 to [`PACKET`] of them,
    /// unbounded), into `out`, as [`Self::nearest_triangles`] finds it, the rays walked
    /// as one packet. Returns the mask of the rays answered (bit `k` for `rays[k]`):
    /// none when the rays do not share a direction octant, the scene has no hierarchy
    /// or the CPU lacks AVX2; not those whose nearest hit has another within
    /// [`TIE_ULPS`]. The caller traces the others alone.
    pub(crate) fn nearest_triangles_packet(
        &self,
        rays: &[Ray],
        out: &mut [Option<(u32, PacketHit)>],
    ) -> u32 {
        assert!(rays.len() <= PACKET && out.len() == rays.len());
        let Some(baked) = &self.baked else {
            return 0;
        };
        let (Some(bvh), Some(packet)) = (&baked.bvh, PacketRay::new(rays)) else {
            return 0;
        };
        let mut near: [Nearest; PACKET] = [(None, f32::INFINITY); PACKET];
        let mut bound = Lanes8([f32::INFINITY; PACKET]);
        if baked.first > 0 && has_avx2() {
            // The packets every ray tests first (a large scene's large triangles).
            for (k, ray) in rays.iter().enumerate() {
                // SAFETY: the CPU has AVX2 and FMA (just checked).
                bound.0[k] = unsafe { hits_avx2(baked, 0, baked.first, ray, &mut near[k]) };
            }
        }
        let walked = bvh.packet_leaves(
            &packet,
            packet.lanes(),
            &mut bound,
            |leaf| baked.prefetch_leaf(leaf),
            |leaf, lanes, bound| {
                let mut m = lanes;
                while m != 0 {
                    let k = m.trailing_zeros() as usize;
                    m &= m - 1;
                    let (start, n) = (leaf.index as usize, (leaf.count as usize).div_ceil(LANES));
                    // SAFETY: the packet walk runs only where the CPU has AVX2 and FMA
                    // (`has_avx2`).
                    bound.0[k] = unsafe { hits_avx2(baked, start, n, &rays[k], &mut near[k]) };
                }
            },
        );
        if !walked {
            return 0;
        }
        let tie = 1.0 + TIE_ULPS * f32::EPSILON;
        let mut answered = 0;
        for (k, ((best, second), o)) in near.iter().zip(out.iter_mut()).enumerate() {
            if best.is_some_and(|(_, h)| *second <= h.t * tie) {
                continue;
            }
            *o = best.map(|(index, h)| (baked.lanes[index][h.lane], h));
            answered |= 1 << k;
        }
        answered
    }
}

/// Tests `ray` against the `n` packets from `start` (a leaf's, or the first packets)
/// with the single ray's test and arithmetic (`triangle8`'s AVX2 test, then
/// `nearest_lane`'s division), every hit within the ray's current bound: the nearer
/// becomes `near`'s nearest, the others lower its second. Returns the ray's new bound,
/// [`LOOSE_ULPS`] beyond its nearest.
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn hits_avx2(baked: &Baked, start: usize, n: usize, ray: &Ray, near: &mut Nearest) -> f32 {
    let loose = 1.0 + LOOSE_ULPS * f32::EPSILON;
    let (best, second) = near;
    let mut bound = best.map_or(f32::INFINITY, |(_, h)| h.t * loose);
    let mut v = [[0f32; LANES]; 4];
    for (i, p) in baked.packets[start..start + n].iter().enumerate() {
        let mut mask = p.test_avx2(ray.origin, ray.dir, bound, &mut v);
        while mask != 0 {
            let lane = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            let inv = 1.0 / v[3][lane];
            let t = v[2][lane] * inv;
            match best {
                Some((_, h)) if t >= h.t => *second = second.min(t),
                _ => {
                    if let Some((_, h)) = best {
                        *second = second.min(h.t);
                    }
                    let hit = PacketHit {
                        lane,
                        t,
                        b1: v[0][lane] * inv,
                        b2: v[1][lane] * inv,
                    };
                    *best = Some((start + i, hit));
                    bound = t * loose;
                }
            }
        }
    }
    bound
}

/// Not reached: the packet walk needs AVX2 (`packet_leaves` does nothing without it).
#[cfg(not(target_arch = "x86_64"))]
unsafe fn hits_avx2(_: &Baked, _: usize, _: usize, _: &Ray, _: &mut Nearest) -> f32 {
    unreachable!("the packet walk needs AVX2")
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Affine3A, Vec3};
    use irradia_geometry::mesh::TriangleMesh;
    use irradia_geometry::packet::has_avx2;
    use irradia_geometry::Instance;
    use irradia_scene::{Object, Scene};
    use std::sync::Arc;

    /// Corners `i0..=i1` by `j0..=j1` of an `n` by `n` grid of squares over
    /// `[-1, 1]²` in the plane `z = 0`, two triangles a square (a sub-grid's corners
    /// are the same floats as the whole grid's).
    fn grid(n: u32, (i0, i1): (u32, u32), (j0, j1): (u32, u32)) -> TriangleMesh {
        let at = |k: u32| -1.0 + 2.0 * k as f32 / n as f32;
        let mut positions = Vec::new();
        for j in j0..=j1 {
            for i in i0..=i1 {
                positions.push(Vec3::new(at(i), at(j), 0.0));
            }
        }
        let w = i1 - i0 + 1;
        let mut indices = Vec::new();
        for j in 0..j1 - j0 {
            for i in 0..i1 - i0 {
                let (a, b, c, d) = (
                    j * w + i,
                    j * w + i + 1,
                    (j + 1) * w + i + 1,
                    (j + 1) * w + i,
                );
                indices.push([a, b, c]);
                indices.push([a, c, d]);
            }
        }
        TriangleMesh::new(positions, indices, None, None).unwrap()
    }

    /// Packets of eight camera-like rays (one eye, targets close together) at a grid
    /// of 1152 triangles, a quarter of which a second mesh covers again (every hit
    /// there ties exactly), aimed at random points and at the grid's corners (where
    /// the triangles that share an edge or a corner tie): every answered ray is the
    /// single ray's answer bit for bit, ties are left to the single ray, and most
    /// rays are answered.
    #[test]
    fn packet_answers_are_the_single_rays() {
        let cornell = irradia_scene::builtin::load("cornell").unwrap();
        let n = 24;
        let meshes = [grid(n, (0, n), (0, n)), grid(n, (n / 2, n), (n / 2, n))];
        let object = |name: &str| Object {
            name: name.into(),
            material: 0,
            leaf_materials: vec![],
        };
        let scene = Scene::new(
            cornell.camera,
            cornell.settings.clone(),
            cornell.materials.clone(),
            vec![],
            vec![object("grid"), object("quarter")],
            meshes
                .into_iter()
                .map(|m| Instance::new(Arc::new(m), Affine3A::IDENTITY))
                .collect(),
        );
        let flat = FlatScene::new(&scene);
        assert!(flat.bvh_stats().is_some(), "a hierarchy over the triangles");
        let eye = Vec3::new(0.1, -0.2, 3.0);
        let corner = |i: u32, j: u32| {
            let at = |k: u32| -1.0 + 2.0 * k as f32 / n as f32;
            Vec3::new(at(i), at(j), 0.0)
        };
        let mut rng = irradia_core::Rng::new(7, 11);
        let (mut answered, mut left, mut rays_n) = (0u32, 0u32, 0u32);
        let mut left_in_quarter = 0u32;
        for round in 0..600 {
            let centre = Vec3::new(2.2 * rng.next_f32() - 1.1, 2.2 * rng.next_f32() - 1.1, 0.0);
            let count = 1 + round % PACKET;
            let mut rays = [Ray::new(eye, Vec3::NEG_Z); PACKET];
            for r in rays[..count].iter_mut() {
                let target = if round % 3 == 0 {
                    // A corner of the grid near the centre: an edge every triangle
                    // around it shares.
                    let k = |x: f32| ((x + 1.0) * n as f32 / 2.0).round().clamp(0.0, n as f32);
                    let (i, j) = (k(centre.x) as u32, k(centre.y) as u32);
                    corner((i + rng.next_f32().round() as u32).min(n), j)
                } else {
                    centre + 0.02 * Vec3::new(rng.next_f32(), rng.next_f32(), 0.0)
                };
                *r = Ray::new(eye, (target - eye).normalize());
            }
            let mut packet = [None; PACKET];
            let mask = flat.nearest_triangles_packet(&rays[..count], &mut packet[..count]);
            let mut single = [None; PACKET];
            flat.nearest_triangles(&rays[..count], &mut single[..count]);
            for k in 0..count {
                rays_n += 1;
                if mask >> k & 1 == 0 {
                    left += 1;
                    let p = rays[k].origin + rays[k].dir * (-rays[k].origin.z / rays[k].dir.z);
                    if p.x > 0.0 && p.y > 0.0 && p.x < 1.0 && p.y < 1.0 {
                        left_in_quarter += 1;
                    }
                    continue;
                }
                answered += 1;
                let bits = |h: Option<(u32, PacketHit)>| {
                    h.map(|(t, h)| (t, h.lane, h.t.to_bits(), h.b1.to_bits(), h.b2.to_bits()))
                };
                assert_eq!(bits(packet[k]), bits(single[k]), "round {round} ray {k}");
            }
        }
        if !has_avx2() {
            assert_eq!(answered, 0, "no packet walk without AVX2");
            return;
        }
        assert!(answered * 2 > rays_n, "{answered} of {rays_n} answered");
        assert!(
            left_in_quarter > 0,
            "{left} left, none on the doubled quarter"
        );
    }
}
