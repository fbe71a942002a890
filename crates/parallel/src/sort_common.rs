//! What the three sorting schemes share: the serial reference render, framebuffer to
//! layer conversion, screen strips as regions, and the wire form of triangles.

use crate::composite::{Layer, FAR};
use irradia_raster::{ColorBuffer, ColorFormat, Framebuffer, Pipeline, Rect, Triangle, Vertex};
use std::ops::Range;

/// The contiguous block of `n` items that `rank` of `size` owns (object order).
pub fn block(n: usize, rank: usize, size: usize) -> Range<usize> {
    n * rank / size..n * (rank + 1) / size
}

/// Screen region of `rank`: horizontal strips (contiguous pixel spans, so a region
/// travels to the display as one span).
pub fn region(width: u32, height: u32, rank: usize, size: usize) -> Rect {
    let r = block(height as usize, rank, size);
    Rect::new(0, r.start as u32, width, r.end as u32)
}

/// Pixel span of a region.
pub fn span(r: &Rect, width: u32) -> Range<usize> {
    (r.y0 * width) as usize..(r.y1 * width) as usize
}

/// A cleared RGBA8 framebuffer for `p`.
pub fn framebuffer(p: &Pipeline) -> Framebuffer {
    Framebuffer::new(p.width, p.height, ColorFormat::Rgba8).expect("pipeline size was checked")
}

/// The framebuffer as a compositing layer (depth 1 = cleared = background).
pub fn to_layer(fb: &Framebuffer) -> Layer<[u8; 4]> {
    let color = match &fb.color {
        ColorBuffer::Rgba8(c) => c.clone(),
        ColorBuffer::Rgba32F(c) => c
            .iter()
            .map(|p| irradia_raster::framebuffer::to_rgba8(*p))
            .collect(),
        ColorBuffer::Id(ids) => ids.iter().map(|i| i.to_le_bytes()).collect(),
    };
    let depth = fb
        .depth
        .iter()
        .map(|&d| if d >= 1.0 { FAR } else { d })
        .collect();
    Layer {
        width: fb.width(),
        height: fb.height(),
        color,
        depth,
    }
}

/// The serial render: every triangle through one pipeline, in order.
pub fn serial(p: &Pipeline, tris: &[Triangle]) -> Layer<[u8; 4]> {
    let mut fb = framebuffer(p);
    p.render_triangles(tris, &mut fb)
        .expect("framebuffer matches the pipeline");
    to_layer(&fb)
}

/// Bytes of one triangle on the wire: three vertices of 12 floats, the id and the
/// material index.
pub const TRIANGLE_BYTES: usize = 3 * 12 * 4 + 8;

pub fn write_triangle(t: &Triangle, out: &mut Vec<u8>) {
    for v in &t.v {
        let f = [
            v.position.x,
            v.position.y,
            v.position.z,
            v.normal.x,
            v.normal.y,
            v.normal.z,
            v.color[0],
            v.color[1],
            v.color[2],
            v.color[3],
            v.uv.x,
            v.uv.y,
        ];
        out.extend_from_slice(bytemuck::cast_slice(&f));
    }
    out.extend_from_slice(&t.id.to_le_bytes());
    out.extend_from_slice(&t.material.to_le_bytes());
}

pub fn read_triangles(buf: &[u8]) -> Option<Vec<Triangle>> {
    if !buf.len().is_multiple_of(TRIANGLE_BYTES) {
        return None;
    }
    Some(
        buf.chunks_exact(TRIANGLE_BYTES)
            .map(|c| {
                let f = |i: usize| f32::from_le_bytes(c[4 * i..4 * i + 4].try_into().unwrap());
                let v = |k: usize| {
                    let b = k * 12;
                    Vertex {
                        position: glam::Vec3::new(f(b), f(b + 1), f(b + 2)),
                        normal: glam::Vec3::new(f(b + 3), f(b + 4), f(b + 5)),
                        color: [f(b + 6), f(b + 7), f(b + 8), f(b + 9)],
                        uv: glam::Vec2::new(f(b + 10), f(b + 11)),
                    }
                };
                let word = |at: usize| u32::from_le_bytes(c[at..at + 4].try_into().unwrap());
                Triangle {
                    v: [v(0), v(1), v(2)],
                    id: word(TRIANGLE_BYTES - 8),
                    material: word(TRIANGLE_BYTES - 4),
                }
            })
            .collect(),
    )
}

/// Rows `[y0, y1]` (inclusive, conservative) a triangle can touch, or `None` when it
/// crosses the eye plane (then it may touch any row).
pub fn screen_rows(p: &Pipeline, t: &Triangle) -> Option<(f32, f32)> {
    let m = p.view.view_proj();
    let mut lo = f32::INFINITY;
    let mut hi = f32::NEG_INFINITY;
    for v in &t.v {
        let c = m * v.position.extend(1.0);
        if c.w <= 1e-6 {
            return None;
        }
        let y = (1.0 - c.y / c.w) * 0.5 * p.height as f32;
        lo = lo.min(y);
        hi = hi.max(y);
    }
    Some((lo - 2.0, hi + 2.0))
}

/// Whether rows `[lo, hi]` meet region `r`.
pub fn rows_meet(lo: f32, hi: f32, r: &Rect) -> bool {
    hi >= r.y0 as f32 && lo <= r.y1 as f32
}
