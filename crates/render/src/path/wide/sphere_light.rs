//! Emissive spheres as lights of the wide kernel's vector stage (see [`super`]): the
//! light choice picks the emitter (its one placeholder facet keeps the facet tables
//! aligned), then every lane whose emitter is a sphere warps its two numbers, the
//! arithmetic of `LightSampler::sample` in the same order: where the sphere has a cone
//! (`lights::visible_sphere`: its transform keeps it a sphere) and the shading point is
//! outside it, to a point of the visible cap by a uniform direction of the cone it
//! subtends, with the density by solid angle; otherwise to a uniform point of the
//! object-space sphere (`sampling::uniform_sphere`, with the azimuth's sine and cosine
//! from [`sin_cos_two_pi`]), carried with its normal to world space, with the density
//! by world area `1 / (4πr² |det M| |M^-T n|)` (the area Jacobian; Pharr, Jakob and
//! Humphreys, PBRT 4th ed., §6.2 and §4.4).

use super::gather::{checked, field, field3, Table};
use super::ggx::sin_cos_two_pi;
use super::kernel::frame;
use crate::path::lights::SphereEmitter;
use irradia_geometry::packet::lanes::{Fw, Mw, V3, W};
use std::f32::consts::TAU;

/// Fields of a sphere-light record (one per emitter; all zero, `IS` included, for
/// the facet emitters).
pub(crate) mod sph {
    pub const CENTER: usize = 0;
    pub const RADIUS: usize = 3;
    /// The object-to-world matrix's columns and translation.
    pub const M: usize = 4;
    pub const T: usize = 13;
    /// The normal matrix's columns.
    pub const N: usize = 16;
    pub const DET: usize = 25;
    pub const AREA: usize = 26;
    pub const RADIANCE: usize = 27;
    pub const TWO_SIDED: usize = 30;
    /// 1 for a sphere emitter.
    pub const IS: usize = 31;
    /// 1 for a sphere sampled by its cone from outside, with its world centre and
    /// radius.
    pub const CONE: usize = 32;
    pub const WORLD_CENTER: usize = 33;
    pub const WORLD_RADIUS: usize = 36;
    pub const LEN: usize = 37;
}

/// The record of `e`.
pub(crate) fn record(e: &SphereEmitter) -> [f32; sph::LEN] {
    let mut r = [0.0; sph::LEN];
    let mut put = |at: usize, v: glam::Vec3| r[at..at + 3].copy_from_slice(&v.to_array());
    put(sph::CENTER, e.center);
    let m = e.to_world.matrix3;
    put(sph::M, m.x_axis.into());
    put(sph::M + 3, m.y_axis.into());
    put(sph::M + 6, m.z_axis.into());
    put(sph::T, e.to_world.translation.into());
    put(sph::N, e.normal_to_world.x_axis);
    put(sph::N + 3, e.normal_to_world.y_axis);
    put(sph::N + 6, e.normal_to_world.z_axis);
    put(
        sph::RADIANCE,
        glam::Vec3::new(e.radiance.r, e.radiance.g, e.radiance.b),
    );
    r[sph::RADIUS] = e.radius;
    r[sph::DET] = e.det;
    r[sph::AREA] = e.area;
    r[sph::TWO_SIDED] = if e.two_sided { 1.0 } else { 0.0 };
    r[sph::IS] = 1.0;
    if let Some(c) = e.cone {
        r[sph::CONE] = 1.0;
        r[sph::WORLD_CENTER..sph::WORLD_CENTER + 3].copy_from_slice(&c.center.to_array());
        r[sph::WORLD_RADIUS] = c.radius;
    }
    r
}

/// A light sample's point, unit normal, radiance, density and sidedness; the density
/// is by area, or by solid angle in the lanes of `solid` (a sphere's cone).
pub(super) struct LightPoint {
    pub q: V3,
    pub n: V3,
    pub radiance: V3,
    pub pdf_area: Fw,
    pub solid: Mw,
    pub two_sided: Mw,
}

/// The sphere records' table.
type Spheres = Table<{ sph::LEN }>;

/// `M v` with the columns of a 3×3 matrix at `at` (glam's column order of sums).
#[inline(always)]
fn mat_vec(table: &Spheres, idx: &[u32; W], at: usize, v: V3) -> V3 {
    // (No closures in the vector stage: one that is not inlined loses the loop's
    // target features.)
    let (c0, c1, c2) = (
        field3(table, idx, at),
        field3(table, idx, at + 3),
        field3(table, idx, at + 6),
    );
    c0.scale(v.x).add(c1.scale(v.y)).add(c2.scale(v.z))
}

/// The cone sample of `VisibleSphere::sample` from the points `p` in every lane: the
/// lanes where `p` is outside its sphere (the others' values are meaningless), the
/// point, its normal and the density by solid angle, the scalar arithmetic in the same
/// order.
#[inline(always)]
fn cone_sample(table: &Spheres, emitter: &[u32; W], u: [Fw; 2], p: V3) -> (Mw, V3, V3, Fw) {
    let c = field3(table, emitter, sph::WORLD_CENTER);
    let r = field(table, emitter, sph::WORLD_RADIUS);
    let v = p.sub(c);
    let d2 = v.dot(v);
    let r2 = r * r;
    let outside = d2.gt(r2);
    let d = d2.sqrt();
    let sin2_max = r2 / d2;
    let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
    let axis = v.scale(1.0 / d);
    let d_over_r = d / r;
    let one_minus_cos_max = sin2_max / (1.0 + cos_max);
    let e = u[0] * one_minus_cos_max;
    let sin2 = e * (2.0 - e);
    let cos_theta = 1.0 - e;
    let k = (sin2 / sin2_max).min(1.0);
    let cos_a = (sin2 * d_over_r + cos_theta * (1.0 - k).sqrt()).min(1.0);
    let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
    let (s, co) = sin_cos_two_pi(u[1]);
    let (fs, ft) = frame(axis);
    let n = fs
        .scale(co * sin_a)
        .add(ft.scale(s * sin_a))
        .add(axis.scale(cos_a));
    let q = c.add(n.scale(r));
    (outside, q, n, 1.0 / (TAU * one_minus_cos_max))
}

/// In the lanes whose chosen emitter (`emitter`) is a sphere, the point its numbers
/// `u` give from the shading points `p` (by the sphere's cone where it has one and `p`
/// is outside, else by area) in place of the facet's `facet`; the other lanes keep
/// `facet`.
#[inline(always)]
pub(super) fn sample(
    table: &Spheres,
    emitter: &[u32; W],
    u: [Fw; 2],
    p: V3,
    facet: LightPoint,
) -> LightPoint {
    checked(table, emitter);
    let is = field(table, emitter, sph::IS).ne(0.0);
    if !is.any() {
        return facet;
    }
    let cone = is & field(table, emitter, sph::CONE).ne(0.0);
    // `uniform_sphere(u)`.
    let z = 1.0 - 2.0 * u[0];
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (s, c) = sin_cos_two_pi(u[1]);
    let no = V3::new(r * c, r * s, z);
    let radius = field(table, emitter, sph::RADIUS);
    let qo = field3(table, emitter, sph::CENTER).add(no.scale(radius));
    let q = mat_vec(table, emitter, sph::M, qo).add(field3(table, emitter, sph::T));
    let nw = mat_vec(table, emitter, sph::N, no);
    let len = nw.dot(nw).sqrt();
    let n = nw.scale(1.0 / len);
    let jacobian = field(table, emitter, sph::DET) * len;
    let pdf_area = 1.0 / (field(table, emitter, sph::AREA) * jacobian);
    let (q, n, pdf_area, solid) = if cone.any() {
        let (outside, cq, cn, pdf) = cone_sample(table, emitter, u, p);
        let solid = cone & outside;
        (
            V3::select(solid, cq, q),
            V3::select(solid, cn, n),
            solid.select(pdf, pdf_area),
            solid,
        )
    } else {
        (q, n, pdf_area, Mw::FALSE)
    };
    LightPoint {
        q: V3::select(is, q, facet.q),
        n: V3::select(is, n, facet.n),
        radiance: V3::select(is, field3(table, emitter, sph::RADIANCE), facet.radiance),
        pdf_area: is.select(pdf_area, facet.pdf_area),
        solid: solid | (!is & facet.solid),
        two_sided: (is & field(table, emitter, sph::TWO_SIDED).ne(0.0)) | (!is & facet.two_sided),
    }
}
