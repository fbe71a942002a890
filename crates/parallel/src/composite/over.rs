//! Ordered compositing of transparent layers: Porter and Duff's "over" (1984) with
//! premultiplied alpha, applied in a visibility order. "Over" is associative but not
//! commutative, so the order matters: as the lecture warns, "standard visualization
//! strategies are incorrect if transparency used" -- compositing in rank order gives a
//! different picture (see the tests).
//!
//! The visibility order comes from a spatial split of the objects (a k-d tree whose leaves
//! are the ranks, Ma et al. 1994): for a viewpoint, the leaves are listed front to back by
//! visiting, at every split plane, the side holding the eye first. It is exact when no
//! object crosses a split plane (objects are assigned by their centroid).

use super::Pixel;
use glam::Vec3;

/// Blends incoming `(colors, depths)` into the local run with "over".
#[inline]
pub fn blend<P: Pixel>(
    lc: &mut [P],
    ld: &mut [f32],
    colors: &[P],
    depths: &[f32],
    incoming_front: bool,
) {
    let n = lc.len();
    let (ld, colors, depths) = (&mut ld[..n], &colors[..n], &depths[..n]);
    for i in 0..n {
        lc[i] = if incoming_front {
            P::over(colors[i], lc[i])
        } else {
            P::over(lc[i], colors[i])
        };
        ld[i] = ld[i].min(depths[i]);
    }
}

/// A k-d split of object centroids into one leaf per rank.
#[derive(Clone, Debug)]
pub struct SpatialSplit {
    /// Rank owning each object.
    pub owner: Vec<usize>,
    root: Node,
}

#[derive(Clone, Debug)]
enum Node {
    Leaf(usize),
    Split {
        axis: usize,
        plane: f32,
        below: Box<Node>,
        above: Box<Node>,
    },
}

impl SpatialSplit {
    /// Splits objects (given by centroid) among `ranks` leaves of near-equal object
    /// counts, cutting the widest axis of each group at the proportional object.
    pub fn build(centroids: &[Vec3], ranks: usize) -> Self {
        assert!(ranks >= 1);
        let mut owner = vec![0; centroids.len()];
        let mut idx: Vec<usize> = (0..centroids.len()).collect();
        let root = split(centroids, &mut idx, 0, ranks, &mut owner);
        Self { owner, root }
    }

    /// Ranks front to back as seen from `eye`.
    pub fn order(&self, eye: Vec3) -> Vec<usize> {
        let mut out = Vec::new();
        visit(&self.root, eye, &mut out);
        out
    }
}

fn split(c: &[Vec3], idx: &mut [usize], first: usize, ranks: usize, owner: &mut [usize]) -> Node {
    if ranks == 1 {
        for &i in idx.iter() {
            owner[i] = first;
        }
        return Node::Leaf(first);
    }
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for &i in idx.iter() {
        lo = lo.min(c[i]);
        hi = hi.max(c[i]);
    }
    let ext = if idx.is_empty() { Vec3::X } else { hi - lo };
    let axis = if ext.x >= ext.y && ext.x >= ext.z {
        0
    } else if ext.y >= ext.z {
        1
    } else {
        2
    };
    idx.sort_by(|&a, &b| c[a][axis].total_cmp(&c[b][axis]).then(a.cmp(&b)));
    let left_ranks = ranks / 2;
    let cut = idx.len() * left_ranks / ranks;
    let plane = match (
        cut.checked_sub(1).map(|k| c[idx[k]][axis]),
        idx.get(cut).map(|&k| c[k][axis]),
    ) {
        (Some(a), Some(b)) => 0.5 * (a + b),
        (Some(a), None) => a,
        (None, Some(b)) => b,
        (None, None) => 0.0,
    };
    let (l, r) = idx.split_at_mut(cut);
    let below = Box::new(split(c, l, first, left_ranks, owner));
    let above = Box::new(split(c, r, first + left_ranks, ranks - left_ranks, owner));
    Node::Split {
        axis,
        plane,
        below,
        above,
    }
}

fn visit(n: &Node, eye: Vec3, out: &mut Vec<usize>) {
    match n {
        Node::Leaf(r) => out.push(*r),
        Node::Split {
            axis,
            plane,
            below,
            above,
        } => {
            let (a, b) = if eye[*axis] < *plane {
                (below, above)
            } else {
                (above, below)
            };
            visit(a, eye, out);
            visit(b, eye, out);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn u8_over_matches_float_within_rounding() {
        for &(f, fa, b) in &[
            (100u8, 128u8, 200u8),
            (0, 0, 255),
            (255, 255, 7),
            (30, 60, 90),
        ] {
            let o = <[u8; 4]>::over([f, f, f, fa], [b, b, b, 255]);
            let exact = f as f32 + b as f32 * (255.0 - fa as f32) / 255.0;
            assert!(
                (o[0] as f32 - exact).abs() <= 0.5 + 1e-4,
                "{o:?} vs {exact}"
            );
        }
    }

    #[test]
    fn order_is_front_to_back() {
        let c: Vec<Vec3> = (0..8).map(|i| Vec3::new(i as f32, 0.0, 0.0)).collect();
        let s = SpatialSplit::build(&c, 4);
        assert_eq!(s.owner, vec![0, 0, 1, 1, 2, 2, 3, 3]);
        assert_eq!(s.order(Vec3::new(-10.0, 0.0, 0.0)), vec![0, 1, 2, 3]);
        assert_eq!(s.order(Vec3::new(10.0, 0.0, 0.0)), vec![3, 2, 1, 0]);
        assert_eq!(s.order(Vec3::new(4.0, 0.0, 0.0)), vec![2, 3, 1, 0]);
    }
}
