//! `irradia.composite` over an mpi4py communicator (cargo feature `mpi`): the
//! communicator's Fortran handle (`comm.py2f()`) becomes a C handle (`MPI_Comm_f2c`),
//! is duplicated so Irradia's messages never meet the caller's, and wrapped as the
//! parallel crate's `MpiComm`, on which the compositors run exactly as under
//! `irradia parallel --comm mpi`.

use crate::composite::{
    check_order, layer_arrays, layers, layout, operator, strategy, Channels, TileSpec,
};
use crate::errors;
use irradia_parallel::comm::mpi::MpiComm;
use irradia_parallel::comm::Comm;
use irradia_parallel::composite::{self, CompositeOptions};
use irradia_parallel::display_tiles;
use numpy::PyReadonlyArrayDyn;
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
    let mut ls = layers::<P>(&c, depth.as_ref())?;
    if ls.len() != 1 {
        return Err(errors::input(
            "color: with a communicator each rank passes one layer of shape (height, width, 4)",
        ));
    }
    let layer = ls.pop().expect("one layer");
    let strategy = strategy(strategy_name)?;
    let op = operator(op)?;
    let fint = i32::try_from(fortran_comm)
        .map_err(|_| errors::input("comm: not an MPI communicator handle"))?;
    if !(timeout.is_finite() && timeout > 0.0) {
        return Err(errors::input(format!(
            "timeout: must be positive seconds (got {timeout})"
        )));
    }
    // The comm is made, used and freed on this thread with the GIL released (an MPI
    // communicator handle is not shared with other threads).
    let out = py.allow_threads(move || -> PyResult<_> {
        // SAFETY: the handle comes from mpi4py's `Comm.py2f()` of a live communicator
        // (checked not null by the Python side); MPI is initialised by mpi4py; every
        // rank calls `composite` together, as the duplicate requires.
        let comm = unsafe {
            let raw = mpi::ffi::RSMPI_Comm_f2c(fint);
            MpiComm::from_raw_dup(raw, Duration::from_secs_f64(timeout))
        };
        let size = comm.size();
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
        let failed = |e: irradia_parallel::comm::CommError| {
            pyo3::exceptions::PyRuntimeError::new_err(e.to_string())
        };
        match &tiles {
            None => composite::composite(&comm, strategy, layer, &opts).map_err(failed),
            Some(tiles) => {
                let l = layout(tiles, layer.width, layer.height, size)?;
                display_tiles::composite_to_tiles(&comm, strategy, layer, &l, &opts).map_err(failed)
            }
        }
    })?;
    out.map(|l| layer_arrays(py, &l)).transpose()
}

/// One layer per rank composited onto `root` (see `irradia.composite`).
#[pyfunction]
#[pyo3(signature = (color, depth, strategy, op, order, root, rle, fortran_comm, timeout, tiles=None))]
#[allow(clippy::too_many_arguments)]
pub fn _composite_mpi(
    py: Python<'_>,
    color: &Bound<'_, PyAny>,
    depth: Option<PyReadonlyArrayDyn<'_, f32>>,
    strategy: &str,
    op: &str,
    order: Option<Vec<usize>>,
    root: usize,
    rle: bool,
    fortran_comm: i64,
    timeout: f64,
    tiles: Option<Vec<TileSpec>>,
) -> PyResult<Option<(PyObject, PyObject)>> {
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
