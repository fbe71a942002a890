//! Sort-first rendering (lecture: "each rasterization unit assigned to an area of the
//! screen; each geometric unit coupled to its own rasterizer; must sort primitives
//! first"): every rank starts with a block of the application's triangles, finds the
//! screen regions each one's projected bounds meet *before* geometry processing, and
//! sends it there (all-to-all); each rank then runs the whole pipeline on what it
//! received, restricted to its region, and the regions are gathered at the display.
//! Received triangles are kept in source-rank order, which is the serial draw order.

use crate::comm::{Comm, CommError};
use crate::composite::{gather::gather, CompositeOptions, Layer, Operator};
use crate::frame::{
    block, framebuffer, read_triangles, region, rows_meet, screen_rows, span, to_layer,
    write_triangle,
};
use irradia_raster::{Pipeline, Triangle};

pub fn render<C: Comm>(
    comm: &C,
    p: &Pipeline,
    tris: &[Triangle],
    root: usize,
) -> Result<Option<Layer<[u8; 4]>>, CommError> {
    let (rank, n) = (comm.rank(), comm.size());
    comm.log().begin_stage("sort");
    let regions: Vec<_> = (0..n).map(|r| region(p.width, p.height, r, n)).collect();
    let mut out: Vec<Vec<u8>> = vec![Vec::new(); n];
    for t in &tris[block(tris.len(), rank, n)] {
        let rows = screen_rows(p, t);
        for (r, reg) in regions.iter().enumerate() {
            if rows.map_or(true, |(lo, hi)| rows_meet(lo, hi, reg)) {
                write_triangle(t, &mut out[r]);
            }
        }
    }
    comm.log().begin_stage("redistribute");
    let got = comm.all_to_all(&out)?;
    comm.log().begin_stage("render");
    let mut mine = Vec::new();
    for (src, buf) in got.iter().enumerate() {
        mine.extend(read_triangles(buf).ok_or(CommError::Malformed {
            rank: src,
            message: "not whole triangles".into(),
        })?);
    }
    let st = p.transform_and_light(&mine);
    let mut fb = framebuffer(p);
    p.rasterize(&st, &mut fb, Some(regions[rank]))
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
