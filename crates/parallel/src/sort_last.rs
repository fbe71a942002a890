//! Sort-last rendering (lecture: "couple rasterizers and geometric units; assign objects
//! to geometric units; composite results at end"; Molnar et al. 1994): each rank renders
//! its own block of the triangles over the whole screen, then the layers are composited
//! with colour and depth. Blocks follow the serial draw order, so the composite equals
//! the serial render bit for bit.

use crate::comm::{Comm, CommError};
use crate::composite::{self, CompositeOptions, Layer, Strategy};
use crate::frame::{block, framebuffer, to_layer};
use irradia_raster::{Pipeline, Triangle};

/// Renders and composites; the image arrives at `opts.root`.
pub fn render<C: Comm>(
    comm: &C,
    p: &Pipeline,
    tris: &[Triangle],
    strategy: Strategy,
    opts: &CompositeOptions,
) -> Result<Option<Layer<[u8; 4]>>, CommError> {
    let layer = render_layer(comm, p, tris);
    composite::composite(comm, strategy, layer, opts)
}

/// The render step alone (stage "render"): this rank's block of the triangles drawn
/// over the whole screen, as a layer to composite (with [`composite::composite`], or
/// onto a tiled display with [`crate::display_tiles::composite_to_tiles`]).
pub fn render_layer<C: Comm>(comm: &C, p: &Pipeline, tris: &[Triangle]) -> Layer<[u8; 4]> {
    comm.log().begin_stage("render");
    let mine = &tris[block(tris.len(), comm.rank(), comm.size())];
    let mut fb = framebuffer(p);
    p.render_triangles(mine, &mut fb)
        .expect("framebuffer matches the pipeline");
    to_layer(&fb)
}
