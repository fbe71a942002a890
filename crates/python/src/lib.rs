//! irradia-python: Irradia from Python (the `irradia` package), a numpy-native binding
//! built with PyO3 (abi3: one wheel for CPython 3.9 and later) and rust-numpy, packaged
//! by maturin (`pip install ./crates/python`). Every function calls the library crates
//! the `irradia` command calls, so an array equals the command's image bit for bit and
//! an error carries the command's message. Rust work runs with the GIL released.
//!
//! - [`scene`]: `load`, `builtin`, `load_dict` (through `_load_json`), the `Scene`
//!   class with its camera, materials and lights;
//! - [`render`]: `Scene.render` (AOVs, progress, Ctrl-C), [`raycast`]: `Scene.cast_rays`;
//! - [`radiosity`]: `form_factor`, `form_factor_cases`, `radiosity`;
//! - [`composite`] (and `composite_mpi` with feature `mpi`): sort-last compositing;
//! - [`image`]: `read_image`, `write_image`; [`errors`]: the exceptions;
//! - [`pool`]: the memory of the composited images, kept mapped between calls.
//!
//! The Python half (`python/irradia/__init__.py`) adds `load_dict`, `composite` (the
//! mpi4py glue) and the tqdm bar; `python/irradia/__init__.pyi` has the type stubs.

#[cfg(feature = "mpi")]
pub mod comm_cache;
pub mod composite;
#[cfg(feature = "mpi")]
pub mod composite_mpi;
pub mod convert;
pub mod errors;
pub mod image;
pub mod pool;
pub mod radiosity;
pub mod raycast;
pub mod render;
pub mod scene;

use pyo3::prelude::*;

/// The compiled half of the `irradia` package.
#[pymodule]
fn _irradia(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("IrradiaError", m.py().get_type::<errors::IrradiaError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("INVALID_ID", raycast::INVALID_ID)?;
    m.add_class::<scene::PyScene>()?;
    m.add_function(wrap_pyfunction!(scene::load, m)?)?;
    m.add_function(wrap_pyfunction!(scene::_load_json, m)?)?;
    m.add_function(wrap_pyfunction!(scene::builtin, m)?)?;
    m.add_function(wrap_pyfunction!(scene::builtins, m)?)?;
    m.add_function(wrap_pyfunction!(image::read_image, m)?)?;
    m.add_function(wrap_pyfunction!(image::write_image, m)?)?;
    m.add_function(wrap_pyfunction!(radiosity::form_factor, m)?)?;
    m.add_function(wrap_pyfunction!(radiosity::form_factor_cases, m)?)?;
    m.add_function(wrap_pyfunction!(radiosity::radiosity, m)?)?;
    m.add_function(wrap_pyfunction!(composite::_composite_serial, m)?)?;
    m.add_function(wrap_pyfunction!(composite::mpi_available, m)?)?;
    m.add_function(wrap_pyfunction!(composite::display_grid, m)?)?;
    m.add_function(wrap_pyfunction!(pool::_pool_stats, m)?)?;
    m.add_class::<pool::PooledBuffer>()?;
    #[cfg(feature = "mpi")]
    m.add_function(wrap_pyfunction!(composite_mpi::_composite_mpi, m)?)?;
    #[cfg(feature = "mpi")]
    m.add_function(wrap_pyfunction!(composite_mpi::_comm_duplicates, m)?)?;
    Ok(())
}
