//! A small z-buffered item-buffer rasterizer for convex polygons (pixel centres, edge
//! functions, nearest = largest 1/depth). The hemicube draws element ids with it.
//!
//! The software rasterizer of `crates/raster` is the project's general pipeline; this
//! buffer keeps only what the hemicube needs (an id per pixel, no shading) so that the
//! per-element cost is a few multiply-adds per covered pixel.

/// Depth and item per pixel.
pub struct ItemBuffer {
    pub width: usize,
    pub height: usize,
    /// 1/depth of the nearest polygon so far (0 = nothing).
    pub inv_depth: Vec<f32>,
    pub item: Vec<u32>,
}

pub const NO_ITEM: u32 = u32::MAX;

impl ItemBuffer {
    pub fn new(width: usize, height: usize) -> Self {
        Self {
            width,
            height,
            inv_depth: vec![0.0; width * height],
            item: vec![NO_ITEM; width * height],
        }
    }

    pub fn clear(&mut self) {
        self.inv_depth.fill(0.0);
        self.item.fill(NO_ITEM);
    }

    /// Draws a convex polygon given as `(x, y, 1/depth)` in pixel units (pixel `(i, j)`
    /// covers `[i, i+1) x [j, j+1)`; it is drawn when its centre is inside).
    pub fn draw(&mut self, pts: &[[f64; 3]], item: u32) {
        if pts.len() < 3 {
            return;
        }
        for k in 1..pts.len() - 1 {
            self.triangle(pts[0], pts[k], pts[k + 1], item);
        }
    }

    fn triangle(&mut self, a: [f64; 3], b: [f64; 3], c: [f64; 3], item: u32) {
        let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        if area == 0.0 || !area.is_finite() {
            return;
        }
        let (b, c, area) = if area < 0.0 {
            (c, b, -area)
        } else {
            (b, c, area)
        };
        let xmin = a[0].min(b[0]).min(c[0]).floor().max(0.0) as usize;
        let ymin = a[1].min(b[1]).min(c[1]).floor().max(0.0) as usize;
        let xmax = (a[0].max(b[0]).max(c[0]).ceil().min(self.width as f64)) as usize;
        let ymax = (a[1].max(b[1]).max(c[1]).ceil().min(self.height as f64)) as usize;
        if xmin >= xmax || ymin >= ymax {
            return;
        }
        let inv_area = 1.0 / area;
        // Evaluated in a canonical vertex order so that the two triangles sharing an
        // edge get exactly opposite values: a pixel centre on the edge goes to one of them.
        let edge = |p: [f64; 3], q: [f64; 3], x: f64, y: f64| {
            if (p[0], p[1]) > (q[0], q[1]) {
                -((p[0] - q[0]) * (y - q[1]) - (p[1] - q[1]) * (x - q[0]))
            } else {
                (q[0] - p[0]) * (y - p[1]) - (q[1] - p[1]) * (x - p[0])
            }
        };
        for y in ymin..ymax {
            let py = y as f64 + 0.5;
            for x in xmin..xmax {
                let px = x as f64 + 0.5;
                let w0 = edge(b, c, px, py);
                let w1 = edge(c, a, px, py);
                let w2 = edge(a, b, px, py);
                if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                    continue;
                }
                let z = ((w0 * a[2] + w1 * b[2] + w2 * c[2]) * inv_area) as f32;
                let k = y * self.width + x;
                if z > self.inv_depth[k] {
                    self.inv_depth[k] = z;
                    self.item[k] = item;
                }
            }
        }
    }
}
