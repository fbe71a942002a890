//! `irradia.composite` over an mpi4py communicator (cargo feature `mpi`): the
//! communicator's Fortran handle (`comm.py2f()`) becomes a C handle (`MPI_Comm_f2c`),
//! whose private duplicate (made once and cached on it, [`crate::comm_cache`], so that
//! Irradia's messages never meet the caller's) is wrapped as the parallel crate's
//! `MpiComm`, on which the compositors run exactly as under `irradia parallel --comm
//! mpi`.

use crate::comm_cache;
use crate::composite::{
    check_order, depth_array, image_arrays, layer_arrays, layout, operator, planes, planes_mut,
    strategy, Channels, TileSpec,
};
use crate::errors;
use irradia_parallel::comm::mpi::MpiComm;
use irradia_parallel::composite::{self, ActiveRect, CompositeOptions, Layer};
use irradia_parallel::display_tiles;
use numpy::{PyArrayMethods, PyReadonlyArrayDyn};
use pyo3::prelude::*;
use std::time::Duration;

#[allow(clippy::too_many_arguments)]
fn run<P: Channels>(
    py: Python<'_>,
    color: &Bound<'_, PyAny>,
    depth: Option<PyReadonlyArrayDyn<'_, f32>>,
    strategy_name: &str,
    op: &str,
    order: Option<Vec<usize>>,
    root: usize,
    rle: bool,
    fortran_comm: i64,
    timeout: f64,
    tiles: Option<Vec<TileSpec>>,
) -> PyResult<Option<(PyObject, PyObject)>> {
    let c: PyReadonlyArrayDyn<'_, P::Channel> = color.extract()?;
    let pl = planes::<P>(&c, depth.as_ref())?;
    if pl.n != 1 {
        return Err(errors::input(
            "color: with a communicator each rank passes one layer of shape (height, width, 4)",
        ));
    }
    let strategy = strategy(strategy_name)?;
    let op = operator(op)?;
    let fint = i32::try_from(fortran_comm)
        .map_err(|_| errors::input("comm: not an MPI communicator handle"))?;
    if !(timeout.is_finite() && timeout > 0.0) {
        return Err(errors::input(format!(
            "timeout: must be positive seconds (got {timeout})"
        )));
    }
    // SAFETY: the handle comes from mpi4py's `Comm.py2f()` of a live communicator
    // (checked not null by the Python side) and MPI is initialised by mpi4py.
    let (rank, size) = unsafe {
        let raw = mpi::ffi::RSMPI_Comm_f2c(fint);
        let (mut rank, mut size) = (0, 0);
        mpi::ffi::MPI_Comm_rank(raw, &mut rank);
        mpi::ffi::MPI_Comm_size(raw, &mut size);
        (rank as usize, size as usize)
    };
    check_order(&order, size)?;
    if root >= size {
        return Err(errors::input(format!(
            "root: rank {root} is not in a communicator of {size} ranks"
        )));
    }
    let opts = CompositeOptions {
        op,
        order,
        rle,
        root,
    };
    let layout = match &tiles {
        Some(t) => Some(layout(t, pl.width, pl.height, size)?),
        None => None,
    };
    // The root's result goes straight into fresh numpy arrays.
    let out = if layout.is_none() && rank == root {
        Some(image_arrays::<P>(py, pl.width, pl.height)?)
    } else {
        None
    };
    let mut out_rw = out.as_ref().map(|(c, d)| (c.readwrite(), d.readwrite()));
    let out_planes = out_rw.as_mut().map(|(c, d)| planes_mut::<P>(c, d));
    // The private duplicate of the caller's communicator (made by the first composite
    // over it, then cached on it: `comm_cache`) is looked up and used on this thread
    // with the GIL released.
    let tile = py.allow_threads(move || -> PyResult<Option<Layer<P>>> {
        // SAFETY: as above; every rank calls `composite` together, as a first
        // composite's duplicate requires, and the cached duplicate outlives this call
        // (it is freed only with the caller's communicator or at MPI_Finalize).
        let comm = unsafe {
            let (raw, _) = comm_cache::private_comm(mpi::ffi::RSMPI_Comm_f2c(fint));
            MpiComm::from_raw_borrowed(raw, Duration::from_secs_f64(timeout))
        };
        let failed = |e: irradia_parallel::comm::CommError| {
            pyo3::exceptions::PyRuntimeError::new_err(e.to_string())
        };
        // The working layer: the last call's (memory already mapped). With a depth plane
        // (and no tiles) the compositor reads the arrays in place and copies into it
        // only what it keeps (`composite_from`); otherwise it is filled from the arrays
        // first.
        let mut layer = P::kept()
            .with(|k| k.borrow_mut().take())
            .unwrap_or_else(|| Layer {
                width: 0,
                height: 0,
                color: Vec::new(),
                depth: Vec::new(),
            });
        let (w, h) = (pl.width, pl.height);
        let in_place = layout.is_none() && pl.depth.is_some();
        if in_place {
            pl.check_depth()?;
        } else {
            pl.copy_into(0, &mut layer)?;
        }
        match &layout {
            None => {
                let (layer, _) = if in_place {
                    composite::composite_from(
                        &comm,
                        strategy,
                        pl.layer(0, &[]),
                        layer,
                        ActiveRect::full(w, h),
                        &opts,
                        out_planes,
                    )
                } else {
                    composite::composite_into(
                        &comm,
                        strategy,
                        layer,
                        ActiveRect::full(w, h),
                        &opts,
                        out_planes,
                    )
                }
                .map_err(failed)?;
                P::kept().with(|k| *k.borrow_mut() = Some(layer));
                Ok(None)
            }
            Some(l) => {
                display_tiles::composite_to_tiles(&comm, strategy, layer, l, &opts).map_err(failed)
            }
        }
    })?;
    drop(out_rw);
    if let Some(t) = tile {
        return Ok(Some(layer_arrays(py, &t)?));
    }
    Ok(out.map(|(c, d)| (c.into_any().unbind(), d.into_any().unbind())))
}

/// One layer per rank composited onto `root` (see `irradia.composite`).
#[pyfunction]
#[pyo3(signature = (color, depth, strategy, op, order, root, rle, fortran_comm, timeout, tiles=None))]
#[allow(clippy::too_many_arguments)]
pub fn _composite_mpi(
    py: Python<'_>,
    color: &Bound<'_, PyAny>,
    depth: Option<&Bound<'_, PyAny>>,
    strategy: &str,
    op: &str,
    order: Option<Vec<usize>>,
    root: usize,
    rle: bool,
    fortran_comm: i64,
    timeout: f64,
    tiles: Option<Vec<TileSpec>>,
) -> PyResult<Option<(PyObject, PyObject)>> {
    let depth = depth_array(depth)?;
    if color.extract::<PyReadonlyArrayDyn<'_, u8>>().is_ok() {
        run::<[u8; 4]>(
            py,
            color,
            depth,
            strategy,
            op,
            order,
            root,
            rle,
            fortran_comm,
            timeout,
            tiles,
        )
    } else if color.extract::<PyReadonlyArrayDyn<'_, f32>>().is_ok() {
        run::<[f32; 4]>(
            py,
            color,
            depth,
            strategy,
            op,
            order,
            root,
            rle,
            fortran_comm,
            timeout,
            tiles,
        )
    } else {
        Err(errors::input(
            "color: expected a uint8 or float32 numpy array (premultiplied RGBA)",
        ))
    }
}

/// How many private duplicates of callers' communicators this process has made (see
/// `comm_cache`): one per communicator composited over, not one per call.
#[pyfunction]
pub fn _comm_duplicates() -> usize {
    comm_cache::duplicates()
}
