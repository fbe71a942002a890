//! The ray tracer in object-parallel (sort-last) form: each rank owns a contiguous block
//! of the scene's objects, casts every pixel's primary ray against its own objects only,
//! shades the nearest hit locally, and writes colour and depth (distance along the ray);
//! the layers are depth-composited with any strategy of [`crate::composite`].
//!
//! What this form can and cannot do (the lecture's point about object-parallel ray
//! tracing): a primary ray needs only the objects it might hit, and the nearest of the
//! ranks' nearest hits is the scene's nearest hit, so *ray casting* distributes exactly.
//! Everything after the first hit does not: a shadow ray must test every object between
//! the point and the light, and a reflected or refracted ray may hit any object, which
//! live on other ranks. So the shading here is local: ambient, emission and the Phong
//! diffuse and specular terms of every light, **without shadows, reflection or
//! refraction** (area lights count as a point at their centre with the rectangle's or
//! sphere's power). Full Whitted ray tracing of a distributed scene would have to send
//! the secondary rays to the ranks owning what they may hit (ray forwarding), which this
//! module does not do; use the image-parallel form ([`crate::raytrace_first`]) for it.
//!
//! The composite equals [`serial`], the same ray casting over the whole scene, bit for
//! bit: per-object intersections do not depend on which other objects share a rank, and
//! the depth compositors break ties towards the lower rank, which owns the objects that
//! come first. One ray goes through each pixel centre (supersampling would average
//! colours of different objects inside a pixel, which a depth composite cannot undo).

use crate::comm::{Comm, CommError};
use crate::composite::{self, ActiveRect, CompositeOptions, Layer, Operator, Strategy, FAR};
use crate::sort_common::block;
use glam::Vec3;
use irradia_core::{Ray, Rgb};
use irradia_geometry::SceneHit;
use irradia_render::sampler::centre_sample;
use irradia_render::{AovSample, Integrator, Stats, Whitted};
use irradia_scene::{Light, Scene};
use rayon::prelude::*;
use std::ops::Range;

/// The scene with only objects `objects` (same camera, settings, materials, lights).
pub fn sub_scene(scene: &Scene, objects: Range<usize>) -> Scene {
    Scene::new(
        scene.camera,
        scene.settings.clone(),
        scene.materials.clone(),
        scene.lights.clone(),
        scene.objects[objects.clone()].to_vec(),
        scene.accel.instances()[objects].to_vec(),
    )
}

/// Ray casts `scene` through every pixel centre: colour (linear RGB, alpha 1) and
/// distance to the nearest hit; pixels that hit nothing are clear at depth [`FAR`].
pub fn cast_layer(scene: &Scene) -> Layer<[f32; 4]> {
    cast_rows(scene).0
}

/// [`cast_layer`] and the rectangle of the pixels that hit something.
fn cast_rows(scene: &Scene) -> (Layer<[f32; 4]>, ActiveRect) {
    let (w, h) = (scene.settings.width, scene.settings.height);
    let cam = scene.camera.rays(w, h);
    let rows: Vec<Vec<([f32; 4], f32)>> = (0..h)
        .into_par_iter()
        .map(|y| {
            (0..w)
                .map(|x| {
                    let (ray, _) = centre_sample(&cam, x, y);
                    match scene.accel.intersect(&ray, f32::INFINITY) {
                        Some(sh) => {
                            let c = shade(scene, &ray, &sh);
                            ([c.r, c.g, c.b, 1.0], sh.hit.t * ray.dir.length())
                        }
                        None => ([0.0; 4], FAR),
                    }
                })
                .collect()
        })
        .collect();
    assemble(rows, w, h)
}

/// The layer of per-row `(colour, depth)` results, and the rectangle of its pixels that
/// hit something (found while filling the layer, so the compositor need not scan for
/// it).
fn assemble(rows: Vec<Vec<([f32; 4], f32)>>, w: u32, h: u32) -> (Layer<[f32; 4]>, ActiveRect) {
    let mut l = Layer::new(w, h);
    let mut rect = ActiveRect::EMPTY;
    for (y, row) in rows.into_iter().enumerate() {
        let at = y * w as usize;
        let mut hit = None::<(usize, usize)>;
        for (x, (c, d)) in row.into_iter().enumerate() {
            l.color[at + x] = c;
            l.depth[at + x] = d;
            if d != FAR {
                hit = Some((hit.map_or(x, |h| h.0), x));
            }
        }
        if let Some((x0, x1)) = hit {
            let row_rect = ActiveRect {
                x0: x0 as u32,
                y0: y as u32,
                x1: x1 as u32 + 1,
                y1: y as u32 + 1,
            };
            rect = rect.union(&row_rect);
        }
    }
    (l, rect)
}

/// Paints the pixels nothing covers with the scene's background colour.
pub fn fill_background(l: &mut Layer<[f32; 4]>, background: Rgb) {
    for (c, &d) in l.color.iter_mut().zip(&l.depth) {
        if d == FAR {
            *c = [background.r, background.g, background.b, 1.0];
        }
    }
}

/// The serial reference: the same ray casting over the whole scene.
pub fn serial(scene: &Scene) -> Layer<[f32; 4]> {
    let mut l = cast_layer(scene);
    fill_background(&mut l, scene.settings.background);
    l
}

/// How each rank shades the hits on its own objects.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shading {
    /// Local shading, no shadows or secondary rays: the composite equals [`serial`].
    Local,
    /// The full Whitted tracer, but over the rank's own objects only: shadow, reflected
    /// and refracted rays miss every object of the other ranks. Shown to make the
    /// lecture's point: the composite differs from the serial Whitted image as soon as
    /// there are two ranks (equal on one rank, with one ray per pixel centre).
    WhittedOwnObjects,
}

/// The Whitted tracer through every pixel centre of `scene`: colour and distance to the
/// first hit (one ray per pixel; misses are clear at depth [`FAR`]).
pub fn whitted_layer(scene: &Scene) -> Layer<[f32; 4]> {
    whitted_rows(scene).0
}

/// [`whitted_layer`] and the rectangle of the pixels that hit something.
fn whitted_rows(scene: &Scene) -> (Layer<[f32; 4]>, ActiveRect) {
    let (w, h) = (scene.settings.width, scene.settings.height);
    let cam = scene.camera.rays(w, h);
    let tracer = Whitted::new(scene);
    let rows: Vec<Vec<([f32; 4], f32)>> = (0..h)
        .into_par_iter()
        .map(|y| {
            let mut stats = Stats::default();
            (0..w)
                .map(|x| {
                    let (ray, mut rng) = centre_sample(&cam, x, y);
                    let mut aov = AovSample::default();
                    let c = tracer.sample(&ray, &mut rng, &mut stats, &mut aov);
                    if aov.depth.is_finite() {
                        ([c.r, c.g, c.b, 1.0], aov.depth)
                    } else {
                        ([0.0; 4], FAR)
                    }
                })
                .collect()
        })
        .collect();
    assemble(rows, w, h)
}

/// Renders object-parallel with local shading and composites with `strategy`; the
/// image arrives at `root`.
pub fn render<C: Comm>(
    comm: &C,
    scene: &Scene,
    strategy: Strategy,
    root: usize,
) -> Result<Option<Layer<[f32; 4]>>, CommError> {
    render_shaded(comm, scene, strategy, root, Shading::Local)
}

/// [`render`] with a choice of [`Shading`].
pub fn render_shaded<C: Comm>(
    comm: &C,
    scene: &Scene,
    strategy: Strategy,
    root: usize,
    shading: Shading,
) -> Result<Option<Layer<[f32; 4]>>, CommError> {
    let (layer, rect) = render_layer_bounded(comm, scene, shading);
    let opts = CompositeOptions {
        op: Operator::Depth,
        order: None,
        rle: true,
        root,
    };
    let mut out = composite::composite_bounded(comm, strategy, layer, rect, &opts)?;
    if let Some(l) = out.as_mut() {
        fill_background(l, scene.settings.background);
    }
    Ok(out)
}

/// The render step alone (stage "render"): this rank's block of the objects, ray cast
/// with `shading`, as a layer to composite (background left clear: apply
/// [`fill_background`] to the composited image).
pub fn render_layer<C: Comm>(comm: &C, scene: &Scene, shading: Shading) -> Layer<[f32; 4]> {
    render_layer_bounded(comm, scene, shading).0
}

/// [`render_layer`] and the rectangle of the pixels where this rank's objects were hit
/// (known from the rays themselves, for any camera), for
/// [`composite::composite_bounded`]: background outside it is never scanned.
pub fn render_layer_bounded<C: Comm>(
    comm: &C,
    scene: &Scene,
    shading: Shading,
) -> (Layer<[f32; 4]>, ActiveRect) {
    comm.log().begin_stage("render");
    let objects = block(scene.objects.len(), comm.rank(), comm.size());
    if objects.is_empty() {
        let (w, h) = (scene.settings.width, scene.settings.height);
        return (Layer::new(w, h), ActiveRect::EMPTY);
    }
    let mine = sub_scene(scene, objects);
    match shading {
        Shading::Local => cast_rows(&mine),
        Shading::WhittedOwnObjects => whitted_rows(&mine),
    }
}

/// Local shading at the nearest hit, no shadows: emission, ambient, and the lecture's
/// Phong terms `E (k_d C cos θ + k_s (R·V)^n)` per light.
pub fn shade(scene: &Scene, ray: &Ray, sh: &SceneHit) -> Rgb {
    let hit = &sh.hit;
    let object = &scene.objects[sh.instance as usize];
    let mat = &scene.materials[object.material_for_leaf(hit.leaf) as usize];
    let ng = if ray.dir.dot(hit.normal) < 0.0 {
        hit.normal
    } else {
        -hit.normal
    };
    let ns = if hit.shading_normal.dot(ng) < 0.0 {
        -hit.shading_normal
    } else {
        hit.shading_normal
    };
    let view = -ray.dir.normalize();
    let colour = mat.color.eval(hit.point, hit.uv);
    let mut c = mat.emission + colour * scene.settings.ambient_light * mat.ambient;
    // POV-Ray's point and spot lights do not fade with distance (as in the Whitted tracer).
    let fade = mat.model != irradia_scene::ShadingModel::PovRay;
    for light in &scene.lights {
        let Some((l, e)) = incident(light, hit.point, fade) else {
            continue;
        };
        let cos = ns.dot(l);
        if cos <= 0.0 || ng.dot(l) <= 0.0 {
            continue;
        }
        if mat.diffuse > 0.0 {
            c += colour * e * (mat.diffuse * cos);
        }
        if mat.specular > 0.0 {
            let r = 2.0 * ns.dot(l) * ns - l;
            let rv = r.dot(view);
            if rv > 0.0 {
                c += e * (mat.specular * rv.powf(mat.shininess));
            }
        }
    }
    c
}

/// Unit direction towards `light` from `p` and the irradiance it brings (normal
/// incidence); area lights as a point at their centre with their power. Point and spot
/// lights fall off as `1 / r²` when `fade`.
fn incident(light: &Light, p: Vec3, fade: bool) -> Option<(Vec3, Rgb)> {
    let towards = |q: Vec3| {
        let d = q - p;
        let r2 = d.length_squared();
        (r2 > 0.0).then(|| (d / r2.sqrt(), r2))
    };
    let point = |q: Vec3| towards(q).map(|(l, r2)| (l, if fade { r2 } else { 1.0 }));
    match *light {
        Light::Point {
            position,
            intensity,
        } => point(position).map(|(l, r2)| (l, intensity / r2)),
        Light::Directional {
            direction,
            irradiance,
        } => Some((-direction.normalize(), irradiance)),
        Light::Spot {
            position,
            direction,
            intensity,
            cos_inner,
            cos_outer,
            profile,
            ..
        } => point(position).map(|(l, r2)| {
            let f = profile.falloff((-l).dot(direction.normalize()), cos_inner, cos_outer);
            (l, intensity * (f / r2))
        }),
        Light::Projector(ref proj) => proj.illuminate(p).map(|s| {
            let r2 = s.dist * s.dist;
            (s.wi, if fade { s.li } else { s.li * r2 })
        }),
        // Lights at infinity bring nothing along a shadow ray here.
        Light::Constant { .. } | Light::Envmap(_) => None,
        Light::Rect {
            corner,
            edge_u,
            edge_v,
            radiance,
            ..
        } => {
            let n = edge_u.cross(edge_v);
            let area = n.length();
            let centre = corner + 0.5 * (edge_u + edge_v);
            towards(centre).map(|(l, r2)| {
                let cos_l = (-l).dot(n / area.max(1e-30)).max(0.0);
                (l, radiance * (area * cos_l / r2))
            })
        }
        Light::Sphere {
            center,
            radius,
            radiance,
            ..
        } => towards(center)
            .map(|(l, r2)| (l, radiance * (std::f32::consts::PI * radius * radius / r2))),
    }
}
