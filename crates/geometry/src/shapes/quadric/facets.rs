//! Polygons for the bounded named quadrics: ellipsoids (a UV sphere stretched), capped
//! cylinders and cones (a ring of quads or triangles plus two cap polygons).

use super::{Quadric, QuadricKind};
use crate::shape::Facets;
use crate::shapes::sphere::uv_sphere;
use glam::{DVec3, Vec3};
use std::f64::consts::TAU;

pub(super) fn facets(q: &Quadric, detail: u32) -> Option<Facets> {
    let to_object = q.to_local.inverse();
    let normal_to_object = q.to_local.matrix3.transpose();
    let mut f = match q.kind {
        QuadricKind::Ellipsoid { radii } => {
            let mut f = uv_sphere(detail);
            for v in &mut f.vertices {
                *v = (v.as_dvec3() * radii).as_vec3();
            }
            for n in &mut f.normals {
                *n = (n.as_dvec3() / radii).normalize().as_vec3();
            }
            f
        }
        QuadricKind::CappedCylinder { radius, height } => frustum(radius, radius, height, detail),
        QuadricKind::CappedCone { r0, r1, height } => frustum(r0, r1, height, detail),
        _ => return None,
    };
    if !q.clip.is_empty()
        && !matches!(
            q.kind,
            QuadricKind::CappedCylinder { .. } | QuadricKind::CappedCone { .. }
        )
    {
        // Extra clipping planes would cut the mesh; not supported.
        return None;
    }
    for v in &mut f.vertices {
        *v = to_object.transform_point3(v.as_dvec3()).as_vec3();
    }
    for n in &mut f.normals {
        *n = (normal_to_object * n.as_dvec3()).normalize().as_vec3();
    }
    Some(f)
}

/// A frustum around local `y` from radius `r0` at `y = 0` to `r1` at `y = h`, faces
/// counter-clockwise seen from outside, with per-vertex normals (sides smooth, caps
/// flat: cap vertices are separate copies).
fn frustum(r0: f64, r1: f64, h: f64, detail: u32) -> Facets {
    let n = detail.max(3) as usize;
    let mut f = Facets::default();
    // Side normal of a frustum: radial component h, axial component (r0 - r1).
    let slope = DVec3::new(h, r0 - r1, 0.0).normalize();
    let ring = |r: f64, y: f64, i: usize| {
        let a = TAU * i as f64 / n as f64;
        (
            Vec3::new((r * a.cos()) as f32, y as f32, (r * a.sin()) as f32),
            Vec3::new(
                (slope.x * a.cos()) as f32,
                slope.y as f32,
                (slope.x * a.sin()) as f32,
            ),
        )
    };
    // Side: bottom ring 0..n, top ring n..2n (a zero radius ring is still n copies of
    // the apex, each with its own normal; its faces become triangles).
    for (r, y) in [(r0, 0.0), (r1, h)] {
        for i in 0..n {
            let (p, nn) = ring(r, y, i);
            f.vertices.push(p);
            f.normals.push(nn);
        }
    }
    for i in 0..n {
        let j = (i + 1) % n;
        let (b0, b1, t0, t1) = (i as u32, j as u32, (n + i) as u32, (n + j) as u32);
        let face = if r1 == 0.0 {
            vec![t0, b1, b0]
        } else if r0 == 0.0 {
            vec![t0, t1, b0]
        } else {
            vec![t0, t1, b1, b0]
        };
        f.faces.push(face);
    }
    // Caps: bottom (normal -y) with increasing angle, top (+y) with decreasing angle.
    for (r, y, normal) in [(r0, 0.0, -Vec3::Y), (r1, h, Vec3::Y)] {
        if r == 0.0 {
            continue;
        }
        let start = f.vertices.len() as u32;
        for i in 0..n {
            f.vertices.push(ring(r, y, i).0);
            f.normals.push(normal);
        }
        let mut face: Vec<u32> = (0..n as u32).map(|i| start + i).collect();
        if normal.y > 0.0 {
            face.reverse();
        }
        f.faces.push(face);
    }
    f
}
