//! Stopping a render from outside: a flag the caller sets (Ctrl-C in the Python
//! binding, a GUI's stop button) that the local sweep reads before each tile, as
//! Mitsuba 3's `render` checks its `should_stop` flag between blocks
//! ([`crate::driver::LocalSweep::cancel`]). Tiles already
//! running finish; the rest are skipped and [`crate::render`] returns
//! [`crate::RenderError::Cancelled`] instead of an image.

/// The error a cancelled sweep fails with (recognised by [`crate::render`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cancelled;

impl std::fmt::Display for Cancelled {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("the render was cancelled")
    }
}

impl std::error::Error for Cancelled {}
