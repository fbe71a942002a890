//! Test scenes for compositing: screen-aligned rectangles with planar depth, drawn with
//! a tiny z-buffer (opaque) or a sorted fragment list (transparent). Depths are
//! quantised so that exact ties between objects of different ranks happen often.
#![allow(dead_code)]

use irradia_core::Rng;
use irradia_parallel::composite::{Layer, Pixel};

pub const W: u32 = 64;
pub const H: u32 = 48;

#[derive(Clone, Debug)]
pub struct Rect {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
    pub d0: f32,
    pub dx: f32,
    pub dy: f32,
    pub rgba: [u8; 4],
}

impl Rect {
    pub fn depth(&self, x: u32, y: u32) -> f32 {
        let d = self.d0 + self.dx * (x - self.x0) as f32 + self.dy * (y - self.y0) as f32;
        (d * 4.0).round() / 4.0
    }
}

pub fn random_rects(count: usize, seed: u64, alpha: u8) -> Vec<Rect> {
    let mut rng = Rng::new(seed, 7);
    (0..count)
        .map(|_| {
            let x0 = (rng.next_f32() * (W - 8) as f32) as u32;
            let y0 = (rng.next_f32() * (H - 8) as f32) as u32;
            let x1 = (x0 + 4 + (rng.next_f32() * 30.0) as u32).min(W);
            let y1 = (y0 + 4 + (rng.next_f32() * 24.0) as u32).min(H);
            let c = |r: &mut Rng| (40.0 + r.next_f32() * 215.0) as u8;
            Rect {
                x0,
                y0,
                x1,
                y1,
                d0: 1.0 + (rng.next_f32() * 8.0).floor(),
                dx: (rng.next_f32() - 0.5) * 0.2,
                dy: (rng.next_f32() - 0.5) * 0.2,
                rgba: [c(&mut rng), c(&mut rng), c(&mut rng), alpha],
            }
        })
        .collect()
}

/// Conversion of the test colour to the pixel type (premultiplied).
pub trait TestPixel: Pixel {
    fn from_rgba(c: [u8; 4]) -> Self;
}
impl TestPixel for [u8; 4] {
    fn from_rgba(c: [u8; 4]) -> Self {
        let a = c[3] as u32;
        [
            (c[0] as u32 * a / 255) as u8,
            (c[1] as u32 * a / 255) as u8,
            (c[2] as u32 * a / 255) as u8,
            c[3],
        ]
    }
}
impl TestPixel for [f32; 4] {
    fn from_rgba(c: [u8; 4]) -> Self {
        let a = c[3] as f32 / 255.0;
        [
            c[0] as f32 / 255.0 * a,
            c[1] as f32 / 255.0 * a,
            c[2] as f32 / 255.0 * a,
            a,
        ]
    }
}

/// Opaque z-buffer render of `rects` in order (strict `<` depth test).
pub fn render_opaque<P: TestPixel>(rects: &[&Rect]) -> Layer<P> {
    let mut l = Layer::<P>::new(W, H);
    for r in rects {
        for y in r.y0..r.y1 {
            for x in r.x0..r.x1 {
                let i = (y * W + x) as usize;
                let d = r.depth(x, y);
                if d < l.depth[i] {
                    l.depth[i] = d;
                    l.color[i] = P::from_rgba(r.rgba);
                }
            }
        }
    }
    l
}

/// Transparent render: per pixel, fragments sorted by depth and composited front to back.
pub fn render_transparent<P: TestPixel>(rects: &[&Rect], from_behind: bool) -> Layer<P> {
    let mut l = Layer::<P>::new(W, H);
    for y in 0..H {
        for x in 0..W {
            let mut frags: Vec<(f32, P)> = rects
                .iter()
                .filter(|r| x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1)
                .map(|r| (r.d0, P::from_rgba(r.rgba)))
                .collect();
            frags.sort_by(|a, b| a.0.total_cmp(&b.0));
            if from_behind {
                frags.reverse();
            }
            let i = (y * W + x) as usize;
            for (d, c) in frags {
                l.color[i] = P::over(l.color[i], c);
                l.depth[i] = l.depth[i].min(d);
            }
        }
    }
    l
}

/// The objects of `rank` when `count` objects are dealt out in contiguous blocks.
pub fn block<T>(items: &[T], rank: usize, ranks: usize) -> Vec<&T> {
    let n = items.len();
    items[n * rank / ranks..n * (rank + 1) / ranks]
        .iter()
        .collect()
}
