//! A bounding volume hierarchy over anything with a box: triangles inside a mesh,
//! instances in the scene (the two levels of DESIGN.md), patches, form-factor
//! occluders in radiosity.
//!
//! The hierarchy knows only boxes. It is built once from a list of primitive boxes
//! ([`Bvh::build`]); its leaves then hold ranges of *slots*, positions in
//! [`Bvh::order`], which maps each slot back to the caller's primitive index. A caller
//! that wants speed stores its primitive data in slot order (as [`crate::TriangleMesh`]
//! does) so that a leaf reads one contiguous block.
//!
//! Queries take a closure that intersects one primitive:
//!
//! ```
//! use irradia_geometry::bvh::Bvh;
//! use irradia_core::{Aabb, Ray, Vec3};
//! let boxes = vec![Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0))];
//! let bvh = Bvh::build(&boxes);
//! let ray = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
//! // The closure gets a slot and the current t_max, and returns Some(t) for a
//! // nearer hit (t < t_max); the traversal shrinks t_max to it.
//! let mut hit_index = None;
//! let t = bvh.closest_hit(&ray, f32::INFINITY, |slot, _t_max| {
//!     hit_index = Some(bvh.order()[slot as usize]);
//!     Some(4.0)
//! });
//! assert_eq!((t, hit_index), (Some(4.0), Some(0)));
//! ```
//!
//! Files: `node.rs` (the 8-wide node and its SIMD box test), `build.rs` (binned SAH,
//! parallel, collapsed to wide nodes), `traverse.rs` (ordered closest-hit and any-hit
//! traversal), `packet_traverse.rs` (eight coherent rays walking the tree together),
//! `interleaved.rs` (incoherent rays walked a few at a time in turns, to overlap their
//! cache misses).

mod build;
mod interleaved;
pub mod node;
pub mod packet_traverse;
mod partition;
mod traverse;

use irradia_core::Aabb;
pub use node::{ChildRef, WideNode, WIDTH};

/// An 8-wide bounding volume hierarchy.
#[derive(Clone, Debug)]
pub struct Bvh {
    nodes: Vec<WideNode>,
    order: Vec<u32>,
    bounds: Aabb,
}

/// Shape statistics of a built hierarchy.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BvhStats {
    pub nodes: usize,
    pub leaves: usize,
    pub primitives: usize,
    pub max_depth: usize,
    pub max_leaf_size: usize,
    /// SAH cost with unit costs for a node visit and a primitive test.
    pub sah_cost: f32,
}

impl Bvh {
    /// Builds the hierarchy over `boxes` (binned SAH, in parallel on the rayon pool).
    /// Primitives whose box is empty or not finite are left out and never reported:
    /// keep unbounded primitives in a list beside the hierarchy.
    pub fn build(boxes: &[Aabb]) -> Self {
        Self::build_blocked(boxes, 1)
    }

    /// Like [`Bvh::build`] for callers that intersect a leaf's primitives `block` at
    /// a time (8 for meshes, whose leaves are tested two 4-triangle packets at a time):
    /// the SAH then counts blocks, so leaves
    /// fill whole blocks.
    pub fn build_blocked(boxes: &[Aabb], block: usize) -> Self {
        Self::build_blocked_by(boxes.len(), |i| boxes[i], block)
    }

    /// Like [`Bvh::build_blocked`] over the boxes `box_of(0..count)`, asked for once
    /// each while the build's own primitive list is filled: a caller that computes its
    /// boxes (a mesh, from its triangles) needs no array of them.
    pub fn build_blocked_by(
        count: usize,
        box_of: impl Fn(usize) -> Aabb + Sync,
        block: usize,
    ) -> Self {
        let (nodes, order) = build::build(count, box_of, block);
        let bounds = (0..WIDTH)
            .map(|i| nodes[0].child_bounds(i))
            .fold(Aabb::EMPTY, Aabb::union);
        Self {
            nodes,
            order,
            bounds,
        }
    }

    /// Slot -> primitive index. Leaves hold ranges of slots.
    #[inline]
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// The box around every primitive in the hierarchy (empty when there are none).
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    pub fn nodes(&self) -> &[WideNode] {
        &self.nodes
    }

    /// Renumbers the leaves: `f(start_slot, count)` gives the leaf's new index, which
    /// the `*_leaves` queries then pass back. A caller that repacks its primitives
    /// by leaf (4-triangle SIMD packets in [`crate::TriangleMesh`]) uses this; after
    /// it, leaf indices are the caller's and no longer slots.
    pub fn map_leaves(&mut self, mut f: impl FnMut(u32, u32) -> u32) {
        // Depth-first, so leaves near each other in the tree get nearby indices.
        let mut stack = vec![0u32];
        while let Some(n) = stack.pop() {
            for i in (0..WIDTH).rev() {
                let c = self.nodes[n as usize].child_ref(i);
                if c.is_leaf() {
                    self.nodes[n as usize].child[i] = f(c.index, c.count);
                } else if !c.is_empty() {
                    stack.push(c.index);
                }
            }
        }
    }

    /// Like [`Bvh::map_leaves`], but `f` gets the leaf's primitives (the caller's
    /// indices, in slot order) instead of its slot range, so a caller repacking its
    /// primitives by leaf needs no copy of [`Bvh::order`].
    pub fn map_leaf_primitives(&mut self, mut f: impl FnMut(&[u32]) -> u32) {
        let order = &self.order;
        let mut stack = vec![0u32];
        while let Some(n) = stack.pop() {
            for i in (0..WIDTH).rev() {
                let c = self.nodes[n as usize].child_ref(i);
                if c.is_leaf() {
                    let prims = &order[c.index as usize..(c.index + c.count) as usize];
                    self.nodes[n as usize].child[i] = f(prims);
                } else if !c.is_empty() {
                    stack.push(c.index);
                }
            }
        }
    }

    /// Counts nodes, leaves and depth, and the SAH cost of the tree.
    pub fn stats(&self) -> BvhStats {
        let mut s = BvhStats {
            nodes: self.nodes.len(),
            primitives: self.order.len(),
            ..Default::default()
        };
        let root_area = self.bounds.surface_area().max(f32::MIN_POSITIVE);
        let mut stack = vec![(0u32, 1usize, root_area)];
        while let Some((n, depth, area)) = stack.pop() {
            s.max_depth = s.max_depth.max(depth);
            s.sah_cost += area / root_area;
            let node = &self.nodes[n as usize];
            for i in 0..WIDTH {
                let c = node.child_ref(i);
                if c.is_empty() {
                    continue;
                }
                let a = node.child_bounds(i).surface_area();
                if c.is_leaf() {
                    s.leaves += 1;
                    s.max_leaf_size = s.max_leaf_size.max(c.count as usize);
                    s.sah_cost += a / root_area * c.count as f32;
                } else {
                    stack.push((c.index, depth + 1, a));
                }
            }
        }
        s
    }
}
