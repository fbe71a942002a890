//! Sort-first rendering (lecture: "each rasterization unit assigned to an area of the
//! screen; each geometric unit coupled to its own rasterizer; must sort primitives
//! first"): every rank starts with a block of the application's triangles, finds the
//! screen regions each one's projected bounds meet *before* geometry processing, and
//! sends it there (all-to-all); each rank then runs the whole pipeline on what it
//! received, restricted to its regions, and the regions are gathered at the display.
//! Received triangles are kept in source-rank order, which is the serial draw order.
//!
//! Regions. With one region per rank the screen is cut into horizontal strips. Strips
//! balance badly when the primitives crowd into part of the screen (the lecture's
//! "load balancing" problem of sort-first), so the screen can instead be cut into a grid
//! of `K` tiles per rank ([`Tiling`]), dealt out either interleaved (tile `i` to rank
//! `i mod n`, the static scheme of Molnar et al. 1994) or by an estimated cost: every
//! rank estimates, from the screen bounds of its own triangles, the work each tile will
//! take, the estimates are summed at rank 0, which deals the tiles out largest first to
//! the least loaded rank (Graham's LPT rule) and broadcasts the assignment
//! (Mueller 1995, "The sort-first rendering architecture for high-performance graphics").

use crate::comm::{Comm, CommError};
use crate::composite::{rle, Layer, Operator, Pixel};
use crate::sort_common::{block, framebuffer, read_triangles, region, to_layer, write_triangle};
use irradia_raster::{Pipeline, Rect, Triangle};

/// How tiles are dealt out to ranks.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Assign {
    /// Tile `i` goes to rank `i mod n`.
    Interleaved,
    /// Largest estimated cost first, to the rank with the least estimated work so far.
    Cost,
}

impl Assign {
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "interleaved" => Some(Assign::Interleaved),
            "cost" => Some(Assign::Cost),
            _ => None,
        }
    }
    pub fn name(&self) -> &'static str {
        match self {
            Assign::Interleaved => "interleaved",
            Assign::Cost => "cost",
        }
    }
}

/// How the screen is cut into regions for sort-first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Tiling {
    /// Regions per rank: 1 gives one horizontal strip per rank.
    pub per_rank: usize,
    pub assign: Assign,
}

impl Tiling {
    /// One horizontal strip per rank.
    pub const STRIPS: Tiling = Tiling {
        per_rank: 1,
        assign: Assign::Interleaved,
    };

    pub fn is_strips(&self) -> bool {
        self.per_rank <= 1
    }
}

impl Default for Tiling {
    fn default() -> Self {
        Tiling::STRIPS
    }
}

/// The screen's regions and the rank owning each.
#[derive(Clone, Debug, PartialEq)]
pub struct TileLayout {
    /// Row-major grid of tiles (strips are a grid of one column).
    pub tiles: Vec<Rect>,
    pub owner: Vec<usize>,
    /// Column boundaries (columns + 1 of them) and row boundaries, in pixels.
    xs: Vec<u32>,
    ys: Vec<u32>,
}

impl TileLayout {
    /// One horizontal strip per rank (strip `r` to rank `r`).
    pub fn strips(width: u32, height: u32, ranks: usize) -> Self {
        let tiles: Vec<Rect> = (0..ranks)
            .map(|r| region(width, height, r, ranks))
            .collect();
        let mut ys: Vec<u32> = tiles.iter().map(|t| t.y0).collect();
        ys.push(height);
        Self {
            tiles,
            owner: (0..ranks).collect(),
            xs: vec![0, width],
            ys,
        }
    }

    /// The regions of `tiling` for `ranks` ranks, before assignment (owners interleaved).
    pub fn unassigned(width: u32, height: u32, ranks: usize, tiling: Tiling) -> Self {
        if tiling.is_strips() {
            return Self::strips(width, height, ranks);
        }
        let tiles = grid(width, height, tiling.per_rank * ranks);
        let owner = (0..tiles.len()).map(|i| i % ranks).collect();
        let mut xs: Vec<u32> = tiles
            .iter()
            .take_while(|t| t.y0 == tiles[0].y0)
            .map(|t| t.x0)
            .collect();
        xs.push(width);
        let mut ys: Vec<u32> = tiles.iter().step_by(xs.len() - 1).map(|t| t.y0).collect();
        ys.push(height);
        Self {
            tiles,
            owner,
            xs,
            ys,
        }
    }

    /// Indices of the tiles a screen box meets (the same test as [`meets`]), found from
    /// the grid's boundaries in logarithmic time rather than by testing every tile.
    pub fn meeting(&self, b: &ScreenBox) -> impl Iterator<Item = usize> {
        let (cols, rows) = (self.xs.len() - 1, self.ys.len() - 1);
        let (c0, c1, r0, r1) = match b {
            None => (0, cols, 0, rows),
            Some(b) => (
                self.xs[1..].partition_point(|&x| (x as f32) < b[0]),
                self.xs[..cols].partition_point(|&x| (x as f32) <= b[2]),
                self.ys[1..].partition_point(|&y| (y as f32) < b[1]),
                self.ys[..rows].partition_point(|&y| (y as f32) <= b[3]),
            ),
        };
        (r0..r1.max(r0)).flat_map(move |j| (c0..c1.max(c0)).map(move |i| j * cols + i))
    }

    /// The regions of `tiling`, dealt out by `costs` (one per tile) when the tiling
    /// asks for it.
    pub fn assigned(width: u32, height: u32, ranks: usize, tiling: Tiling, costs: &[f64]) -> Self {
        let mut l = Self::unassigned(width, height, ranks, tiling);
        if !tiling.is_strips() && tiling.assign == Assign::Cost {
            l.owner = deal_by_cost(costs, ranks);
        }
        l
    }

    /// The tiles of `rank`, in tile order.
    pub fn mine(&self, rank: usize) -> impl Iterator<Item = &Rect> + '_ {
        self.tiles
            .iter()
            .zip(&self.owner)
            .filter(move |(_, &o)| o == rank)
            .map(|(t, _)| t)
    }

    /// Sum of `costs` (one per tile) per rank.
    pub fn rank_costs(&self, costs: &[f64], ranks: usize) -> Vec<f64> {
        let mut c = vec![0.0; ranks];
        for (&o, &x) in self.owner.iter().zip(costs) {
            c[o] += x;
        }
        c
    }
}

/// Largest to smallest over the mean of per-rank loads (1 = perfect balance).
pub fn imbalance(loads: &[f64]) -> f64 {
    let mean = loads.iter().sum::<f64>() / loads.len().max(1) as f64;
    let max = loads.iter().cloned().fold(0.0, f64::max);
    if mean > 0.0 {
        max / mean
    } else {
        1.0
    }
}

/// About `count` tiles in a grid of near-square tiles covering the screen (at least
/// `count`, fewer only when the screen has fewer pixels).
pub fn grid(width: u32, height: u32, count: usize) -> Vec<Rect> {
    let count = count.max(1) as f64;
    let rows = ((count * height as f64 / width.max(1) as f64).sqrt().round() as u32)
        .clamp(1, height.max(1));
    let cols = ((count / rows as f64).ceil() as u32).clamp(1, width.max(1));
    let mut tiles = Vec::with_capacity((rows * cols) as usize);
    for j in 0..rows {
        let y = block(height as usize, j as usize, rows as usize);
        for i in 0..cols {
            let x = block(width as usize, i as usize, cols as usize);
            tiles.push(Rect::new(
                x.start as u32,
                y.start as u32,
                x.end as u32,
                y.end as u32,
            ));
        }
    }
    tiles
}

/// Graham's LPT rule: tiles by decreasing cost, each to the least loaded rank (ties to
/// the lower tile index and the lower rank, so every rank computes the same answer).
pub fn deal_by_cost(costs: &[f64], ranks: usize) -> Vec<usize> {
    let mut order: Vec<usize> = (0..costs.len()).collect();
    order.sort_by(|&a, &b| costs[b].total_cmp(&costs[a]).then(a.cmp(&b)));
    let mut load = vec![0.0f64; ranks.max(1)];
    let mut owner = vec![0; costs.len()];
    for t in order {
        let r = (0..load.len())
            .min_by(|&a, &b| load[a].total_cmp(&load[b]).then(a.cmp(&b)))
            .expect("at least one rank");
        owner[t] = r;
        load[r] += costs[t];
    }
    owner
}

/// A conservative screen box `[x0, x1] x [y0, y1]` in pixels (2 pixels of margin), or
/// `None` when the triangle crosses the eye plane (then it may touch any pixel).
pub type ScreenBox = Option<[f32; 4]>;

/// The screen box of a triangle's projection.
pub fn triangle_box(p: &Pipeline, t: &Triangle) -> ScreenBox {
    points_box(p, t.v.iter().map(|v| v.position))
}

/// The screen box of the projections of `points`.
pub fn points_box(p: &Pipeline, points: impl IntoIterator<Item = glam::Vec3>) -> ScreenBox {
    let m = p.view.view_proj();
    let mut b = [
        f32::INFINITY,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NEG_INFINITY,
    ];
    for q in points {
        let c = m * q.extend(1.0);
        if c.w.is_nan() || c.w <= 1e-6 {
            return None;
        }
        let x = (c.x / c.w + 1.0) * 0.5 * p.width as f32;
        let y = (1.0 - c.y / c.w) * 0.5 * p.height as f32;
        b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
    }
    Some([b[0] - 2.0, b[1] - 2.0, b[2] + 2.0, b[3] + 2.0])
}

/// Pixels of `r` the box covers (all of them for `None`).
pub fn overlap(b: &ScreenBox, r: &Rect) -> f64 {
    let full = (r.x1 - r.x0) as f64 * (r.y1 - r.y0) as f64;
    let Some(b) = b else { return full };
    let w = (b[2].min(r.x1 as f32) - b[0].max(r.x0 as f32)).max(0.0) as f64;
    let h = (b[3].min(r.y1 as f32) - b[1].max(r.y0 as f32)).max(0.0) as f64;
    w * h
}

/// Whether the box meets the region.
pub fn meets(b: &ScreenBox, r: &Rect) -> bool {
    match b {
        None => true,
        Some(b) => {
            b[2] >= r.x0 as f32 && b[0] <= r.x1 as f32 && b[3] >= r.y0 as f32 && b[1] <= r.y1 as f32
        }
    }
}

/// Estimated rasterization work per tile for `tris`: one unit per triangle that meets
/// the tile (setup) plus its covered bounding-box pixels over 25 (fill; a pixel costs
/// about a twenty-fifth of a triangle setup in `crates/raster`).
pub fn raster_costs(p: &Pipeline, tris: &[Triangle], layout: &TileLayout) -> Vec<f64> {
    let mut c = vec![0.0; layout.tiles.len()];
    for t in tris {
        let b = triangle_box(p, t);
        for k in layout.meeting(&b) {
            c[k] += 1.0 + overlap(&b, &layout.tiles[k]) / 25.0;
        }
    }
    c
}

/// The layout of `tiling` for the raster pipeline: with cost assignment, every rank
/// estimates the cost of its own block of triangles, rank `root` sums the estimates,
/// deals the tiles out and broadcasts the owners.
pub fn raster_layout<C: Comm>(
    comm: &C,
    p: &Pipeline,
    tris: &[Triangle],
    tiling: Tiling,
    root: usize,
) -> Result<TileLayout, CommError> {
    let (rank, n) = (comm.rank(), comm.size());
    let mut layout = TileLayout::unassigned(p.width, p.height, n, tiling);
    if tiling.is_strips() || tiling.assign != Assign::Cost {
        return Ok(layout);
    }
    let mine = raster_costs(p, &tris[block(tris.len(), rank, n)], &layout);
    let all = comm.gather(root, bytemuck::cast_slice(&mine))?;
    let mut owners = Vec::new();
    if rank == root {
        let mut total = vec![0.0f64; layout.tiles.len()];
        for (src, buf) in all.iter().enumerate() {
            if buf.len() != total.len() * 8 {
                return Err(CommError::Malformed {
                    rank: src,
                    message: "tile cost estimates of the wrong length".into(),
                });
            }
            for (k, c) in buf.chunks_exact(8).enumerate() {
                total[k] += f64::from_le_bytes(c.try_into().expect("8 bytes"));
            }
        }
        owners = deal_by_cost(&total, n)
            .into_iter()
            .map(|o| o as u32)
            .collect::<Vec<u32>>();
    }
    let got = comm.broadcast(root, bytemuck::cast_slice(&owners))?;
    if got.len() != layout.tiles.len() * 4 {
        return Err(CommError::Malformed {
            rank: root,
            message: "tile owners of the wrong length".into(),
        });
    }
    layout.owner = got
        .chunks_exact(4)
        .map(|c| (u32::from_le_bytes(c.try_into().expect("4 bytes")) as usize).min(n - 1))
        .collect();
    Ok(layout)
}

/// Sort-first with one strip per rank.
pub fn render<C: Comm>(
    comm: &C,
    p: &Pipeline,
    tris: &[Triangle],
    root: usize,
) -> Result<Option<Layer<[u8; 4]>>, CommError> {
    render_tiled(comm, p, tris, root, Tiling::STRIPS)
}

/// Sort-first with the regions of `tiling`; the image arrives at `root`.
pub fn render_tiled<C: Comm>(
    comm: &C,
    p: &Pipeline,
    tris: &[Triangle],
    root: usize,
    tiling: Tiling,
) -> Result<Option<Layer<[u8; 4]>>, CommError> {
    render_tiled_layout(comm, p, tris, root, tiling).map(|(img, _)| img)
}

/// The image (at the root) and the layout the ranks agreed on.
pub type TiledFrame = (Option<Layer<[u8; 4]>>, TileLayout);

/// [`render_tiled`], also returning the layout the ranks agreed on.
pub fn render_tiled_layout<C: Comm>(
    comm: &C,
    p: &Pipeline,
    tris: &[Triangle],
    root: usize,
    tiling: Tiling,
) -> Result<TiledFrame, CommError> {
    let (rank, n) = (comm.rank(), comm.size());
    comm.log().begin_stage("sort");
    let layout = raster_layout(comm, p, tris, tiling, root)?;
    let mut out: Vec<Vec<u8>> = vec![Vec::new(); n];
    let mut sent_to = vec![usize::MAX; n];
    for (i, t) in tris[block(tris.len(), rank, n)].iter().enumerate() {
        let b = triangle_box(p, t);
        for k in layout.meeting(&b) {
            let o = layout.owner[k];
            if sent_to[o] != i {
                sent_to[o] = i;
                write_triangle(t, &mut out[o]);
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
    for r in layout.mine(rank) {
        p.rasterize(&st, &mut fb, Some(*r))
            .expect("framebuffer matches the pipeline");
    }
    let layer = to_layer(&fb);
    comm.log().begin_stage("gather");
    let img = gather_tiles(comm, &layer, &layout, root, Operator::Depth)?;
    comm.barrier()?;
    comm.log().end_stage();
    Ok((img, layout))
}

const TAG_TILES: u32 = 0x0ffe;

/// Gathers every rank's tiles of `layer` at `root`: one message per rank holding, tile
/// by tile and row by row, length-prefixed active-pixel run lengths ([`rle`]).
pub fn gather_tiles<P: Pixel, C: Comm>(
    comm: &C,
    layer: &Layer<P>,
    layout: &TileLayout,
    root: usize,
    op: Operator,
) -> Result<Option<Layer<P>>, CommError> {
    let w = layer.width as usize;
    let rows = |rank: usize| {
        layout
            .mine(rank)
            .flat_map(move |r| {
                (r.y0..r.y1)
                    .map(move |y| y as usize * w + r.x0 as usize..y as usize * w + r.x1 as usize)
            })
            .collect::<Vec<_>>()
    };
    if comm.rank() != root {
        let mut msg = Vec::new();
        for span in rows(comm.rank()) {
            let piece = rle::encode(layer, span, op, true);
            msg.extend_from_slice(&(piece.len() as u32).to_le_bytes());
            msg.extend_from_slice(&piece);
        }
        comm.send(root, TAG_TILES, &msg)?;
        return Ok(None);
    }
    let mut out = Layer::new(layer.width, layer.height);
    for span in rows(root) {
        out.color[span.clone()].copy_from_slice(&layer.color[span.clone()]);
        out.depth[span.clone()].copy_from_slice(&layer.depth[span]);
    }
    for r in (0..comm.size()).filter(|&r| r != root) {
        let buf = comm.recv(r, TAG_TILES)?;
        let bad = |message: String| CommError::Malformed { rank: r, message };
        let mut at = 0;
        while at < buf.len() {
            let len = buf
                .get(at..at + 4)
                .map(|b| u32::from_le_bytes(b.try_into().expect("4 bytes")) as usize)
                .ok_or_else(|| bad("truncated tile header".into()))?;
            let piece = buf
                .get(at + 4..at + 4 + len)
                .ok_or_else(|| bad("truncated tile".into()))?;
            rle::apply(&mut out, piece, rle::Apply::Replace).map_err(bad)?;
            at += 4 + len;
        }
    }
    Ok(Some(out))
}
