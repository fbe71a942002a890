//! Sort-last image compositing: every rank holds a full-screen layer (colour + depth) of
//! its own objects; a strategy combines them so that each rank ends up owning a piece of
//! the final image, and [`gather`] collects the pieces at the display rank.
//!
//! The catalogue (one strategy per file, as IceT keeps `src/strategies/*.c`):
//! [`direct_send`], [`tree`], [`binary_swap`] (with folding for rank counts that are not
//! powers of two) and [`radix_k`]. Pixels travel as active-pixel run lengths ([`rle`]) so
//! that background costs (almost) nothing. The per-pixel operators are [`depth`] (opaque,
//! z-test) and [`over`] (ordered transparency, Porter-Duff "over" in a visibility order).
//! Every strategy's rounds (binary swap's swaps and fold, radix-k's and direct send's
//! group rounds, the tree's transfers) go through [`pairwise::transfer`], which sends
//! dense spans in place and in pieces into reused receive buffers, chooses run lengths
//! only when they pay ([`active`] finds the runs, skipping what lies outside the
//! layer's [`ActiveRect`]) and records where its time goes ([`profile`]).
//!
//! Ordering. Strategies work on *positions* 0..p, the ranks sorted in compositing order
//! (identity for depth; front to back for "over"). Every group a strategy forms holds a
//! contiguous run of positions, and the lower run is always "in front": for "over" that
//! is the visibility order, for depth it breaks ties the way a serial z-buffer with a
//! strict `<` test does when objects are drawn in rank order. That is why an opaque
//! composite equals the serial render bit for bit.

pub mod active;
pub mod binary_swap;
pub mod depth;
pub mod direct_send;
pub mod gather;
pub mod over;
pub mod pairwise;
pub mod profile;
pub mod radix_k;
pub mod rle;
pub mod tree;

pub use active::ActiveRect;

use crate::comm::{Comm, CommError};
use std::ops::Range;

/// A colour pixel with premultiplied alpha that compositing can move and blend.
pub trait Pixel: bytemuck::Pod + Send + Sync + PartialEq + std::fmt::Debug {
    /// The background (fully transparent black).
    const CLEAR: Self;
    /// Porter-Duff "over" with premultiplied alpha: `front + (1 - alpha_front) * back`.
    fn over(front: Self, back: Self) -> Self;
    /// True when this pixel is fully transparent black (inactive for "over").
    fn is_clear(&self) -> bool;
}

impl Pixel for [u8; 4] {
    const CLEAR: Self = [0; 4];
    #[inline]
    fn over(f: Self, b: Self) -> Self {
        let k = 255 - f[3] as u32;
        let mut o = [0u8; 4];
        for c in 0..4 {
            // exact rounding of f + b * (255 - fa) / 255
            let t = b[c] as u32 * k + 128;
            let v = f[c] as u32 + ((t + (t >> 8)) >> 8);
            o[c] = v.min(255) as u8;
        }
        o
    }
    #[inline]
    fn is_clear(&self) -> bool {
        u32::from_ne_bytes(*self) == 0
    }
}

impl Pixel for [f32; 4] {
    const CLEAR: Self = [0.0; 4];
    #[inline]
    fn over(f: Self, b: Self) -> Self {
        let k = 1.0 - f[3];
        [
            f[0] + k * b[0],
            f[1] + k * b[1],
            f[2] + k * b[2],
            f[3] + k * b[3],
        ]
    }
    #[inline]
    fn is_clear(&self) -> bool {
        self[0] == 0.0 && self[1] == 0.0 && self[2] == 0.0 && self[3] == 0.0
    }
}

/// Depth of a background pixel.
pub const FAR: f32 = f32::INFINITY;

/// A full-screen layer: colour (premultiplied RGBA) and depth, row-major from the top left.
#[derive(Clone, Debug, PartialEq)]
pub struct Layer<P> {
    pub width: u32,
    pub height: u32,
    pub color: Vec<P>,
    pub depth: Vec<f32>,
}

/// A layer in borrowed memory (colour and depth planes of `width * height` pixels).
#[derive(Clone, Copy, Debug)]
pub struct LayerRef<'a, P> {
    pub width: u32,
    pub height: u32,
    pub color: &'a [P],
    pub depth: &'a [f32],
}

impl<'a, P> From<&'a Layer<P>> for LayerRef<'a, P> {
    fn from(l: &'a Layer<P>) -> Self {
        LayerRef {
            width: l.width,
            height: l.height,
            color: &l.color,
            depth: &l.depth,
        }
    }
}

pub type Rgba8Layer = Layer<[u8; 4]>;
pub type Rgba32Layer = Layer<[f32; 4]>;

impl<P: Pixel> Layer<P> {
    /// A background layer (clear colour, depth at infinity).
    pub fn new(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Self {
            width,
            height,
            color: vec![P::CLEAR; n],
            depth: vec![FAR; n],
        }
    }

    pub fn len(&self) -> usize {
        self.color.len()
    }

    /// The layer as borrowed planes.
    pub fn view(&self) -> LayerRef<'_, P> {
        LayerRef {
            width: self.width,
            height: self.height,
            color: &self.color,
            depth: &self.depth,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.color.is_empty()
    }

    /// Fraction of pixels that are active under `op`.
    pub fn active_fraction(&self, op: Operator) -> f64 {
        let n = (0..self.len()).filter(|&i| op.active(self, i)).count();
        n as f64 / self.len().max(1) as f64
    }
}

/// How two layers combine.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Operator {
    /// Opaque: the nearer fragment wins; on a tie the one in front in compositing order.
    Depth,
    /// Transparent: Porter-Duff "over" in the compositing (visibility) order.
    Over,
}

impl Operator {
    /// Whether pixel `i` carries anything (inactive pixels are not sent).
    #[inline]
    pub fn active<'a, P: Pixel>(self, l: impl Into<LayerRef<'a, P>>, i: usize) -> bool {
        let l = l.into();
        match self {
            Operator::Depth => l.depth[i] != FAR,
            Operator::Over => !l.color[i].is_clear(),
        }
    }
}

/// The compositing strategies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Strategy {
    DirectSend,
    Tree,
    BinarySwap,
    /// Radix-k with rounds of at most `k` partners (Peterka et al. 2009).
    RadixK(usize),
}

impl Strategy {
    pub fn name(&self) -> String {
        match self {
            Strategy::DirectSend => "direct-send".into(),
            Strategy::Tree => "tree".into(),
            Strategy::BinarySwap => "binary-swap".into(),
            Strategy::RadixK(k) => format!("radix-{k}"),
        }
    }

    /// Parses `direct-send`, `tree`, `binary-swap`, `radix-k` (k = 4) or `radix-N`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "direct-send" => Some(Strategy::DirectSend),
            "tree" => Some(Strategy::Tree),
            "binary-swap" => Some(Strategy::BinarySwap),
            "radix-k" => Some(Strategy::RadixK(4)),
            _ => s
                .strip_prefix("radix-")
                .and_then(|k| k.parse().ok())
                .filter(|&k: &usize| k >= 2)
                .map(Strategy::RadixK),
        }
    }

    pub const ALL: [Strategy; 4] = [
        Strategy::DirectSend,
        Strategy::Tree,
        Strategy::BinarySwap,
        Strategy::RadixK(4),
    ];
}

/// Options of one composite.
#[derive(Clone, Debug)]
pub struct CompositeOptions {
    pub op: Operator,
    /// Compositing order: `order[position] = rank`, front first. `None` = rank order.
    pub order: Option<Vec<usize>>,
    /// Send active-pixel run lengths (true) or dense spans.
    pub rle: bool,
    /// The rank that receives the final image.
    pub root: usize,
}

impl Default for CompositeOptions {
    fn default() -> Self {
        Self {
            op: Operator::Depth,
            order: None,
            rle: true,
            root: 0,
        }
    }
}

/// The map between ranks and compositing positions.
#[derive(Clone, Debug)]
pub struct Order {
    rank_at: Vec<usize>,
    pos_of: Vec<usize>,
}

impl Order {
    pub fn new(size: usize, order: Option<&[usize]>) -> Self {
        let rank_at: Vec<usize> = match order {
            Some(o) => {
                assert_eq!(o.len(), size, "compositing order must list every rank once");
                o.to_vec()
            }
            None => (0..size).collect(),
        };
        let mut pos_of = vec![usize::MAX; size];
        for (p, &r) in rank_at.iter().enumerate() {
            assert!(
                r < size && pos_of[r] == usize::MAX,
                "order is not a permutation"
            );
            pos_of[r] = p;
        }
        Self { rank_at, pos_of }
    }
    #[inline]
    pub fn rank(&self, pos: usize) -> usize {
        self.rank_at[pos]
    }
    #[inline]
    pub fn pos(&self, rank: usize) -> usize {
        self.pos_of[rank]
    }
    pub fn len(&self) -> usize {
        self.rank_at.len()
    }
    pub fn is_empty(&self) -> bool {
        self.rank_at.is_empty()
    }
}

/// Splits `span` into `k` contiguous parts of nearly equal size.
pub fn split_span(span: &Range<usize>, k: usize) -> Vec<Range<usize>> {
    let n = span.len();
    (0..k)
        .map(|i| span.start + n * i / k..span.start + n * (i + 1) / k)
        .collect()
}

/// Tag space: each strategy round gets its own tag so stray messages never match.
pub(crate) const TAG_COMPOSITE: u32 = 0x100;

/// Runs `strategy`, gathers the final image at `opts.root` (`Some` there, `None`
/// elsewhere) and ends with a barrier, so a fault anywhere fails the frame on every rank. Stages "composite" and "gather" are recorded in the comm's log.
pub fn composite<P: Pixel, C: Comm>(
    comm: &C,
    strategy: Strategy,
    layer: Layer<P>,
    opts: &CompositeOptions,
) -> Result<Option<Layer<P>>, CommError> {
    let all = ActiveRect::full(layer.width, layer.height);
    composite_bounded(comm, strategy, layer, all, opts)
}

/// [`composite`] of a layer whose active pixels all lie inside `rect` (the screen
/// bounds of what this rank drew, as IceT's `icetBoundingBox` gives them; Moreland et
/// al. 2011): nothing outside the rectangle is read when looking for active runs.
pub fn composite_bounded<P: Pixel, C: Comm>(
    comm: &C,
    strategy: Strategy,
    layer: Layer<P>,
    rect: ActiveRect,
    opts: &CompositeOptions,
) -> Result<Option<Layer<P>>, CommError> {
    comm.log().begin_stage("composite");
    let mut rect = rect;
    let (layer, span) = reduce_tracked(comm, strategy, layer, &mut rect, opts)?;
    comm.log().begin_stage("gather");
    let out = gather::gather_bounded(comm, &layer, span, &rect, opts)?;
    // Frame barrier: every rank learns whether the frame completed everywhere.
    comm.barrier()?;
    comm.log().end_stage();
    Ok(out)
}

/// [`composite_bounded`] for a caller that composites frame after frame out of its own
/// memory (the Python binding's numpy arrays): the root's image is gathered straight
/// into `out` (its colour and depth planes, `layer.len()` pixels each, every pixel
/// written; `None` on the other ranks, see [`gather::gather_into`]), and the working
/// layer is handed back so that its buffers serve the next frame. Returns the layer and
/// whether `out` was written (this rank is `opts.root`).
pub fn composite_into<P: Pixel, C: Comm>(
    comm: &C,
    strategy: Strategy,
    layer: Layer<P>,
    rect: ActiveRect,
    opts: &CompositeOptions,
    out: Option<(&mut [P], &mut [f32])>,
) -> Result<(Layer<P>, bool), CommError> {
    assert!(
        rect.fits(layer.width, layer.height),
        "active rectangle {rect:?} off the {}x{} layer",
        layer.width,
        layer.height
    );
    comm.log().begin_stage("composite");
    let mut rect = rect;
    let (layer, span) = reduce_tracked(comm, strategy, layer, &mut rect, opts)?;
    comm.log().begin_stage("gather");
    let wrote = gather::gather_into(comm, &layer, span, &rect, opts, out)?;
    comm.barrier()?;
    comm.log().end_stage();
    Ok((layer, wrote))
}

/// [`composite_into`] of a layer still in the caller's memory, `src` (read in place:
/// the Python binding's numpy arrays), with `work` as working memory (resized to the
/// layer; what it holds does not matter, and it is handed back for the next frame).
/// Binary swap sends straight from `src` and copies into `work` only the half each rank
/// keeps in its first round ([`binary_swap::reduce_from`]); the other strategies start
/// from a copy of `src` in `work`.
pub fn composite_from<P: Pixel, C: Comm>(
    comm: &C,
    strategy: Strategy,
    src: LayerRef<'_, P>,
    mut work: Layer<P>,
    rect: ActiveRect,
    opts: &CompositeOptions,
    out: Option<(&mut [P], &mut [f32])>,
) -> Result<(Layer<P>, bool), CommError> {
    let n = src.width as usize * src.height as usize;
    assert!(
        src.color.len() == n && src.depth.len() == n,
        "composite: planes of {} and {} pixels for a {}x{} layer",
        src.color.len(),
        src.depth.len(),
        src.width,
        src.height
    );
    assert!(
        rect.fits(src.width, src.height),
        "active rectangle {rect:?} off the {}x{} layer",
        src.width,
        src.height
    );
    (work.width, work.height) = (src.width, src.height);
    work.color.resize(n, P::CLEAR);
    work.depth.resize(n, FAR);
    comm.log().begin_stage("composite");
    let mut rect = rect;
    let (layer, span) = match strategy {
        Strategy::BinarySwap => binary_swap::reduce_from(comm, work, Some(src), &mut rect, opts)?,
        _ => {
            work.color.copy_from_slice(src.color);
            work.depth.copy_from_slice(src.depth);
            reduce_tracked(comm, strategy, work, &mut rect, opts)?
        }
    };
    comm.log().begin_stage("gather");
    let wrote = gather::gather_into(comm, &layer, span, &rect, opts, out)?;
    comm.barrier()?;
    comm.log().end_stage();
    Ok((layer, wrote))
}

/// Runs only the reduce part of `strategy`: returns the layer and the span of it that
/// this rank now owns in the final image (empty when it owns none).
pub fn reduce<P: Pixel, C: Comm>(
    comm: &C,
    strategy: Strategy,
    layer: Layer<P>,
    opts: &CompositeOptions,
) -> Result<(Layer<P>, Range<usize>), CommError> {
    let all = ActiveRect::full(layer.width, layer.height);
    reduce_bounded(comm, strategy, layer, all, opts)
}

/// [`reduce`] of a layer whose active pixels all lie inside `rect` (see
/// [`composite_bounded`]).
pub fn reduce_bounded<P: Pixel, C: Comm>(
    comm: &C,
    strategy: Strategy,
    layer: Layer<P>,
    rect: ActiveRect,
    opts: &CompositeOptions,
) -> Result<(Layer<P>, Range<usize>), CommError> {
    assert!(
        rect.fits(layer.width, layer.height),
        "active rectangle {rect:?} off the {}x{} layer",
        layer.width,
        layer.height
    );
    let mut rect = rect;
    reduce_tracked(comm, strategy, layer, &mut rect, opts)
}

/// [`reduce_bounded`] that leaves in `rect` a rectangle holding every active pixel of the
/// returned layer (the union of the rectangles of every rank whose pixels reached it),
/// for whatever sends the owned span on (the final gather, the tiled-display delivery).
pub(crate) fn reduce_tracked<P: Pixel, C: Comm>(
    comm: &C,
    strategy: Strategy,
    layer: Layer<P>,
    rect: &mut ActiveRect,
    opts: &CompositeOptions,
) -> Result<(Layer<P>, Range<usize>), CommError> {
    match strategy {
        Strategy::DirectSend => direct_send::reduce(comm, layer, rect, opts),
        Strategy::Tree => tree::reduce(comm, layer, rect, opts),
        Strategy::BinarySwap => binary_swap::reduce(comm, layer, rect, opts),
        Strategy::RadixK(k) => radix_k::reduce(comm, layer, rect, opts, k),
    }
}

/// Composites layers one after another in `order` (front first) on one thread: the
/// oracle the parallel strategies are tested against.
pub fn serial<P: Pixel>(layers: &[Layer<P>], op: Operator, order: Option<&[usize]>) -> Layer<P> {
    let views: Vec<LayerRef<'_, P>> = layers.iter().map(Layer::view).collect();
    let n = layers[0].len();
    let mut out = Layer {
        width: layers[0].width,
        height: layers[0].height,
        color: vec![P::CLEAR; n],
        depth: vec![0.0; n],
    };
    serial_into(&views, op, order, &mut out.color, &mut out.depth);
    out
}

/// [`serial`] of borrowed layers (another program's memory, e.g. numpy arrays) into the
/// caller's planes (`color`, `depth`: every pixel is written).
pub fn serial_into<P: Pixel>(
    layers: &[LayerRef<'_, P>],
    op: Operator,
    order: Option<&[usize]>,
    color: &mut [P],
    depth: &mut [f32],
) {
    let o = Order::new(layers.len(), order);
    let front = &layers[o.rank(0)];
    let n = front.color.len();
    assert!(
        layers
            .iter()
            .all(|l| l.color.len() == n && l.depth.len() == n)
            && color.len() == n
            && depth.len() == n,
        "serial composite of layers of different sizes"
    );
    color.copy_from_slice(front.color);
    depth.copy_from_slice(front.depth);
    for pos in 1..layers.len() {
        let back = &layers[o.rank(pos)];
        for i in 0..n {
            match op {
                Operator::Depth => {
                    if back.depth[i] < depth[i] {
                        depth[i] = back.depth[i];
                        color[i] = back.color[i];
                    }
                }
                Operator::Over => {
                    color[i] = P::over(color[i], back.color[i]);
                    depth[i] = depth[i].min(back.depth[i]);
                }
            }
        }
    }
}
