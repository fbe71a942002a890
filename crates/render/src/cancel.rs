//! Stopping a render from outside: a flag the caller sets (Ctrl-C in the Python
//! binding, a GUI's stop button) that the local sweep reads before each tile, as
//! Mitsuba 3's `render` checks its `should_stop` flag between blocks. Tiles already
//! running finish; the rest are skipped and [`crate::render`] returns
//! [`crate::RenderError::Cancelled`] instead of an image.

use crate::driver::{sweep_local, PassWork, Sink, Sweep, SweepError, Tile, TileJob};
use crate::integrator::Integrator;
use std::sync::atomic::AtomicBool;

/// The error a cancelled sweep fails with (recognised by [`crate::render`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cancelled;

impl std::fmt::Display for Cancelled {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("the render was cancelled")
    }
}

impl std::error::Error for Cancelled {}

/// [`crate::driver::LocalSweep`] that stops once `cancel` is set.
#[derive(Clone, Copy, Debug)]
pub struct CancellableSweep<'c> {
    pub cancel: &'c AtomicBool,
}

impl Sweep for CancellableSweep<'_> {
    fn sweep<I: Integrator>(
        &mut self,
        job: &TileJob<'_, I>,
        tiles: &[Tile],
        sink: &mut Sink<'_>,
        work: PassWork,
        on_tile: &(dyn Fn(u64) + Sync),
    ) -> Result<(), SweepError> {
        sweep_local(job, tiles, sink, work, on_tile, Some(self.cancel))
    }
}
