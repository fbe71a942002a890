//! The flat scene's triangles and their hierarchy ([`Baked`]): a small scene's
//! triangles tested one packet after another; a larger scene's in an 8-wide SAH tree
//! with packet leaves, except its large triangles, which every ray tests first
//! ([`LARGE_TRIANGLE_AREA`]). Nearest hits and shadow rays, one ray at a time or a
//! lane's worth walked in turns.

use super::{prefetch_bytes, FlatTriangle};
use glam::Vec3;
use irradia_core::{Aabb, Ray};
use irradia_geometry::bvh::{Bvh, ChildRef};
#[cfg(target_arch = "x86_64")]
use irradia_geometry::packet::bounds8::{any_culled_avx2, nearest_culled_avx2};
#[cfg(target_arch = "x86_64")]
use irradia_geometry::packet::has_avx2;
use irradia_geometry::packet::lanes::W;
use irradia_geometry::packet::triangle8 as packet;
use irradia_geometry::packet::{PacketBounds, PacketHit, TrianglePacket, LANES};

/// Up to this many triangles are tested one packet after another without a
/// hierarchy: for the Cornell box (36 triangles) nine packet tests cost less than
/// descending a tree whose big wall triangles overlap every box.
pub(super) const BRUTE_FORCE_TRIANGLES: usize = 64;

/// In a larger scene, a triangle whose box has at least this fraction of the scene box's
/// surface area is tested by every ray before the hierarchy, not put in it (at most
/// [`BRUTE_FORCE_TRIANGLES`] of them, the largest first). By the surface area
/// heuristic (MacDonald and Booth 1990) a ray meets such a box about as often as the
/// scene's, so a tree gains nothing by culling it, and its box swells every node above
/// it: the walls of a room around a mesh (a sixth to a third of the room's area each)
/// made the bunny's walks descend through the walls' leaves. Their nearest hit, found
/// first, also bounds the walk of the mesh's tree.
pub(super) const LARGE_TRIANGLE_AREA: f32 = 1.0 / 16.0;

/// The triangles and their hierarchy.
#[derive(Debug)]
pub(super) struct Baked {
    /// The packets every ray tests before the hierarchy: `packets[..first]` (all of a
    /// small scene's; a large scene's large triangles, [`LARGE_TRIANGLE_AREA`]).
    pub(super) first: usize,
    /// For at most eight first packets: their boxes, to skip the packets a ray passes
    /// by.
    pub(super) bounds: Option<PacketBounds>,
    /// `None` for small scenes (every packet is a first packet); otherwise its leaves
    /// index `packets` after the first ones: a leaf of n triangles owns ceil(n / 4)
    /// packets.
    pub(super) bvh: Option<Bvh>,
    pub(super) packets: Vec<TrianglePacket>,
    /// The triangle of each packet lane.
    pub(super) lanes: Vec<[u32; LANES]>,
    pub(super) triangles: Vec<FlatTriangle>,
    /// Whether several rays' walks take turns ([`Self::intersect_many`]): only where
    /// the packets outgrow [`INTERLEAVE_BYTES`].
    pub(super) interleave: bool,
}

/// The size of the packets beyond which several rays walk the BVH in turns. Taking
/// turns hides cache misses but costs bookkeeping, so it pays only where the walks
/// miss the last-level cache: measured in the wide path kernel (CPU, paired runs,
/// 16 spp, load 6), the 2.25M-triangle gyroid (~80 MB of packets) in the Cornell box
/// 1.12x faster with it, the 69k-triangle bunny (~2.5 MB) 0.85x (again with 16 lanes
/// in flight, 16 spp, load 7: 1.07x the CPU time of the render without).
const INTERLEAVE_BYTES: usize = 16 << 20;

/// The packets of triangles `ids` tested one after another: grouped as the SAH
/// builder's leaves, so each packet is compact and its box can cull it; with their
/// boxes when there are at most eight packets. The groups are of triangle indices;
/// `boxes` are every triangle's (empty for a degenerate one).
fn first_groups(ids: &[u32], boxes: &[Aabb]) -> (Vec<Vec<u32>>, Option<PacketBounds>) {
    let own: Vec<Aabb> = ids.iter().map(|&t| boxes[t as usize]).collect();
    let mut tree = Bvh::build_blocked(&own, LANES);
    let order = tree.order().to_vec();
    let mut groups: Vec<Vec<u32>> = Vec::new();
    tree.map_leaves(|start, count| {
        for chunk in order[start as usize..(start + count) as usize].chunks(LANES) {
            groups.push(chunk.iter().map(|&k| ids[k as usize]).collect());
        }
        0
    });
    if groups.len() <= LANES {
        let packet_boxes: Vec<Aabb> = groups
            .iter()
            .map(|g| {
                g.iter()
                    .fold(Aabb::EMPTY, |b, &t| b.union(boxes[t as usize]))
            })
            .collect();
        (groups, Some(PacketBounds::new(&packet_boxes)))
    } else {
        let all: Vec<u32> = ids
            .iter()
            .copied()
            .filter(|&t| !boxes[t as usize].is_empty())
            .collect();
        (all.chunks(LANES).map(<[u32]>::to_vec).collect(), None)
    }
}

/// The triangles of a large scene ([`BRUTE_FORCE_TRIANGLES`]) that every ray tests
/// before the tree, in index order: those whose boxes are large against the scene's
/// ([`LARGE_TRIANGLE_AREA`]), the largest first, at most [`BRUTE_FORCE_TRIANGLES`]
/// of them; then, when they fit in that number too, the emitters' (`emitter[t]`), where
/// every shadow ray ends: in the tree their leaves would be entered by every shadow
/// ray, so a room's light would stretch the box the tree's walks are culled by.
fn first_triangles(boxes: &[Aabb], emitter: &[bool]) -> Vec<u32> {
    let scene = boxes.iter().fold(Aabb::EMPTY, |b, &t| b.union(t));
    let area = |b: &Aabb| {
        let e = b.max - b.min;
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    };
    let least = area(&scene) * LARGE_TRIANGLE_AREA;
    let mut first: Vec<u32> = (0..boxes.len() as u32)
        .filter(|&t| !boxes[t as usize].is_empty() && area(&boxes[t as usize]) >= least)
        .collect();
    first.sort_by(|&a, &b| area(&boxes[b as usize]).total_cmp(&area(&boxes[a as usize])));
    first.truncate(BRUTE_FORCE_TRIANGLES);
    let lights: Vec<u32> = (0..boxes.len() as u32)
        .filter(|&t| emitter[t as usize] && !boxes[t as usize].is_empty())
        .filter(|t| !first.contains(t))
        .collect();
    if first.len() + lights.len() <= BRUTE_FORCE_TRIANGLES {
        first.extend(lights);
    }
    first.sort_unstable();
    first
}

impl Baked {
    /// The packets and tree of `triangles`; `emissive[m]` says whether material `m`
    /// emits (its triangles are tested first where they fit: [`first_triangles`]).
    pub(super) fn build(triangles: Vec<FlatTriangle>, emissive: &[bool]) -> Self {
        let mut packets = Vec::new();
        let mut lanes = Vec::new();
        let mut pack = |chunk: &[u32]| {
            let corners: Vec<[Vec3; 3]> = chunk
                .iter()
                .map(|&t| triangles[t as usize].corners)
                .collect();
            packets.push(TrianglePacket::new(&corners));
            let mut ids = [u32::MAX; LANES];
            ids[..chunk.len()].copy_from_slice(chunk);
            lanes.push(ids);
        };
        let boxes: Vec<Aabb> = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.corners;
                if (b - a).cross(c - a) == Vec3::ZERO {
                    Aabb::EMPTY // degenerate: never hit
                } else {
                    Aabb::new(a.min(b).min(c), a.max(b).max(c))
                }
            })
            .collect();
        let small = triangles.len() <= BRUTE_FORCE_TRIANGLES;
        let first_ids: Vec<u32> = if small {
            (0..triangles.len() as u32).collect()
        } else {
            let emitter: Vec<bool> = triangles
                .iter()
                .map(|t| emissive.get(t.material as usize).copied().unwrap_or(false))
                .collect();
            first_triangles(&boxes, &emitter)
        };
        let (groups, bounds) = if first_ids.is_empty() {
            (Vec::new(), None)
        } else {
            first_groups(&first_ids, &boxes)
        };
        groups.iter().for_each(|g| pack(g));
        let first = groups.len();
        let bvh = (!small).then(|| {
            let mut in_first = vec![false; triangles.len()];
            first_ids.iter().for_each(|&t| in_first[t as usize] = true);
            let rest: Vec<u32> = (0..triangles.len() as u32)
                .filter(|&t| !in_first[t as usize])
                .collect();
            let rest_boxes: Vec<Aabb> = rest.iter().map(|&t| boxes[t as usize]).collect();
            let mut bvh = Bvh::build_blocked(&rest_boxes, LANES);
            let order: Vec<u32> = bvh.order().iter().map(|&k| rest[k as usize]).collect();
            let mut next = first as u32;
            bvh.map_leaves(|start, count| {
                let at = next;
                for chunk in order[start as usize..(start + count) as usize].chunks(LANES) {
                    pack(chunk);
                    next += 1;
                }
                at
            });
            bvh
        });
        let interleave = bvh.is_some()
            && packets.len() * std::mem::size_of::<TrianglePacket>() > INTERLEAVE_BYTES;
        Self {
            first,
            bounds,
            bvh,
            packets,
            lanes,
            triangles,
            interleave,
        }
    }

    /// The triangles of `packets`, in the order the packets hold them.
    pub(super) fn triangles_in(&self, packets: std::ops::Range<usize>) -> Vec<u32> {
        self.lanes[packets]
            .iter()
            .flatten()
            .copied()
            .filter(|&t| t != u32::MAX)
            .collect()
    }

    #[inline(always)]
    pub(super) fn leaf_packets(&self, leaf: ChildRef) -> &[TrianglePacket] {
        let start = leaf.index as usize;
        &self.packets[start..start + (leaf.count as usize).div_ceil(LANES)]
    }

    /// The nearest hit among the first packets with `0 < t < t_max`: (packet, hit).
    #[inline(always)]
    fn nearest_first(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<(usize, PacketHit)> {
        let first = &self.packets[..self.first];
        match &self.bounds {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: the CPU supports AVX2 and FMA.
            Some(b) if has_avx2() => unsafe { nearest_culled_avx2(first, b, o, d, t_max) },
            _ => packet::nearest(first, o, d, t_max),
        }
    }

    /// Whether a first packet's triangle is hit with `0 < t < t_max`.
    #[inline(always)]
    fn any_first(&self, o: Vec3, d: Vec3, t_max: f32) -> bool {
        let first = &self.packets[..self.first];
        match &self.bounds {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: the CPU supports AVX2 and FMA.
            Some(b) if has_avx2() => unsafe { any_culled_avx2(first, b, o, d, t_max) },
            _ => packet::any(first, o, d, t_max),
        }
    }

    /// Starts loading a leaf's packets when its box is entered (large meshes: most
    /// leaves are not in cache).
    #[inline(always)]
    pub(super) fn prefetch_leaf(&self, leaf: ChildRef) {
        if let Some(first) = self.packets.get(leaf.index as usize) {
            prefetch_bytes(first, std::mem::size_of::<TrianglePacket>());
        }
    }

    /// The nearest triangle with `0 < t < t_max`: (triangle, hit). The first packets
    /// are tested first; the hierarchy's walk is bounded by their nearest hit, so of
    /// equally near hits a first packet's wins.
    #[inline]
    pub(super) fn intersect(&self, ray: &Ray, t_max: f32) -> Option<(u32, PacketHit)> {
        let first = self
            .nearest_first(ray.origin, ray.dir, t_max)
            .map(|(index, h)| (self.lanes[index][h.lane], h));
        let bound = first.map_or(t_max, |(_, h)| h.t);
        self.tree_nearest(ray, bound).or(first)
    }

    /// The nearest triangle of the hierarchy (none in a small scene) with
    /// `0 < t < t_max`.
    #[inline]
    fn tree_nearest(&self, ray: &Ray, t_max: f32) -> Option<(u32, PacketHit)> {
        let bvh = self.bvh.as_ref()?;
        let (o, d) = (ray.origin, ray.dir);
        let mut best = None;
        bvh.closest_hit_leaves_prefetch(
            ray,
            t_max,
            |leaf| self.prefetch_leaf(leaf),
            |leaf, t| {
                let (k, h) = packet::nearest(self.leaf_packets(leaf), o, d, t)?;
                best = Some((leaf.index as usize + k, h));
                Some(h.t)
            },
        )?;
        let (index, h): (usize, PacketHit) = best?;
        Some((self.lanes[index][h.lane], h))
    }

    /// [`Self::tree_nearest`] of each of `rays` (at most [`W`]; ray `i` up to
    /// `t_max[i]`), into `out`: with a large BVH ([`INTERLEAVE_BYTES`]) the rays are
    /// walked in turns (geometry's `bvh/interleaved.rs`), so one ray's cache misses
    /// overlap the others' work; each walk, and so each answer, is the single ray's bit
    /// for bit.
    pub(super) fn tree_nearest_many(
        &self,
        rays: &[Ray],
        t_max: &[f32],
        out: &mut [Option<(u32, PacketHit)>],
    ) {
        let Some(bvh) = self.bvh.as_ref().filter(|_| self.interleave) else {
            for ((r, &t), o) in rays.iter().zip(t_max).zip(out.iter_mut()) {
                *o = self.tree_nearest(r, t);
            }
            return;
        };
        let mut best = [None; W];
        let best = &mut best[..rays.len()];
        bvh.closest_hit_leaves_interleaved(
            rays,
            t_max,
            |leaf| self.prefetch_leaf(leaf),
            |i, leaf, t| {
                let r = &rays[i];
                let (k, h) = packet::nearest(self.leaf_packets(leaf), r.origin, r.dir, t)?;
                best[i] = Some((leaf.index as usize + k, h));
                Some(h.t)
            },
        );
        for (o, b) in out.iter_mut().zip(best.iter()) {
            *o = b.map(|(index, h): (usize, PacketHit)| (self.lanes[index][h.lane], h));
        }
    }

    /// [`Self::intersect`] (unbounded) of each of `rays` (at most [`W`]), into `out`,
    /// the hierarchy walked as in [`Self::tree_nearest_many`].
    pub(super) fn intersect_many(&self, rays: &[Ray], out: &mut [Option<(u32, PacketHit)>]) {
        let mut bound = [f32::INFINITY; W];
        let bound = &mut bound[..rays.len()];
        let mut first = [None; W];
        for ((r, b), f) in rays.iter().zip(bound.iter_mut()).zip(first.iter_mut()) {
            *f = self.nearest_first(r.origin, r.dir, f32::INFINITY);
            *b = f.map_or(f32::INFINITY, |(_, h)| h.t);
        }
        self.tree_nearest_many(rays, bound, out);
        for (o, f) in out.iter_mut().zip(first) {
            if o.is_none() {
                *o = f.map(|(index, h)| (self.lanes[index][h.lane], h));
            }
        }
    }

    /// Whether a triangle of the hierarchy (none in a small scene) is hit with
    /// `0 < t < t_max`.
    #[inline]
    fn tree_any(&self, ray: &Ray, t_max: f32) -> bool {
        let (o, d) = (ray.origin, ray.dir);
        self.bvh.as_ref().is_some_and(|bvh| {
            bvh.any_hit_leaves(ray, t_max, |leaf, t| {
                packet::any(self.leaf_packets(leaf), o, d, t)
            })
        })
    }

    /// [`Self::tree_any`] of each of `rays` (ray `i` up to `t_max[i]`), into `out`,
    /// walked in turns as in [`Self::tree_nearest_many`]; the same answers.
    pub(super) fn tree_any_many(&self, rays: &[Ray], t_max: &[f32], out: &mut [bool]) {
        let Some(bvh) = self.bvh.as_ref().filter(|_| self.interleave) else {
            for ((r, &t), o) in rays.iter().zip(t_max).zip(out.iter_mut()) {
                *o = self.tree_any(r, t);
            }
            return;
        };
        bvh.any_hit_leaves_interleaved(rays, t_max, out, |i, leaf, t| {
            packet::any(self.leaf_packets(leaf), rays[i].origin, rays[i].dir, t)
        });
    }

    /// [`Self::occluded`] of each of `rays` (at most [`W`]; ray `i` up to `t_max[i]`),
    /// into `out`: the rays the first packets leave open walk the hierarchy as in
    /// [`Self::tree_any_many`].
    pub(super) fn occluded_many(&self, rays: &[Ray], t_max: &[f32], out: &mut [bool]) {
        let (mut open, mut open_rays, mut open_t) =
            ([0usize; W], [Ray::new(Vec3::ZERO, Vec3::X); W], [0f32; W]);
        let mut n = 0;
        for (i, (r, &t)) in rays.iter().zip(t_max).enumerate() {
            out[i] = self.any_first(r.origin, r.dir, t);
            if !out[i] {
                (open[n], open_rays[n], open_t[n]) = (i, *r, t);
                n += 1;
            }
        }
        let mut hit = [false; W];
        self.tree_any_many(&open_rays[..n], &open_t[..n], &mut hit[..n]);
        for (&i, &h) in open[..n].iter().zip(&hit[..n]) {
            out[i] = h;
        }
    }

    #[inline]
    pub(super) fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.any_first(ray.origin, ray.dir, t_max) || self.tree_any(ray, t_max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use irradia_core::Rng;

    fn triangle(corners: [Vec3; 3]) -> FlatTriangle {
        FlatTriangle {
            corners,
            normal: Vec3::Y,
            instance: 0,
            material: 0,
            face: 0,
            smooth: None,
        }
    }

    /// The nearest hit and the shadow answer of one ray by testing every triangle
    /// alone with the same packet test (no hierarchy, no first packets).
    fn brute(tris: &[FlatTriangle], ray: &Ray, t_max: f32) -> (Option<(u32, f32)>, bool) {
        let mut best: Option<(u32, f32)> = None;
        for (i, t) in tris.iter().enumerate() {
            let p = [TrianglePacket::new(&[t.corners])];
            if let Some((_, h)) = packet::nearest(&p, ray.origin, ray.dir, f32::INFINITY) {
                if best.is_none_or(|(_, b)| h.t < b) {
                    best = Some((i as u32, h.t));
                }
            }
        }
        (best, best.is_some_and(|(_, t)| t < t_max))
    }

    /// A room of six walls (two large triangles each) around 600 small triangles: the
    /// walls are tested first and the small triangles are in the tree; every ray's
    /// nearest hit and shadow answer, one at a time and walked in turns, are those of
    /// testing every triangle alone.
    #[test]
    fn large_triangles_go_first_and_every_answer_is_exact() {
        let mut rng = Rng::new(3, 8);
        let mut tris = Vec::new();
        let c = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        for axis in 0..3 {
            for side in [-2.0f32, 2.0] {
                let p = |u: f32, v: f32| {
                    let mut q = [u, v, side];
                    q.rotate_right(axis);
                    c(q[0], q[1], q[2])
                };
                tris.push(triangle([p(-2.0, -2.0), p(2.0, -2.0), p(2.0, 2.0)]));
                tris.push(triangle([p(-2.0, -2.0), p(2.0, 2.0), p(-2.0, 2.0)]));
            }
        }
        let mut v = |s: f32| rng.next_centered_vec3() * s;
        for _ in 0..600 {
            let at = v(1.5);
            tris.push(triangle([at + v(0.25), at + v(0.25), at + v(0.25)]));
        }
        // Material 1 emits: the light's two triangles go first too.
        let light = [c(-0.2, 1.9, -0.2), c(0.2, 1.9, -0.2), c(0.2, 1.9, 0.2)];
        tris.push(FlatTriangle {
            material: 1,
            ..triangle(light)
        });
        let mut baked = Baked::build(tris.clone(), &[false, true]);
        assert!(baked.bvh.is_some(), "a tree over the small triangles");
        let mut first = baked.triangles_in(0..baked.first);
        first.sort_unstable();
        let mut walls_and_light: Vec<u32> = (0..12).collect();
        walls_and_light.push(tris.len() as u32 - 1);
        assert_eq!(first, walls_and_light, "the walls and the light go first");
        let mut rng = Rng::new(4, 1);
        let (mut walls, mut small) = (0, 0);
        for interleave in [false, true] {
            baked.interleave = interleave;
            for _ in 0..200 {
                let rays: Vec<Ray> = (0..W)
                    .map(|_| Ray::new(rng.next_centered_vec3() * 1.9, rng.next_centered_vec3()))
                    .collect();
                let bounds: Vec<f32> = (0..W).map(|_| 3.0 * rng.next_f32()).collect();
                let mut many = [None; W];
                baked.intersect_many(&rays, &mut many);
                let mut blocked = [false; W];
                baked.occluded_many(&rays, &bounds, &mut blocked);
                for (k, ray) in rays.iter().enumerate() {
                    let (want, want_blocked) = brute(&tris, ray, bounds[k]);
                    let got = baked.intersect(ray, f32::INFINITY).map(|(t, h)| (t, h.t));
                    assert_eq!(got, want, "{ray:?}");
                    assert_eq!(many[k].map(|(t, h)| (t, h.t)), want, "{ray:?} in turns");
                    assert_eq!(baked.occluded(ray, bounds[k]), want_blocked, "{ray:?}");
                    assert_eq!(blocked[k], want_blocked, "{ray:?} in turns");
                    match want {
                        Some((t, _)) if walls_and_light.contains(&t) => walls += 1,
                        Some(_) => small += 1,
                        None => {}
                    }
                }
            }
        }
        assert!(
            walls > 1000 && small > 1000,
            "{walls} wall hits, {small} small"
        );
    }
}
