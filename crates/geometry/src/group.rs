//! A shape group placed many times: Mitsuba 3's `shapegroup` with its `instance`s, and
//! pbrt's `ObjectBegin` / `ObjectInstance`. The members are placed once in the group's
//! own space under one hierarchy of their own (an [`Accel`]); every placement is an
//! [`Instance`] of the same `Arc<ShapeGroup>`, so a forest of a thousand trees holds
//! one tree and one hierarchy (the two-level scheme of Wald et al., "Ray tracing
//! animated scenes", and of pbrt-v4's instancing, chapter 7.1.6).
//!
//! A hit on member `m` reports `Hit::leaf = first_leaf(m) + its own leaf`, so the
//! members' materials (and the CSG leaves inside them) stay apart: the object placing
//! the group lists them in its `leaf_materials`.

use crate::accel::Accel;
use crate::instance::Instance;
use crate::mesh::AttributePoint;
use crate::shape::{Facets, Hit, Shape, Span};
use glam::Vec3;
use irradia_core::{Aabb, Ray};

#[derive(Debug)]
pub struct ShapeGroup {
    accel: Accel,
    /// First leaf number of each member, in member order.
    first_leaf: Vec<u32>,
    leaves: u32,
    bounds: Aabb,
}

impl ShapeGroup {
    /// A group of `members`, each an instance (in the group's space) and the number of
    /// leaves it reports (1 for a plain shape, a CSG tree's leaf count).
    pub fn new(members: Vec<(Instance, u32)>) -> ShapeGroup {
        let mut first_leaf = Vec::with_capacity(members.len());
        let mut leaves = 0u32;
        let mut bounds = Aabb::EMPTY;
        let mut instances = Vec::with_capacity(members.len());
        for (instance, n) in members {
            first_leaf.push(leaves);
            leaves += n.max(1);
            bounds = bounds.union(instance.bounds());
            instances.push(instance);
        }
        ShapeGroup {
            accel: Accel::build(instances),
            first_leaf,
            leaves,
            bounds,
        }
    }

    /// The number of leaves of all members together.
    pub fn leaf_count(&self) -> u32 {
        self.leaves
    }

    /// The members, in the order given.
    pub fn members(&self) -> &[Instance] {
        self.accel.instances()
    }

    /// The member reporting group leaf `leaf`, and the member's own leaf number.
    fn member_of(&self, leaf: u32) -> (usize, u32) {
        let m = self
            .first_leaf
            .partition_point(|&f| f <= leaf)
            .saturating_sub(1);
        (m, leaf - self.first_leaf[m])
    }
}

impl Shape for ShapeGroup {
    fn kind(&self) -> &'static str {
        "group"
    }

    fn bounds(&self) -> Aabb {
        self.bounds
    }

    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let sh = self.accel.intersect(ray, t_max)?;
        let mut hit = sh.hit;
        hit.leaf += self.first_leaf[sh.instance as usize];
        Some(hit)
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.accel.occluded(ray, t_max)
    }

    fn uv_derivatives_at(&self, hit: &Hit) -> (Vec3, Vec3) {
        if self.first_leaf.is_empty() {
            return (Vec3::ZERO, Vec3::ZERO);
        }
        let (m, leaf) = self.member_of(hit.leaf);
        let mut member_hit = *hit;
        member_hit.leaf = leaf;
        self.members()[m].uv_derivatives(&member_hit)
    }

    fn attribute_point(&self, hit: &Hit) -> Option<AttributePoint<'_>> {
        if self.first_leaf.is_empty() {
            return None;
        }
        let (m, leaf) = self.member_of(hit.leaf);
        let mut member_hit = *hit;
        member_hit.leaf = leaf;
        self.members()[m].attribute_point(&member_hit)
    }

    /// A group is a set of surfaces, not one solid (its members may overlap).
    fn is_solid(&self) -> bool {
        false
    }

    fn spans(&self, _ray: &Ray, _out: &mut Vec<Span>) {}

    /// Every member's facets, placed in the group's space.
    fn facets(&self, detail: u32) -> Option<Facets> {
        let mut out = Facets::default();
        let mut smooth = true;
        let mut parts = Vec::new();
        for m in self.members() {
            let f = m.shape.facets(detail)?;
            smooth &= f.normals.len() == f.vertices.len();
            parts.push((m, f));
        }
        for (m, f) in parts {
            let base = out.vertices.len() as u32;
            let to_world = m.to_world();
            out.vertices
                .extend(f.vertices.iter().map(|&v| to_world.transform_point3(v)));
            out.faces.extend(
                f.faces
                    .iter()
                    .map(|face| face.iter().map(|&i| i + base).collect::<Vec<u32>>()),
            );
            if smooth {
                let n = to_world.matrix3.inverse().transpose();
                out.normals.extend(
                    f.normals
                        .iter()
                        .map(|&v| Vec3::from(n.mul_vec3a(v.into())).normalize()),
                );
            }
        }
        Some(out)
    }
}
