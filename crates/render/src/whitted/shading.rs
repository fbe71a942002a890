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
use glam::Vec3;
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
        // The feeler's origin is written into the ray once per hit, in place, and only
        // its direction per light sample: built per sample from the origin's three
        // lanes, the ray was assembled through a stack copy whose 8-byte reload of two
        // 4-byte stores stalled on store forwarding (perf annotate, `whitted`).
        let mut feeler = Ray::new(offset_ray_origin(hit.point, ng, hit.error), Vec3::ZERO);
        for light in &self.lights {
            for i in 0..light.samples() {
                let Some(s) = light.sample(hit.point, i, !pov, cx.rng) else {
                    continue;
                };
                let cos = ns.dot(s.dir);
                if cos <= 0.0 || ng.dot(s.dir) <= 0.0 {
                    continue;
                }
                feeler.dir = s.dir;
                let tr = self.shadow_transmittance(&feeler, s.dist, depth, cx);
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
