//! Emissive spheres as lights of the wide kernel's vector stage (see [`super`]): the
//! light choice picks the emitter (its one placeholder facet keeps the facet tables
//! aligned), then every lane whose emitter is a sphere warps its two numbers to a
//! uniform point of the object-space sphere (`sampling::uniform_sphere`, with the
//! azimuth's sine and cosine from [`sin_cos_two_pi`]), carries it and its normal to
//! world space and takes its density by world area,
//! `1 / (4πr² |det M| |M^-T n|)` (the area Jacobian; Pharr, Jakob and Humphreys, PBRT
//! 4th ed., §6.2 and §4.4), the arithmetic of `LightSampler::sample` for an emissive
//! object sampled by its own sampler, in the same order.

use super::gather::{checked, field, field3, Table};
use super::ggx::sin_cos_two_pi;
use crate::path::lights::SphereEmitter;
use irradia_geometry::packet::lanes::{Fw, Mw, V3, W};

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
    pub const LEN: usize = 32;
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
    r
}

/// A light sample's point, unit normal, radiance, density by area and sidedness.
pub(super) struct LightPoint {
    pub q: V3,
    pub n: V3,
    pub radiance: V3,
    pub pdf_area: Fw,
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

/// In the lanes whose chosen emitter (`emitter`) is a sphere, the point its numbers
/// `u` give in place of the facet's `facet`; the other lanes keep `facet`.
#[inline(always)]
pub(super) fn sample(
    table: &Spheres,
    emitter: &[u32; W],
    u: [Fw; 2],
    facet: LightPoint,
) -> LightPoint {
    checked(table, emitter);
    let is = field(table, emitter, sph::IS).ne(0.0);
    if !is.any() {
        return facet;
    }
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
    LightPoint {
        q: V3::select(is, q, facet.q),
        n: V3::select(is, n, facet.n),
        radiance: V3::select(is, field3(table, emitter, sph::RADIANCE), facet.radiance),
        pdf_area: is.select(pdf_area, facet.pdf_area),
        two_sided: (is & field(table, emitter, sph::TWO_SIDED).ne(0.0)) | (!is & facet.two_sided),
    }
}
