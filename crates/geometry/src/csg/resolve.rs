//! The surface at one boundary of a CSG node's spans combined by their parameters
//! alone.
//!
//! Combining spans (Roth 1982) needs only where each boundary lies; the surface there
//! (normal, texture coordinates, primitive) matters for the one boundary a ray reports,
//! and for none when a shadow ray only asks whether anything is hit. So `Csg` combines
//! parameter-only spans ([`crate::Shape::spans_t`]) whose boundaries are named by leaf
//! and by place in that leaf's own span list (`Csg::operand_spans`), and then computes
//! the winner's surface here: that boundary of the leaf's own spans
//! ([`crate::Shape::span_boundary`]), along the same ray carried through the same
//! transforms. Every step is the one the full
//! combination takes (the same shape call, the same normal transforms), and `combine`'s
//! negation of subtracted faces, carried as the sign of the stand-in normal, is exact and
//! commutes with the transforms and the normalisation; so the result is the boundary the
//! full combination gives, bit for bit.

use super::node::Csg;
use crate::shape::{Boundary, Span};
use irradia_core::Ray;

impl Csg {
    /// The full boundary (surface included) that the parameter-only boundary `e` of
    /// this node's spans along `ray` stands for. `buf` is scratch space.
    pub(super) fn resolve(&self, ray: &Ray, e: &Boundary, buf: &mut Vec<Span>) -> Boundary {
        let mut b = self.boundary_of_leaf(ray, e, e.leaf, buf);
        debug_assert_eq!(
            b.t.to_bits(),
            e.t.to_bits(),
            "resolved a different boundary"
        );
        if e.normal.x < 0.0 {
            b.normal = -b.normal;
        }
        b
    }

    /// Boundary number `e.prim` (`2i` the enter of span `i`, `2i + 1` its exit) of leaf
    /// `leaf`'s own spans along `ray`, carried to this node's space and with the leaf
    /// renumbered as `operand_spans` does, before any negation by `combine`. `e` is
    /// that boundary as the leaf's `spans_t` gave it (named, combined).
    fn boundary_of_leaf(
        &self,
        ray: &Ray,
        e: &Boundary,
        leaf: u32,
        buf: &mut Vec<Span>,
    ) -> Boundary {
        let index = e.prim;
        // Children are in leaf order, each holding at least one leaf.
        let i = self.children.partition_point(|c| c.leaf_offset <= leaf) - 1;
        let c = &self.children[i];
        let mut b = match &c.node {
            None => c
                .instance
                .span_boundary_of(ray, index, e, buf)
                .expect("a boundary of the leaf's own spans"),
            Some(node) => {
                let r = c.instance.ray_to_object(ray);
                let mut b = node.boundary_of_leaf(&r, e, leaf - c.leaf_offset, buf);
                b.normal = c.instance.carry_boundary_normal(b.t, b.normal);
                b
            }
        };
        b.leaf += c.leaf_offset;
        b
    }
}
