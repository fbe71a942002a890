//! `Scene.cast_rays`: batches of rays against the scene through the one ray-query
//! interface (`irradia_geometry::RayQuery`, answered by the render crate's
//! `PreparedScene`, the structure the Whitted tracer renders with), in chunks spread
//! over rayon's threads, with Open3D's `RaycastingScene.cast_rays` conventions: rays
//! of shape (..., 6), results named t_hit, geometry_ids, primitive_ids, primitive_uvs
//! and primitive_normals, misses at t_hit = inf with ids 4294967295
//! (`RaycastingScene.INVALID_ID`).

use crate::convert::values;
use crate::errors;
use irradia_core::{Ray, Vec3};
use irradia_geometry::{ObjectSet, RayQuery, RaySegment};
use irradia_render::PreparedScene;
use irradia_scene::Scene;
use numpy::{PyArray1, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;

/// Id of a ray that hit nothing (Open3D's `RaycastingScene.INVALID_ID`).
pub const INVALID_ID: u32 = u32::MAX;

/// Rays handed to one batched query.
const CHUNK: usize = 256;

/// One ray's answer.
#[derive(Clone, Copy)]
struct Answer {
    t: f32,
    object: u32,
    prim: u32,
    uv: [f32; 2],
    normal: [f32; 3],
}

const MISS: Answer = Answer {
    t: f32::INFINITY,
    object: INVALID_ID,
    prim: INVALID_ID,
    uv: [0.0; 2],
    normal: [0.0; 3],
};

/// The rays and the leading shape of the input.
fn read_rays(
    rays: &PyReadonlyArrayDyn<'_, f32>,
    directions: Option<&PyReadonlyArrayDyn<'_, f32>>,
) -> PyResult<(Vec<Ray>, Vec<usize>)> {
    let shape = rays.shape().to_vec();
    let last = shape.last().copied().unwrap_or(0);
    let lead = shape[..shape.len().saturating_sub(1)].to_vec();
    let pairs: Vec<Ray> = match directions {
        None => {
            if shape.is_empty() || last != 6 {
                return Err(errors::input(format!(
                    "rays: expected an array of shape (..., 6) (origin, direction), got {shape:?}; \
                     or pass origins and directions of shape (..., 3)"
                )));
            }
            values(rays)
                .chunks_exact(6)
                .map(|r| Ray::new(Vec3::new(r[0], r[1], r[2]), Vec3::new(r[3], r[4], r[5])))
                .collect()
        }
        Some(d) => {
            if shape.is_empty() || last != 3 || d.shape() != shape.as_slice() {
                return Err(errors::input(format!(
                    "origins and directions: expected two arrays of the same shape (..., 3), got {shape:?} and {:?}",
                    d.shape()
                )));
            }
            let (o, d) = (values(rays), values(d));
            o.chunks_exact(3)
                .zip(d.chunks_exact(3))
                .map(|(o, d)| Ray::new(Vec3::from_slice(o), Vec3::from_slice(d)))
                .collect()
        }
    };
    if let Some(i) = pairs
        .iter()
        .position(|r| !(r.origin.is_finite() && r.dir.is_finite()))
    {
        return Err(errors::input(format!(
            "rays[{i}]: origin and direction must be finite numbers"
        )));
    }
    Ok((pairs, lead))
}

/// Casts `rays` (see the module); `t_max` ends every ray (default: unbounded).
pub fn cast_rays(
    py: Python<'_>,
    scene: &Scene,
    rays: PyReadonlyArrayDyn<'_, f32>,
    directions: Option<PyReadonlyArrayDyn<'_, f32>>,
    t_max: Option<f32>,
    threads: Option<u32>,
) -> PyResult<PyObject> {
    let (rays, lead) = read_rays(&rays, directions.as_ref())?;
    let t_max = t_max.unwrap_or(f32::INFINITY);
    if t_max.is_nan() || t_max <= 0.0 {
        return Err(errors::input(format!(
            "t_max: must be positive (got {t_max})"
        )));
    }
    let answers = py
        .allow_threads(|| {
            irradia_render::pool::with_threads(threads.map(|t| t.max(1) as usize), || {
                cast(scene, &rays, t_max)
            })
        })
        .map_err(errors::render)?;
    let n = answers.len();
    let shaped = |v: PyObject, extra: Option<usize>| -> PyResult<PyObject> {
        let mut s = lead.clone();
        s.extend(extra);
        Ok(v.bind(py).call_method1("reshape", (s,))?.unbind())
    };
    let d = PyDict::new(py);
    let t: Vec<f32> = answers.iter().map(|a| a.t).collect();
    d.set_item(
        "t_hit",
        shaped(PyArray1::from_vec(py, t).into_any().unbind(), None)?,
    )?;
    let g: Vec<u32> = answers.iter().map(|a| a.object).collect();
    d.set_item(
        "geometry_ids",
        shaped(PyArray1::from_vec(py, g).into_any().unbind(), None)?,
    )?;
    let p: Vec<u32> = answers.iter().map(|a| a.prim).collect();
    d.set_item(
        "primitive_ids",
        shaped(PyArray1::from_vec(py, p).into_any().unbind(), None)?,
    )?;
    let mut uv = Vec::with_capacity(2 * n);
    let mut nrm = Vec::with_capacity(3 * n);
    for a in &answers {
        uv.extend_from_slice(&a.uv);
        nrm.extend_from_slice(&a.normal);
    }
    d.set_item(
        "primitive_uvs",
        shaped(PyArray1::from_vec(py, uv).into_any().unbind(), Some(2))?,
    )?;
    d.set_item(
        "primitive_normals",
        shaped(PyArray1::from_vec(py, nrm).into_any().unbind(), Some(3))?,
    )?;
    Ok(d.into_any().unbind())
}

/// The closest hit of every ray, in parallel chunks of batched queries.
fn cast(scene: &Scene, rays: &[Ray], t_max: f32) -> Vec<Answer> {
    let prepared = PreparedScene::new(scene);
    // Build the query structure once, before the threads ask for it.
    let _ = prepared.objects();
    let mut out = vec![MISS; rays.len()];
    out.par_chunks_mut(CHUNK)
        .zip(rays.par_chunks(CHUNK))
        .for_each(|(out, rays)| {
            let segments: Vec<RaySegment> =
                rays.iter().map(|r| RaySegment::new(*r, t_max)).collect();
            let mut hits = vec![None; rays.len()];
            prepared.closest_hits(ObjectSet::All, &segments, &mut hits);
            for (o, h) in out.iter_mut().zip(hits) {
                if let Some(h) = h {
                    *o = Answer {
                        t: h.hit.t,
                        object: h.instance,
                        prim: h.hit.prim,
                        uv: h.hit.uv.to_array(),
                        normal: h.hit.normal.to_array(),
                    };
                }
            }
        });
    out
}
