//! The two-pass image (Wallace, Cohen and Greenberg 1987, "A two-pass solution to the
//! rendering equation"; lecture, "Radiosity" — radiosity for the view-independent
//! diffuse part, ray tracing for the view-dependent specular part).
//!
//! Pass one is the radiosity solution. Pass two traces a ray from the eye through each
//! pixel (a Whitted tracer, lecture "Recursive Ray Tracer"):
//! - at a diffuse surface it returns the solved radiance: the vertex radiosity of the
//!   display mesh (`mesh::weld`) interpolated linearly over the triangle hit, divided
//!   by π — exactly what the Gouraud image shows at that point;
//! - at a mirror it returns the reflectance times the radiance along the mirrored ray;
//! - at glass it returns `F L_reflected + (1 − F) T L_refracted` with the Fresnel
//!   reflectance `F` of a smooth dielectric (`irradia_scatter::optics`), total internal
//!   reflection included;
//! - a ray that leaves the scene returns black.
//!
//! Recursion stops after `max_depth` specular bounces or when the ray's weight falls
//! below `min_weight`. Which specular objects the radiosity pass saw, and how, is
//! described in `crate::two_pass_scene`.

use crate::display::View;
use crate::error::{RadiosityError, Result};
use crate::mesh::weld::DisplayMesh;
use crate::two_pass_scene::{SpecularMaterial, SpecularObject};
use glam::{DVec3, Vec3};
use irradia_core::{offset_ray_origin, Image, Ray, Rgb};
use irradia_geometry::{Accel, Instance, SceneHit, TriangleMesh};
use irradia_scatter::optics::{fresnel_dielectric, reflect_about, refract_through};
use rayon::prelude::*;
use std::f64::consts::PI;
use std::sync::Arc;

/// Settings of the second pass.
#[derive(Clone, Copy, Debug)]
pub struct TwoPassOptions {
    /// Rays per pixel along each axis (`n²` stratified rays per pixel; 1 = the pixel
    /// centre only, as the rasterizer samples).
    pub samples_per_axis: u32,
    /// Most specular bounces after the camera ray.
    pub max_depth: u32,
    /// A ray whose weight (product of the coefficients from the camera, largest
    /// channel) falls below this is not traced.
    pub min_weight: f64,
}

impl Default for TwoPassOptions {
    fn default() -> Self {
        Self {
            samples_per_axis: 2,
            max_depth: 12,
            min_weight: 1e-3,
        }
    }
}

/// The scene of the second pass: the diffuse display triangles with their vertex
/// radiosity, and the specular objects.
pub struct TwoPass<'a> {
    display: &'a DisplayMesh,
    objects: &'a [SpecularObject],
    accel: Accel,
    /// For each triangle of the traced mesh, its index in `display.triangles`.
    triangles: Vec<u32>,
    /// The instance of the diffuse mesh (`None` when every triangle is hidden); the
    /// specular objects follow in order.
    mesh_instance: Option<u32>,
}

impl<'a> TwoPass<'a> {
    /// Prepares the second pass over the triangles of `display` whose patch `keep`
    /// accepts (the stand-ins of specular objects are left out) and `objects`.
    pub fn new(
        display: &'a DisplayMesh,
        keep: impl Fn(u32) -> bool,
        objects: &'a [SpecularObject],
    ) -> Result<Self> {
        let triangles: Vec<u32> = (0..display.triangles.len() as u32)
            .filter(|&t| keep(display.patch[display.triangles[t as usize][0] as usize]))
            .collect();
        let mut instances = Vec::with_capacity(objects.len() + 1);
        let mesh_instance = if triangles.is_empty() {
            None
        } else {
            let mesh = TriangleMesh::new(
                display.positions.iter().map(|p| p.as_vec3()).collect(),
                triangles
                    .iter()
                    .map(|&t| display.triangles[t as usize])
                    .collect(),
                None,
                None,
            )
            .map_err(|e| RadiosityError::Failure(format!("display mesh for ray tracing: {e}")))?;
            instances.push(Instance::untransformed(Arc::new(mesh)));
            Some(0)
        };
        instances.extend(
            objects
                .iter()
                .map(|o| Instance::untransformed(o.shape.clone())),
        );
        Ok(Self {
            display,
            objects,
            accel: Accel::build(instances),
            triangles,
            mesh_instance,
        })
    }

    /// Radiance (RGB) arriving at `origin` from direction `dir` (towards the origin's
    /// opposite: the radiance seen looking along `dir`).
    pub fn radiance(&self, origin: DVec3, dir: DVec3, opts: &TwoPassOptions) -> [f64; 3] {
        self.trace(origin.as_vec3(), dir.normalize().as_vec3(), 0, 1.0, opts)
    }

    fn trace(&self, o: Vec3, d: Vec3, depth: u32, weight: f64, opts: &TwoPassOptions) -> [f64; 3] {
        let Some(h) = self.accel.intersect(&Ray::new(o, d), f32::INFINITY) else {
            return [0.0; 3];
        };
        if Some(h.instance) == self.mesh_instance {
            return self.diffuse(&h);
        }
        let k = h.instance as usize - self.mesh_instance.map_or(0, |_| 1);
        if depth >= opts.max_depth || weight < opts.min_weight {
            return [0.0; 3];
        }
        let n = h.hit.normal;
        let p = h.hit.point;
        // A new ray starts off the surface on the side it leaves towards.
        let spawn = |dir: Vec3| {
            let side = if dir.dot(n) >= 0.0 { n } else { -n };
            offset_ray_origin(p, side, h.hit.error)
        };
        match self.objects[k].material {
            SpecularMaterial::Mirror { reflectance } => {
                let r = reflect_about(-d, n);
                let w = weight * max3(reflectance);
                let l = self.trace(spawn(r), r, depth + 1, w, opts);
                mul(reflectance, l)
            }
            SpecularMaterial::Glass { ior, transmittance } => {
                // `n` points out of the solid: entering when the ray runs against it.
                let entering = d.dot(n) < 0.0;
                let (nn, eta) = if entering {
                    (n, 1.0 / ior as f32)
                } else {
                    (-n, ior as f32)
                };
                // `eta` is n1/n2; the optics module's is the far side's over the near's.
                let f =
                    fresnel_dielectric((-d.dot(nn)).clamp(0.0, 1.0), 1.0 / eta).reflectance as f64;
                let r = reflect_about(-d, nn);
                let mut l = [0.0; 3];
                if f > 0.0 {
                    let lr = self.trace(spawn(r), r, depth + 1, weight * f, opts);
                    l = lr.map(|v| v * f);
                }
                if let Some(t) = refract_through(-d, nn, 1.0 / eta) {
                    let w = weight * (1.0 - f) * max3(transmittance);
                    let lt = self.trace(spawn(t), t, depth + 1, w, opts);
                    for c in 0..3 {
                        l[c] += (1.0 - f) * transmittance[c] * lt[c];
                    }
                }
                l
            }
        }
    }

    /// The radiance of the diffuse surface at a hit: vertex radiosity interpolated with
    /// the barycentric weights of the hit point, divided by π.
    fn diffuse(&self, h: &SceneHit) -> [f64; 3] {
        let tri = self.display.triangles[self.triangles[h.hit.prim as usize] as usize];
        let [a, b, c] = tri.map(|i| self.display.positions[i as usize]);
        let l = barycentric(h.hit.point.as_dvec3(), a, b, c);
        let mut out = [0.0; 3];
        for (w, &i) in l.iter().zip(&tri) {
            let rad = self.display.radiosity[i as usize];
            for ch in 0..3 {
                out[ch] += w * rad[ch] / PI;
            }
        }
        out
    }

    /// The two-pass image: `opts.samples_per_axis²` stratified rays per pixel from the
    /// eye of `view`, averaged.
    pub fn render(&self, view: &View, opts: &TwoPassOptions) -> Result<Image> {
        let (w, h) = (view.width as usize, view.height as usize);
        let mut img = Image::new(view.width, view.height)
            .map_err(|e| RadiosityError::Input(format!("image size: {e}")))?;
        let n = opts.samples_per_axis.max(1);
        let inv = 1.0 / (n * n) as f64;
        img.pixels_mut()
            .par_chunks_mut(w)
            .enumerate()
            .for_each(|(j, row)| {
                for (i, px) in row.iter_mut().enumerate() {
                    let mut sum = [0.0; 3];
                    for sy in 0..n {
                        for sx in 0..n {
                            let x = i as f64 + (sx as f64 + 0.5) / n as f64;
                            let y = j as f64 + (sy as f64 + 0.5) / n as f64;
                            let l = self.radiance(view.eye, view.ray_direction(x, y), opts);
                            for c in 0..3 {
                                sum[c] += l[c];
                            }
                        }
                    }
                    *px = Rgb::new(
                        (sum[0] * inv) as f32,
                        (sum[1] * inv) as f32,
                        (sum[2] * inv) as f32,
                    );
                }
            });
        debug_assert_eq!(img.pixels().len(), w * h);
        Ok(img)
    }
}

/// Barycentric weights of `p` (on or near the triangle's plane) in triangle `a b c`,
/// clamped to the triangle.
pub fn barycentric(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> [f64; 3] {
    let n = (b - a).cross(c - a);
    let nn = n.length_squared();
    if nn <= 0.0 {
        return [1.0, 0.0, 0.0];
    }
    let la = (c - b).cross(p - b).dot(n) / nn;
    let lb = (a - c).cross(p - c).dot(n) / nn;
    let l = [la.max(0.0), lb.max(0.0), (1.0 - la - lb).max(0.0)];
    let s = l[0] + l[1] + l[2];
    l.map(|v| v / s)
}

fn max3(c: [f64; 3]) -> f64 {
    c[0].max(c[1]).max(c[2])
}

fn mul(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] * b[0], a[1] * b[1], a[2] * b[2]]
}
