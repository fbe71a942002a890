//! Parallel submission as in WireGL and Chromium (Humphreys et al. 2001, 2002): several
//! clients stream draw commands to the servers that own screen regions. Each client keeps,
//! per server, the graphics state that server last saw from it and sends a state change
//! only to a server that is about to draw with a different state ("lazy state update";
//! the lecture: "most of the gain ... is because Chromium and WireGL can group
//! state-changing commands separately from rendering commands"). Servers replay the
//! streams in client order, which is the serial draw order, so the image equals the
//! serial render. The state tracked here is the current colour, as `glColor`, and the
//! current material (an index into the pipeline's material table, as a bound material
//! or shader would be).

use crate::comm::{Comm, CommError};
use crate::composite::{gather::gather, CompositeOptions, Layer, Operator};
use crate::sort_common::{
    block, framebuffer, read_triangles, region, rows_meet, screen_rows, span, to_layer,
    write_triangle, TRIANGLE_BYTES,
};
use irradia_raster::{Pipeline, Triangle};

/// One draw command of a client: set the colour and material state, then draw
/// triangles with it.
#[derive(Clone, Debug, PartialEq)]
pub struct Batch {
    pub color: [f32; 4],
    /// Index into the pipeline's material table (`Pipeline::materials`).
    pub material: u32,
    pub triangles: Vec<Triangle>,
}

const OP_STATE: u8 = 1;
const OP_DRAW: u8 = 2;
/// Bytes of a state command: the opcode, the colour, the material index.
const STATE_BYTES: usize = 1 + 16 + 4;

/// How many state bytes the lazy tracking sent, against broadcasting every change.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SubmissionStats {
    pub state_bytes: u64,
    pub broadcast_state_bytes: u64,
    pub draw_bytes: u64,
}

/// Encodes a client's batches into one command stream per server.
pub fn encode_streams(
    p: &Pipeline,
    batches: &[Batch],
    servers: usize,
) -> (Vec<Vec<u8>>, SubmissionStats) {
    let regions: Vec<_> = (0..servers)
        .map(|r| region(p.width, p.height, r, servers))
        .collect();
    let mut out: Vec<Vec<u8>> = vec![Vec::new(); servers];
    let mut seen: Vec<Option<([f32; 4], u32)>> = vec![None; servers];
    let mut stats = SubmissionStats::default();
    for b in batches {
        stats.broadcast_state_bytes += (servers * STATE_BYTES) as u64;
        let state = (b.color, b.material);
        for t in &b.triangles {
            let rows = screen_rows(p, t);
            for (s, reg) in regions.iter().enumerate() {
                if !rows.is_none_or(|(lo, hi)| rows_meet(lo, hi, reg)) {
                    continue;
                }
                if seen[s] != Some(state) {
                    out[s].push(OP_STATE);
                    out[s].extend_from_slice(bytemuck::cast_slice(&b.color));
                    out[s].extend_from_slice(&b.material.to_le_bytes());
                    seen[s] = Some(state);
                    stats.state_bytes += STATE_BYTES as u64;
                }
                out[s].push(OP_DRAW);
                write_triangle(t, &mut out[s]);
                stats.draw_bytes += 1 + TRIANGLE_BYTES as u64;
            }
        }
    }
    (out, stats)
}

/// Replays a stream: the triangles with their vertex colours and material set from the
/// state.
pub fn decode_stream(buf: &[u8]) -> Option<Vec<Triangle>> {
    let mut color = [1.0f32; 4];
    let mut material = 0u32;
    let mut tris = Vec::new();
    let mut i = 0;
    while i < buf.len() {
        match buf[i] {
            OP_STATE if i + STATE_BYTES <= buf.len() => {
                color = bytemuck::pod_read_unaligned(&buf[i + 1..i + 17]);
                material = u32::from_le_bytes(buf[i + 17..i + 21].try_into().ok()?);
                i += STATE_BYTES;
            }
            OP_DRAW if i + 1 + TRIANGLE_BYTES <= buf.len() => {
                let mut t = read_triangles(&buf[i + 1..i + 1 + TRIANGLE_BYTES])?.pop()?;
                for v in t.v.iter_mut() {
                    v.color = color;
                }
                t.material = material;
                tris.push(t);
                i += 1 + TRIANGLE_BYTES;
            }
            _ => return None,
        }
    }
    Some(tris)
}

/// The batches drawn with their colour as vertex colour and their material (the serial
/// meaning).
pub fn flatten(batches: &[Batch]) -> Vec<Triangle> {
    batches
        .iter()
        .flat_map(|b| {
            b.triangles.iter().map(move |t| {
                let mut t = *t;
                for v in t.v.iter_mut() {
                    v.color = b.color;
                }
                t.material = b.material;
                t
            })
        })
        .collect()
}

/// An RGBA8 image layer, as the root receives it.
type Image8 = Layer<[u8; 4]>;

/// Every rank is a client (submitting its block of `batches`) and a server (owning a
/// strip of the screen); the image arrives at `root`.
pub fn render<C: Comm>(
    comm: &C,
    p: &Pipeline,
    batches: &[Batch],
    root: usize,
) -> Result<(Option<Image8>, SubmissionStats), CommError> {
    let (rank, n) = (comm.rank(), comm.size());
    comm.log().begin_stage("submit");
    let (streams, stats) = encode_streams(p, &batches[block(batches.len(), rank, n)], n);
    let got = comm.all_to_all(&streams)?;
    comm.log().begin_stage("render");
    let mut mine = Vec::new();
    for (src, buf) in got.iter().enumerate() {
        mine.extend(decode_stream(buf).ok_or(CommError::Malformed {
            rank: src,
            message: "bad command stream".into(),
        })?);
    }
    let reg = region(p.width, p.height, rank, n);
    let st = p.transform_and_light(&mine);
    let mut fb = framebuffer(p);
    p.rasterize(&st, &mut fb, Some(reg))
        .expect("framebuffer matches the pipeline");
    comm.log().begin_stage("gather");
    let opts = CompositeOptions {
        op: Operator::Depth,
        order: None,
        rle: true,
        root,
    };
    let img = gather(comm, &to_layer(&fb), span(&reg, p.width), &opts)?;
    comm.barrier()?;
    comm.log().end_stage();
    Ok((img, stats))
}
