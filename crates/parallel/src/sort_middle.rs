//! Sort-middle rendering (lecture: "geometric units and rasterization units decoupled;
//! each geometric unit can be assigned any group of objects; each rasterizer is assigned
//! to an area of the screen; must sort between stages"): every rank transforms and
//! lights its block of triangles, sends each screen-space triangle to the rasterizers
//! whose regions its bounds meet (all-to-all), and rasterizes what it received inside its
//! region; the regions are gathered at the display.

use crate::comm::{Comm, CommError};
use crate::composite::{gather::gather, CompositeOptions, Layer, Operator};
use crate::sort_common::{block, framebuffer, region, rows_meet, span, to_layer};
use irradia_raster::{Pipeline, ScreenTriangle, Triangle, SCREEN_TRIANGLE_BYTES};

pub fn render<C: Comm>(
    comm: &C,
    p: &Pipeline,
    tris: &[Triangle],
    root: usize,
) -> Result<Option<Layer<[u8; 4]>>, CommError> {
    let (rank, n) = (comm.rank(), comm.size());
    comm.log().begin_stage("geometry");
    let regions: Vec<_> = (0..n).map(|r| region(p.width, p.height, r, n)).collect();
    let screen = p.transform_and_light(&tris[block(tris.len(), rank, n)]);
    let mut out: Vec<Vec<u8>> = vec![Vec::new(); n];
    for t in &screen {
        let lo = t.v.iter().map(|v| v.y).fold(f32::INFINITY, f32::min) - 2.0;
        let hi = t.v.iter().map(|v| v.y).fold(f32::NEG_INFINITY, f32::max) + 2.0;
        for (r, reg) in regions.iter().enumerate() {
            if rows_meet(lo, hi, reg) {
                t.write_bytes(&mut out[r]);
            }
        }
    }
    comm.log().begin_stage("redistribute");
    let got = comm.all_to_all(&out)?;
    comm.log().begin_stage("render");
    let mut mine = Vec::new();
    for (src, buf) in got.iter().enumerate() {
        if buf.len() % SCREEN_TRIANGLE_BYTES != 0 {
            return Err(CommError::Malformed {
                rank: src,
                message: "not whole screen triangles".into(),
            });
        }
        mine.extend(
            buf.chunks_exact(SCREEN_TRIANGLE_BYTES)
                .filter_map(ScreenTriangle::read_bytes),
        );
    }
    let mut fb = framebuffer(p);
    p.rasterize(&mine, &mut fb, Some(regions[rank]))
        .expect("framebuffer matches the pipeline");
    let layer = to_layer(&fb);
    comm.log().begin_stage("gather");
    let opts = CompositeOptions {
        op: Operator::Depth,
        order: None,
        rle: true,
        root,
    };
    let img = gather(comm, &layer, span(&regions[rank], p.width), &opts)?;
    comm.barrier()?;
    comm.log().end_stage();
    Ok(img)
}
