//! Shaft culling for the links' shadow rays (Haines and Wallace 1994, "Shaft culling
//! for efficient ray-cast radiosity"; Teller and Hanrahan 1993 classify node pairs the
//! same way): a link whose two nodes have no possible occluder between them is wholly
//! visible, and its shadow rays are not cast.
//!
//! The shaft is the convex hull of the two nodes. A patch cannot block any of a link's
//! shadow rays when a plane separates it from that hull: an axis plane (the boxes are
//! disjoint), its own plane (both nodes lie on one side), or the plane of either node
//! (the patch lies behind it; a shadow ray runs in front of both nodes' planes, because
//! `form_factor` skips sample pairs that do not face each other). The candidate
//! occluders of a patch pair are found once per pair ([`Shaft::candidates`]); a link
//! then tests only those ([`Shaft::clear`]). Every test keeps a margin of twice the
//! rays' offset from the surfaces (`visibility.rs`, 1e-6 of the scene size), so a patch
//! that a shadow ray could touch is never culled: the visible fraction of a culled link
//! is exactly 1, as its rays would have found, and the result is a function of the two
//! nodes alone (the distributed solve of `irradia-parallel` stays equal bit for bit).

use crate::geom::Poly;
use glam::DVec3;

/// Geometry of one side of a link: the polygon and its plane.
#[derive(Clone, Copy)]
pub(super) struct Side<'a> {
    pub poly: &'a Poly,
    pub normal: DVec3,
    pub centroid: DVec3,
}

/// A patch that may block shadow rays: its polygon, box and plane.
#[derive(Clone, Copy, Debug)]
struct Occluder {
    poly: Poly,
    lo: DVec3,
    hi: DVec3,
    normal: DVec3,
}

/// The shaft tests for one scene: the patches and the rays' offset from the surfaces.
#[derive(Clone, Debug)]
pub(super) struct Shaft {
    occluders: Vec<Occluder>,
    /// The shadow rays' offset off each end's surface (`Visibility::offset`).
    offset: f64,
}

/// The shaft of one pair of polygons: the box around both (grown by the margin) and
/// the rays' lowest height above each one's plane.
struct Hull<'a> {
    a: Side<'a>,
    b: Side<'a>,
    lo: DVec3,
    hi: DVec3,
    floors: (f64, f64),
}

fn bounds(vs: &[DVec3]) -> (DVec3, DVec3) {
    vs.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), v| (lo.min(*v), hi.max(*v)),
    )
}

impl Shaft {
    /// The tests over the patches `polys`, for rays offset by `offset`.
    pub(super) fn new(polys: &[Poly], offset: f64) -> Self {
        let occluders = polys
            .iter()
            .map(|p| {
                let (lo, hi) = bounds(p.verts());
                Occluder {
                    poly: *p,
                    lo,
                    hi,
                    normal: p.normal(),
                }
            })
            .collect();
        Self { occluders, offset }
    }

    /// Lowest height above `a`'s plane of a shadow ray from `a` to `b`: its start is
    /// `offset` above, its end (a point of `b` above the plane, moved by `offset`) at
    /// least the lowest corner of `b` (or 0) less `offset`.
    fn floor(&self, a: &Side, b: &Side) -> f64 {
        let low = b
            .poly
            .verts()
            .iter()
            .map(|v| a.normal.dot(*v - a.centroid))
            .fold(f64::INFINITY, f64::min);
        self.offset.min(low.max(0.0) - self.offset)
    }

    fn hull<'a>(&self, a: &Side<'a>, b: &Side<'a>) -> Hull<'a> {
        let m = DVec3::splat(2.0 * self.offset);
        let (alo, ahi) = bounds(a.poly.verts());
        let (blo, bhi) = bounds(b.poly.verts());
        Hull {
            a: *a,
            b: *b,
            lo: alo.min(blo) - m,
            hi: ahi.max(bhi) + m,
            floors: (self.floor(a, b), self.floor(b, a)),
        }
    }

    /// Whether occluder `c` lies wholly outside the shaft `h` (then no shadow ray
    /// between its two polygons can touch it).
    fn separated(&self, c: &Occluder, h: &Hull) -> bool {
        // Boxes.
        if c.lo.cmpgt(h.hi).any() || c.hi.cmplt(h.lo).any() {
            return true;
        }
        // Behind either polygon's plane (below the rays' lowest height, with a margin
        // of half the offset for the f32 rounding of the rays).
        let fuzz = 0.5 * self.offset;
        let below = |s: &Side, floor: f64| {
            c.poly
                .verts()
                .iter()
                .all(|v| s.normal.dot(*v - s.centroid) < floor - fuzz)
        };
        if below(&h.a, h.floors.0) || below(&h.b, h.floors.1) {
            return true;
        }
        // Both polygons on one side of the occluder's plane.
        let m = 2.0 * self.offset;
        let c0 = c.poly.v[0];
        let (mut lo_d, mut hi_d) = (f64::INFINITY, f64::NEG_INFINITY);
        for v in h.a.poly.verts().iter().chain(h.b.poly.verts()) {
            let d = c.normal.dot(*v - c0);
            lo_d = lo_d.min(d);
            hi_d = hi_d.max(d);
        }
        lo_d > m || hi_d < -m
    }

    /// The patches that may block a shadow ray between a point of `a` and a point of
    /// `b`; each node pair below them needs to test only these.
    pub(super) fn candidates(&self, a: &Side, b: &Side) -> Vec<u32> {
        let h = self.hull(a, b);
        (0..self.occluders.len() as u32)
            .filter(|&c| !self.separated(&self.occluders[c as usize], &h))
            .collect()
    }

    /// Whether none of `candidates` can block a shadow ray between `a` and `b`.
    pub(super) fn clear(&self, candidates: &[u32], a: &Side, b: &Side) -> bool {
        if candidates.is_empty() {
            return true;
        }
        let h = self.hull(a, b);
        candidates
            .iter()
            .all(|&c| self.separated(&self.occluders[c as usize], &h))
    }
}

#[cfg(test)]
mod tests {
    use super::super::{side, HierarchicalOptions, Hierarchy};
    use crate::mesh::{Mesh, MeshOptions};
    use crate::scenes;
    use irradia_core::sampling::hash64;
    use irradia_core::Rng;

    /// The culling is conservative: wherever a node pair of the Cornell box with blocks
    /// is declared clear, 64 shadow rays drawn as `form_factor` draws them all pass;
    /// and it has power: many pairs are clear, and every pair whose rays were blocked
    /// was kept.
    #[test]
    fn culled_links_have_no_blocked_rays() {
        let mesh = Mesh::build(&scenes::cornell_measured(), MeshOptions::default()).unwrap();
        let opts = HierarchicalOptions {
            target_leaves: Some(3000),
            ..Default::default()
        };
        let h = Hierarchy::new(&mesh, opts).unwrap();
        let (shaft, vis) = (h.shaft.as_ref().unwrap(), h.vis.as_ref().unwrap());
        let (mut clear, mut blocked, mut tried) = (0, 0, 0);
        let n = h.nodes.len() as u64;
        for k in 0..20_000u64 {
            let pi = (hash64(2 * k) % n) as usize;
            let qi = (hash64(2 * k + 1) % n) as usize;
            let (p, q) = (&h.nodes[pi], &h.nodes[qi]);
            if p.patch == q.patch || !Hierarchy::faces(p, q) {
                continue;
            }
            tried += 1;
            let (pp, pq) = (&h.nodes[p.patch as usize], &h.nodes[q.patch as usize]);
            let cands = shaft.candidates(&side(pp), &side(pq));
            let is_clear = shaft.clear(&cands, &side(p), &side(q));
            let mut rng = Rng::new(hash64(k), 7);
            let mut hidden = false;
            for _ in 0..64 {
                let a = p.poly.sample(rng.next_f64(), rng.next_f64());
                let b = q.poly.sample(rng.next_f64(), rng.next_f64());
                if p.normal.dot(b - a) <= 0.0 || q.normal.dot(a - b) <= 0.0 {
                    continue;
                }
                hidden |= !vis.visible(a, p.normal, b, q.normal);
            }
            assert!(
                !(is_clear && hidden),
                "nodes {pi} and {qi} culled, but a shadow ray between them is blocked"
            );
            clear += is_clear as usize;
            blocked += hidden as usize;
        }
        assert!(tried > 5000, "{tried} facing pairs");
        // Measured: 3,386 of 13,714 random pairs (of every level) culled.
        assert!(clear * 5 > tried, "only {clear} of {tried} pairs culled");
        eprintln!("{clear} culled, {blocked} with a blocked ray, of {tried} pairs");
        assert!(
            blocked * 20 > tried,
            "only {blocked} of {tried} pairs blocked"
        );
    }
}
