//! Local (direct) shading at a hit: ambient, emission, and per light sample the diffuse
//! and specular Phong terms, each light attenuated by its shadow (feeler) rays.
//!
//! Two models (`Material::model`):
//! - `Phong`, the lecture's: `k_a C A + Σ E (k_d C cosθ + k_s (R·V)^n)` with
//!   `E = I / r²` for point lights. No 1/π: a white diffuse surface with `k_d = 1`
//!   facing a point light of intensity I at distance r has radiance `I / r²`.
//! - `PovRay`, POV-Ray 3.7's `finish` (`Trace::ComputeLightedTexture`,
//!   `ComputeDiffuseColour`, `ComputePhongColour`): point and spot lights do not fade
//!   with distance (POV-Ray's default), and the ambient and diffuse terms of a surface
//!   whose pigment filters light are scaled by its opacity `1 - filter`; highlights are
//!   not. The highlight is `phong * (R·L)^phong_size` in the light's colour.

use super::{Ctx, RayQuery, Whitted};
use crate::raytree::Recorder;
use glam::{Vec3, Vec4};
use irradia_core::{offset_ray_origin, Ray, Rgb};
use irradia_geometry::Hit;
use irradia_scatter::optics::reflect_about;
use irradia_scene::{Material, ShadingModel};

impl<G: RayQuery> Whitted<'_, G> {
    /// The local colour at `hit`: `ng` and `ns` are the geometric and shading normals
    /// turned towards the viewer, `view` the unit direction to the viewer, `colour` the
    /// texture's colour there, `filter` the transmitted fraction (colour).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn local<R: Recorder>(
        &self,
        hit: &Hit,
        ng: Vec3,
        ns: Vec3,
        view: Vec3,
        mat: &Material,
        colour: Rgb,
        filter: Rgb,
        depth: u32,
        cx: &mut Ctx<'_, R>,
    ) -> Rgb {
        let pov = mat.model == ShadingModel::PovRay;
        // POV-Ray's opacity of a filtering pigment (TransColour::Opacity).
        let att = if pov {
            (1.0 - filter.luminance()).clamp(0.0, 1.0)
        } else {
            1.0
        };
        let mut c = mat.emission + colour * self.ambient_light * (mat.ambient * att);
        let kd = mat.diffuse * att;
        if (kd <= 0.0 && mat.specular <= 0.0) || self.lights.is_empty() {
            return c;
        }
        // The feeler ray is written per light sample as two 16-byte stores
        // ([`FeelerRay`]); the origin is computed once per hit.
        let origin = offset_ray_origin(hit.point, ng, hit.error);
        let mut feeler = FeelerRay::new();
        for light in &self.lights {
            for i in 0..light.samples() {
                let Some(s) = light.sample(hit.point, i, !pov, cx.rng) else {
                    continue;
                };
                let cos = ns.dot(s.dir);
                if cos <= 0.0 || ng.dot(s.dir) <= 0.0 {
                    continue;
                }
                let tr = self.shadow_transmittance(feeler.set(origin, s.dir), s.dist, depth, cx);
                if tr.is_black() {
                    continue;
                }
                let e = s.irradiance * tr;
                if kd > 0.0 {
                    c += colour * e * (kd * cos);
                }
                if mat.specular > 0.0 {
                    let rv = reflect_about(s.dir, ns).dot(view);
                    if rv > 0.0 {
                        c += e * (mat.specular * phong_power(rv, mat.shininess));
                    }
                }
            }
        }
        c
    }
}

/// The shadow feeler's [`Ray`] in a 32-byte block, written as two 16-byte stores:
/// `(o.x, o.y, o.z, 0)` at byte 0, then `(d.x, d.y, d.z, 0)` at byte 12.
///
/// A load can take its bytes from a store still in the store buffer only when one
/// store wrote all of them (store forwarding); otherwise it waits for the stores to
/// reach the cache (a store-forwarding stall). The scan over the objects and the
/// shapes' `occluded` read the ray right after it is written, in pieces of 4, 8 and 16
/// bytes that straddle the lanes (`Query::occluded` loads `(d.x, d.y)` as one 8-byte
/// value, `Plane::occluded` `(o.y, o.z)` and `(d.y, d.z)`). Written field by field (the
/// origin as three 4-byte stores, the direction as 8 + 4 bytes), such loads stalled:
/// `perf annotate` put ~10% of `Whitted::trace`'s samples, then ~35% of
/// `Plane::occluded`'s, on one. With one store per vector only a load across byte 12
/// (`Sphere`'s quadratic reads `(o.x, o.y, o.z, d.x)` at once) still waits. The block
/// is 32-byte aligned so that the store at byte 12 never splits across cache lines.
#[repr(C, align(32))]
struct FeelerRay {
    ray: Ray,
    _pad: [f32; 2],
}

// `set` writes the ray's bytes by offset.
const _: () = assert!(
    std::mem::offset_of!(Ray, origin) == 0
        && std::mem::offset_of!(Ray, dir) == 12
        && std::mem::size_of::<Ray>() == 24
        && std::mem::size_of::<FeelerRay>() == 32
);

impl FeelerRay {
    #[inline(always)]
    fn new() -> Self {
        Self {
            ray: Ray::new(Vec3::ZERO, Vec3::ZERO),
            _pad: [0.0; 2],
        }
    }

    /// The ray from `origin` along `dir`, written as two 16-byte stores.
    #[inline(always)]
    fn set(&mut self, origin: Vec3, dir: Vec3) -> &Ray {
        let p = (self as *mut Self).cast::<u8>();
        // SAFETY: `self` is 32 bytes of plain f32s (asserted above); the writes cover
        // bytes 0..16 and 12..28, inside it, and bytes 0..24 are `ray`'s origin then
        // direction, so afterwards `ray` is (origin, dir).
        unsafe {
            p.cast::<Vec4>().write_unaligned(origin.extend(0.0));
            p.add(12).cast::<Vec4>().write_unaligned(dir.extend(0.0));
        }
        &self.ray
    }
}

/// `x^n` for the Phong highlight: by repeated squaring when `n` is a whole number (the
/// usual case, e.g. POV-Ray's `phong_size 80`), which is several times cheaper than
/// `powf`; `powf` otherwise.
#[inline]
fn phong_power(x: f32, n: f32) -> f32 {
    // (`n as u32` saturates, so the range check comes first; no libm `truncf` call.)
    if (0.0..=4096.0).contains(&n) && (n as u32) as f32 == n {
        powi_u32(x, n as u32)
    } else {
        x.powf(n)
    }
}

/// `x^n` by binary exponentiation, inline: the same products in the same order as
/// `f32::powi` (compiler-rt's `__powisf2`), so the same bits, without the call.
#[inline]
fn powi_u32(mut x: f32, mut n: u32) -> f32 {
    let mut r = 1.0f32;
    loop {
        if n & 1 == 1 {
            r *= x;
        }
        n >>= 1;
        if n == 0 {
            return r;
        }
        x *= x;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integer_power_matches_powi() {
        for &x in &[0.0f32, 0.3, 0.5, 0.77, 0.999, 1.0] {
            for n in [0u32, 1, 2, 3, 7, 80, 120, 4096] {
                // (black_box: as in rendering, `powi` is called, not folded at compile
                // time, which LLVM does with a differently rounded power.)
                let (xb, nb) = (std::hint::black_box(x), std::hint::black_box(n as i32));
                assert_eq!(powi_u32(x, n).to_bits(), xb.powi(nb).to_bits());
            }
        }
        assert_eq!(phong_power(0.9, 2.5), 0.9f32.powf(2.5));
    }
}
