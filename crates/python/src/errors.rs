//! Irradia's errors as Python exceptions, with the command line's messages (file,
//! line and field for scene files): bad input raises [`IrradiaError`] (a subclass of
//! `ValueError`), a file that cannot be read or written raises `OSError`, Ctrl-C
//! raises `KeyboardInterrupt`. Nothing here panics: every library error maps to one.

use irradia_core::ImageError;
use irradia_radiosity::RadiosityError;
use irradia_render::RenderError;
use irradia_scene::SceneError;
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::PyErr;

pyo3::create_exception!(
    irradia,
    IrradiaError,
    PyValueError,
    "Bad input to Irradia (a scene file, an option, an unknown name), with the message \
     `irradia` prints: a scene error names its file, line and field. A ValueError."
);

/// Bad input, said in one line.
pub fn input(message: impl Into<String>) -> PyErr {
    IrradiaError::new_err(message.into())
}

/// A scene error: bad input is an [`IrradiaError`], an unreadable file an `OSError`.
pub fn scene(e: SceneError) -> PyErr {
    if e.is_bad_input() {
        IrradiaError::new_err(e.to_string())
    } else {
        PyOSError::new_err(e.to_string())
    }
}

/// A render error, split as `irradia render`'s exit codes split it (2: bad input).
pub fn render(e: RenderError) -> PyErr {
    use RenderError as E;
    match e {
        E::Image(e) => image(e),
        E::PixelOutside { .. } | E::Settings(_) | E::Resume(_) | E::TraceDirect => {
            IrradiaError::new_err(e.to_string())
        }
        E::CheckpointWrite(_) => PyOSError::new_err(e.to_string()),
        E::Cancelled => pyo3::exceptions::PyKeyboardInterrupt::new_err(e.to_string()),
        _ => PyRuntimeError::new_err(e.to_string()),
    }
}

/// An image error: a file that cannot be read or written is an `OSError`, a bad size
/// or extension an [`IrradiaError`].
pub fn image(e: ImageError) -> PyErr {
    match e {
        ImageError::File { .. } => PyOSError::new_err(e.to_string()),
        _ => IrradiaError::new_err(e.to_string()),
    }
}

/// A radiosity error: bad input or a failure while working.
pub fn radiosity(e: RadiosityError) -> PyErr {
    match e {
        RadiosityError::Input(m) => IrradiaError::new_err(m),
        RadiosityError::Failure(m) => PyRuntimeError::new_err(m),
    }
}
