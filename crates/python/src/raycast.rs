//! `Scene.cast_rays`: batches of rays against the scene through the one ray-query
//! interface (`irradia_geometry::RayQuery`, answered by the render crate's
//! `PreparedScene`, the structure the Whitted tracer renders with), in chunks spread
//! over rayon's threads, with Open3D's `RaycastingScene.cast_rays` conventions: rays
//! of shape (..., 6), results named t_hit, geometry_ids, primitive_ids, primitive_uvs
//! and primitive_normals, misses at t_hit = inf with ids 4294967295
//! (`RaycastingScene.INVALID_ID`).
//!
//! Nothing is staged between numpy and the kernel: C-contiguous float32 rays are read
//! in place (any other layout is copied once), the five result arrays are allocated
//! once with their final shapes, and every chunk of rays, with the GIL released, asks
//! the scene's batch query (`Accel::intersect_cast_hits`: coherent groups of eight rays
//! traced as packets through the top level and each mesh, the rest ray by ray; a scene
//! of one untransformed mesh straight through that mesh) for only the four values
//! returned, and writes them straight into its slices of those arrays.

use crate::convert::values;
use crate::errors;
use irradia_core::{Ray, Vec3};
use irradia_geometry::CastHit;
use irradia_scene::Scene;
use numpy::{PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Id of a ray that hit nothing (Open3D's `RaycastingScene.INVALID_ID`).
pub const INVALID_ID: u32 = u32::MAX;

/// Rays per parallel task.
const CHUNK: usize = 256;

/// Where the rays are: one (..., 6) array, or origins and directions (..., 3).
#[derive(Clone, Copy)]
enum Rays<'a> {
    Packed(&'a [f32]),
    Split(&'a [f32], &'a [f32]),
}

impl Rays<'_> {
    #[inline]
    fn ray(&self, i: usize) -> Ray {
        match self {
            Rays::Packed(r) => {
                let r = &r[6 * i..6 * i + 6];
                Ray::new(Vec3::new(r[0], r[1], r[2]), Vec3::new(r[3], r[4], r[5]))
            }
            Rays::Split(o, d) => Ray::new(
                Vec3::from_slice(&o[3 * i..3 * i + 3]),
                Vec3::from_slice(&d[3 * i..3 * i + 3]),
            ),
        }
    }

    /// The first ray whose origin or direction is not finite.
    fn first_bad(&self, n: usize) -> Option<usize> {
        (0..n).find(|&i| !finite(&self.ray(i)))
    }
}

#[inline]
fn finite(r: &Ray) -> bool {
    r.origin.is_finite() && r.dir.is_finite()
}

/// The result arrays, in the order of `NAMES`.
const NAMES: [&str; 5] = [
    "t_hit",
    "geometry_ids",
    "primitive_ids",
    "primitive_uvs",
    "primitive_normals",
];

/// One chunk's slices of the five result arrays.
struct Out<'a> {
    t: &'a mut [f32],
    object: &'a mut [u32],
    prim: &'a mut [u32],
    uv: &'a mut [f32],
    normal: &'a mut [f32],
}

/// Casts `rays` (see the module); `t_max` ends every ray (default: unbounded).
/// `packets: false` traces every ray alone (`Accel::intersect_cast`), the reference
/// for the batched path.
#[allow(clippy::too_many_arguments)]
pub fn cast_rays(
    py: Python<'_>,
    scene: &Scene,
    rays: PyReadonlyArrayDyn<'_, f32>,
    directions: Option<PyReadonlyArrayDyn<'_, f32>>,
    t_max: Option<f32>,
    threads: Option<u32>,
    packets: bool,
) -> PyResult<PyObject> {
    let shape = rays.shape().to_vec();
    let last = shape.last().copied().unwrap_or(0);
    let lead = shape[..shape.len().saturating_sub(1)].to_vec();
    let n: usize = lead.iter().product();
    let (packed, split);
    let input = match directions.as_ref() {
        None => {
            if shape.is_empty() || last != 6 {
                return Err(errors::input(format!(
                    "rays: expected an array of shape (..., 6) (origin, direction), got {shape:?}; \
                     or pass origins and directions of shape (..., 3)"
                )));
            }
            packed = values(&rays);
            Rays::Packed(&packed)
        }
        Some(d) => {
            if shape.is_empty() || last != 3 || d.shape() != shape.as_slice() {
                return Err(errors::input(format!(
                    "origins and directions: expected two arrays of the same shape (..., 3), got {shape:?} and {:?}",
                    d.shape()
                )));
            }
            split = (values(&rays), values(d));
            Rays::Split(&split.0, &split.1)
        }
    };
    let t_max = t_max.unwrap_or(f32::INFINITY);
    let bad_rays = |i: usize| {
        errors::input(format!(
            "rays[{i}]: origin and direction must be finite numbers"
        ))
    };
    if t_max.is_nan() || t_max <= 0.0 {
        // A bad ray is reported first, as the rays are read before the options.
        if let Some(i) = input.first_bad(n) {
            return Err(bad_rays(i));
        }
        return Err(errors::input(format!(
            "t_max: must be positive (got {t_max})"
        )));
    }
    let with = |extra: Option<usize>| {
        let mut s = lead.clone();
        s.extend(extra);
        s
    };
    // SAFETY (the five `new`): every element is written below before Python sees the
    // arrays; on an error they are dropped unread.
    let t = unsafe { PyArrayDyn::<f32>::new(py, with(None), false) };
    let g = unsafe { PyArrayDyn::<u32>::new(py, with(None), false) };
    let p = unsafe { PyArrayDyn::<u32>::new(py, with(None), false) };
    let uv = unsafe { PyArrayDyn::<f32>::new(py, with(Some(2)), false) };
    let nrm = unsafe { PyArrayDyn::<f32>::new(py, with(Some(3)), false) };
    {
        let (mut tw, mut gw, mut pw, mut uvw, mut nw) = (
            t.readwrite(),
            g.readwrite(),
            p.readwrite(),
            uv.readwrite(),
            nrm.readwrite(),
        );
        let slice = |e| errors::input(format!("cast_rays: result array not contiguous ({e})"));
        let out = Out {
            t: tw.as_slice_mut().map_err(slice)?,
            object: gw.as_slice_mut().map_err(slice)?,
            prim: pw.as_slice_mut().map_err(slice)?,
            uv: uvw.as_slice_mut().map_err(slice)?,
            normal: nw.as_slice_mut().map_err(slice)?,
        };
        let bad = py
            .allow_threads(|| {
                irradia_render::pool::with_threads(threads.map(|t| t.max(1) as usize), || {
                    cast(scene, input, t_max, out, packets)
                })
            })
            .map_err(errors::render)?;
        if let Some(i) = bad {
            return Err(bad_rays(i));
        }
    }
    let d = PyDict::new(py);
    d.set_item(NAMES[0], t)?;
    d.set_item(NAMES[1], g)?;
    d.set_item(NAMES[2], p)?;
    d.set_item(NAMES[3], uv)?;
    d.set_item(NAMES[4], nrm)?;
    Ok(d.into_any().unbind())
}

/// The closest hit of every ray into `out`, in parallel chunks of rays; the first ray
/// that is not finite, if any (then `out` is partly written).
///
/// Each chunk goes to the scene's batch query (`Accel::intersect_cast_hits`), which
/// answers every ray as the two-level hierarchy's single-ray `Accel::intersect_cast`
/// does, bit for bit (the same hits as the renderer's `RayQuery::closest_hit` over all
/// objects), asking only for what is returned: a triangle mesh answers from the leaf
/// it hit (its packet holds the triangle id and corners), so no mesh index, vertex or
/// vertex normal is looked up, as in the kernel of bench/triangles. Groups of eight
/// consecutive rays that share a direction octant are traced together: through the
/// top level and then, as one packet, through each mesh instance they reach (carried
/// into object space where the instance is transformed); a scene of one untransformed
/// triangle mesh (`Accel::sole_mesh`) skips the top level and goes straight to that
/// mesh's batch query, and a scene of several untransformed meshes goes through one
/// mesh of all their triangles, built on the first call (`Accel::prepare_cast_batches`,
/// irradia_geometry::flat_meshes; near ties between triangles are traced again
/// through the two levels). The rest go ray by ray (tests/test_cast_rays.py holds the
/// batched and single-ray answers equal).
fn cast(scene: &Scene, rays: Rays<'_>, t_max: f32, out: Out<'_>, packets: bool) -> Option<usize> {
    let accel = &scene.accel;
    if !packets {
        return cast_with(rays, t_max, out, |r, t, hits| {
            for (h, r) in hits.iter_mut().zip(r) {
                *h = accel.intersect_cast(r, t);
            }
        });
    }
    accel.prepare_cast_batches();
    cast_with(rays, t_max, out, |r, t, hits| {
        accel.intersect_cast_hits(r, t, hits)
    })
}

/// [`cast`] with the query `hits(rays, t_max, answers)` answering a chunk of rays (the
/// object and its hit), compiled once per kind of query.
fn cast_with<Q>(rays: Rays<'_>, t_max: f32, out: Out<'_>, hits: Q) -> Option<usize>
where
    Q: Fn(&[Ray], f32, &mut [Option<(u32, CastHit)>]) + Sync,
{
    let bad = AtomicUsize::new(usize::MAX);
    out.t
        .par_chunks_mut(CHUNK)
        .zip(out.object.par_chunks_mut(CHUNK))
        .zip(out.prim.par_chunks_mut(CHUNK))
        .zip(out.uv.par_chunks_mut(2 * CHUNK))
        .zip(out.normal.par_chunks_mut(3 * CHUNK))
        .enumerate()
        .for_each(|(c, ((((t, object), prim), uv), normal))| {
            let first = c * CHUNK;
            let n = t.len();
            let mut chunk = [Ray::new(Vec3::ZERO, Vec3::ZERO); CHUNK];
            for (k, slot) in chunk[..n].iter_mut().enumerate() {
                *slot = rays.ray(first + k);
                if !finite(slot) {
                    bad.fetch_min(first + k, Ordering::Relaxed);
                    return;
                }
            }
            let mut answers = [None; CHUNK];
            hits(&chunk[..n], t_max, &mut answers[..n]);
            for (k, a) in answers[..n].iter().enumerate() {
                let (tk, ok, pk, uvk, nk) = match a {
                    Some((i, h)) => (h.t, *i, h.prim, h.uv.to_array(), h.normal.to_array()),
                    None => (f32::INFINITY, INVALID_ID, INVALID_ID, [0.0; 2], [0.0; 3]),
                };
                t[k] = tk;
                object[k] = ok;
                prim[k] = pk;
                uv[2 * k..2 * k + 2].copy_from_slice(&uvk);
                normal[3 * k..3 * k + 3].copy_from_slice(&nk);
            }
        });
    match bad.into_inner() {
        usize::MAX => None,
        i => Some(i),
    }
}

/// Seconds the kernel alone takes on `rays` (..., 6), for the benchmark's "binding
/// overhead" (bench/python/cast_rays_gyroid.py: `cast_rays` time minus this): the
/// rays are read and the answers' buffer allocated before the clock starts, then the
/// same queries (the sole mesh's or the scene's, as [`cast`] picks) run in the same
/// chunks on the same threads as `cast_rays`, the answers left as the kernel gives
/// them. `packets: false` asks ray by ray instead (the sole mesh's
/// `TriangleMesh::intersect_cast_hit`, or the scene's `Accel::intersect_cast`: the paths
/// before packet traversal), for paired comparisons of the two in one process.
pub fn kernel_seconds(
    py: Python<'_>,
    scene: &Scene,
    rays: PyReadonlyArrayDyn<'_, f32>,
    threads: Option<u32>,
    packets: bool,
) -> PyResult<f64> {
    if rays.shape().last() != Some(&6) {
        return Err(errors::input("rays: expected an array of shape (..., 6)"));
    }
    let v = values(&rays);
    let input = Rays::Packed(&v);
    let n = v.len() / 6;
    if let Some(i) = input.first_bad(n) {
        return Err(errors::input(format!(
            "rays[{i}]: origin and direction must be finite numbers"
        )));
    }
    let rays: Vec<Ray> = (0..n).map(|i| input.ray(i)).collect();
    let mut hits: Vec<Option<(u32, CastHit)>> = vec![None; n];
    py.allow_threads(|| {
        irradia_render::pool::with_threads(threads.map(|t| t.max(1) as usize), || {
            let accel = &scene.accel;
            if packets {
                accel.prepare_cast_batches();
            }
            let start = std::time::Instant::now();
            match accel.sole_mesh() {
                _ if packets => answer_all(&rays, &mut hits, |r, t, h| {
                    accel.intersect_cast_hits(r, t, h)
                }),
                Some(mesh) => answer_all(&rays, &mut hits, |r, t, h| {
                    for (h, r) in h.iter_mut().zip(r) {
                        *h = mesh.intersect_cast_hit(r, t).map(|h| (0, h));
                    }
                }),
                None => answer_all(&rays, &mut hits, |r, t, h| {
                    for (h, r) in h.iter_mut().zip(r) {
                        *h = accel.intersect_cast(r, t);
                    }
                }),
            }
            start.elapsed().as_secs_f64()
        })
    })
    .map_err(errors::render)
}

/// `hits[i]` = the answer to `rays[i]` (unbounded), in [`cast`]'s chunks (the kernel
/// of [`kernel_seconds`]).
fn answer_all<Q>(rays: &[Ray], hits: &mut [Option<(u32, CastHit)>], query: Q)
where
    Q: Fn(&[Ray], f32, &mut [Option<(u32, CastHit)>]) + Sync,
{
    hits.par_chunks_mut(CHUNK)
        .zip(rays.par_chunks(CHUNK))
        .for_each(|(h, r)| query(r, f32::INFINITY, h));
}
