//! Mitsuba 3's `normalmap` and `bumpmap`: a nested BSDF evaluated in a perturbed shading
//! frame. Both plugins differ only in how the perturbed normal is found (read from an
//! RGB texture as `2 c - 1`, or from the gradient of a height texture); that lookup
//! belongs to the caller, which hands this wrapper the normal in the local (unperturbed)
//! frame.
//!
//! As Mitsuba: when `flip_invalid_normals` is set and the normal faces away from `wo`
//! (`wo.z (wo·n) ≤ 0`), its tangential part is mirrored; the perturbed frame's tangent
//! is the local x axis made orthogonal to `n`; a direction counts only when it lies on
//! the same side in both frames; and, with `use_shadowing_function`, the value is
//! attenuated by the microfacet shadowing term of Estevez et al. ("A Microfacet-Based
//! Shadowing Function to Solve the Bump Terminator Problem", *Ray Tracing Gems*, 2019).
//! Mitsuba's BSDF value carries the cosine to the perturbed normal; this crate's values
//! exclude the cosine to the local one, so `f = f_nested |cos θ'i| / |cos θi|`.
//! Neither energy nor reciprocity is preserved by normal mapping (Mitsuba's behaviour).

use crate::bsdf::{Bsdf, BsdfSample, LobeFlags, Scatter};
use glam::{Vec2, Vec3};
use irradia_core::Rgb;

#[derive(Clone, Debug)]
pub struct NormalMap {
    /// The perturbed shading normal in the local frame (need not be unit length).
    pub normal: Vec3,
    /// Mitsuba's `flip_invalid_normals` (default true).
    pub flip_invalid_normals: bool,
    /// Mitsuba's `use_shadowing_function` (default true).
    pub use_shadowing_function: bool,
    /// Mitsuba's nested BSDF.
    pub nested_bsdf: Box<Bsdf>,
}

/// The perturbed frame: tangent, bitangent, normal (orthonormal, in the local frame).
struct Perturbed {
    s: Vec3,
    t: Vec3,
    n: Vec3,
}

impl Perturbed {
    fn to_local(&self, w: Vec3) -> Vec3 {
        Vec3::new(w.dot(self.s), w.dot(self.t), w.dot(self.n))
    }

    fn to_world(&self, w: Vec3) -> Vec3 {
        self.s * w.x + self.t * w.y + self.n * w.z
    }
}

/// `tan² θ` of `w` to +z.
fn tan2(w: Vec3) -> f32 {
    let c2 = w.z * w.z;
    ((1.0 - c2) / c2).max(0.0)
}

impl NormalMap {
    /// Wraps `nested_bsdf` with Mitsuba's defaults.
    pub fn new(normal: Vec3, nested_bsdf: Bsdf) -> Self {
        Self {
            normal,
            flip_invalid_normals: true,
            use_shadowing_function: true,
            nested_bsdf: Box::new(nested_bsdf),
        }
    }

    fn frame(&self, wo: Vec3) -> Option<Perturbed> {
        let mut n = self.normal;
        if self.flip_invalid_normals && wo.z * wo.dot(n) <= 0.0 {
            n = Vec3::new(-n.x, -n.y, n.z);
        }
        let n = n.try_normalize()?;
        let s = (Vec3::X - n * n.x).try_normalize()?;
        Some(Perturbed {
            s,
            t: n.cross(s),
            n,
        })
    }

    /// Estevez et al.'s shadowing of the bump terminator for direction `w` (local).
    fn shadowing(&self, n: Vec3, w: Vec3) -> f32 {
        if !self.use_shadowing_function {
            return 1.0;
        }
        let alpha2 = (0.125 * tan2(n)).min(1.0);
        2.0 / (1.0 + (1.0 + alpha2 * tan2(w)).sqrt())
    }
}

impl Scatter for NormalMap {
    fn flags(&self) -> LobeFlags {
        self.nested_bsdf.flags()
    }

    fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let Some(p) = self.frame(wo) else {
            return Rgb::BLACK;
        };
        let (po, pi) = (p.to_local(wo), p.to_local(wi));
        if wi.z * pi.z <= 0.0 || wi.z == 0.0 {
            return Rgb::BLACK;
        }
        self.nested_bsdf.eval(po, pi) * (pi.z.abs() / wi.z.abs() * self.shadowing(p.n, wi))
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Some(p) = self.frame(wo) else {
            return 0.0;
        };
        let (po, pi) = (p.to_local(wo), p.to_local(wi));
        if wi.z * pi.z <= 0.0 {
            return 0.0;
        }
        self.nested_bsdf.pdf(po, pi)
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        let p = self.frame(wo)?;
        let s = self.nested_bsdf.sample(p.to_local(wo), u_lobe, u)?;
        let wi = p.to_world(s.wi);
        if s.wi.z * wi.z <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: s.weight * self.shadowing(p.n, wi),
            ..s
        })
    }
}
