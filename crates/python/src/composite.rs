//! `irradia.composite`: sort-last compositing of numpy images with Irradia's
//! compositors (`irradia_parallel::composite`: direct send, tree, binary swap,
//! radix-k; opaque by depth or ordered "over"), for codes that render themselves.
//! Over an mpi4py communicator (cargo feature `mpi`) each rank passes its own layer
//! and the root gets the composite; without a communicator the layers of one process
//! (a stack of shape (n, h, w, 4)) are composited one after another, the oracle the
//! parallel strategies equal (`composite::serial`).
//!
//! Pixels are premultiplied RGBA, uint8 or float32 (Porter and Duff 1984); depth is
//! float32 with infinity for the background.

use crate::convert::values;
use crate::errors;
use crate::pool;
use irradia_parallel::composite::{self, Layer, LayerRef, Operator, Pixel, Strategy};
use irradia_parallel::display_tiles::{DisplayLayout, DisplayTile};
use numpy::ndarray::Dim;
use numpy::{
    PyArray2, PyArray3, PyArrayMethods, PyReadonlyArrayDyn, PyReadwriteArray2, PyReadwriteArray3,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use std::borrow::Cow;
use std::cell::RefCell;
use std::thread::LocalKey;

/// The operator by name ("depth" or "over").
pub fn operator(name: &str) -> PyResult<Operator> {
    match name {
        "depth" => Ok(Operator::Depth),
        "over" => Ok(Operator::Over),
        _ => Err(errors::input(format!(
            "op: unknown operator '{name}' (use depth or over)"
        ))),
    }
}

/// The strategy by the command line's name (`--compositor`).
pub fn strategy(name: &str) -> PyResult<Strategy> {
    Strategy::parse(name).ok_or_else(|| {
        errors::input(format!(
            "strategy: unknown compositor '{name}' (use direct-send, tree, binary-swap, radix-k or radix-N)"
        ))
    })
}

/// A colour array of shape (h, w, 4) (one layer) or (n, h, w, 4) (a stack) and its
/// depth, (h, w) / (n, h, w) or none, checked and seen as pixel planes: C-contiguous
/// arrays are borrowed in place (no copy), others copied once.
pub struct Planes<'a, P: Clone> {
    /// Layers.
    pub n: usize,
    pub width: u32,
    pub height: u32,
    /// `n * width * height` pixels, layer after layer.
    pub color: Cow<'a, [P]>,
    /// As many depths, or `None` (background depth everywhere).
    pub depth: Option<Cow<'a, [f32]>>,
}

impl<P: Channels> Planes<'_, P> {
    /// Pixels of one layer.
    pub fn pixels(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// Refuses NaN depths (one vectorised pass, without the GIL in the callers).
    pub fn check_depth(&self) -> PyResult<()> {
        if let Some(d) = &self.depth {
            if d.chunks(4096)
                .any(|c| c.iter().fold(false, |acc, x| acc | x.is_nan()))
            {
                return Err(nan_depth());
            }
        }
        Ok(())
    }

    /// Layer `k` as borrowed planes (`far`: background depths of one layer, used when
    /// there is no depth).
    pub fn layer<'s>(&'s self, k: usize, far: &'s [f32]) -> LayerRef<'s, P> {
        let px = self.pixels();
        LayerRef {
            width: self.width,
            height: self.height,
            color: &self.color[k * px..(k + 1) * px],
            depth: match &self.depth {
                Some(d) => &d[k * px..(k + 1) * px],
                None => far,
            },
        }
    }

    /// Layer `k` copied into `layer` (resized to fit: a kept working layer is reused
    /// without new allocation when its size matches), NaN depths refused in the same
    /// pass (see [`Planes::check_depth`]).
    pub fn copy_into(&self, k: usize, layer: &mut Layer<P>) -> PyResult<()> {
        let px = self.pixels();
        layer.width = self.width;
        layer.height = self.height;
        layer.color.resize(px, P::CLEAR);
        layer.depth.resize(px, composite::FAR);
        layer
            .color
            .copy_from_slice(&self.color[k * px..(k + 1) * px]);
        match &self.depth {
            Some(d) => {
                let mut nan = false;
                for (o, i) in layer
                    .depth
                    .chunks_mut(4096)
                    .zip(d[k * px..(k + 1) * px].chunks(4096))
                {
                    nan |= o.iter_mut().zip(i).fold(false, |acc, (o, &x)| {
                        *o = x;
                        acc | x.is_nan()
                    });
                }
                if nan {
                    return Err(nan_depth());
                }
            }
            None => layer.depth.fill(composite::FAR),
        }
        Ok(())
    }
}

/// The depth argument as a float32 array (an `IrradiaError` for anything else).
pub fn depth_array<'py>(
    depth: Option<&Bound<'py, PyAny>>,
) -> PyResult<Option<PyReadonlyArrayDyn<'py, f32>>> {
    depth
        .map(|d| {
            d.extract().map_err(|_| {
                let got = d
                    .getattr("dtype")
                    .map(|t| t.to_string())
                    .unwrap_or_else(|_| d.get_type().to_string());
                errors::input(format!(
                    "depth: expected a float32 numpy array (inf for the background), got {got}"
                ))
            })
        })
        .transpose()
}

fn nan_depth() -> PyErr {
    errors::input("depth: NaN is not a depth (use inf for the background)")
}

/// The pixels of a C-contiguous array in place, any other array copied once.
fn pixels_of<'a, P: Channels>(a: &'a PyReadonlyArrayDyn<'_, P::Channel>) -> Cow<'a, [P]> {
    match values(a) {
        Cow::Borrowed(s) => match bytemuck::try_cast_slice::<P::Channel, P>(s) {
            Ok(p) => Cow::Borrowed(p),
            Err(_) => Cow::Owned(bytemuck::pod_collect_to_vec(s)),
        },
        Cow::Owned(v) => Cow::Owned(bytemuck::pod_collect_to_vec(&v)),
    }
}

/// Checks the shapes of `color` and `depth` and sees them as [`Planes`].
pub fn planes<'a, P: Channels>(
    color: &'a PyReadonlyArrayDyn<'_, P::Channel>,
    depth: Option<&'a PyReadonlyArrayDyn<'_, f32>>,
) -> PyResult<Planes<'a, P>> {
    let shape = color.shape().to_vec();
    let (n, h, w) = match shape.as_slice() {
        [h, w, 4] => (1, *h, *w),
        [n, h, w, 4] => (*n, *h, *w),
        _ => {
            return Err(errors::input(format!(
                "color: expected premultiplied RGBA of shape (height, width, 4) or (n, height, width, 4), got {shape:?}"
            )))
        }
    };
    if n == 0 || h == 0 || w == 0 {
        return Err(errors::input(format!("color: empty image {shape:?}")));
    }
    let (width, height) = (
        u32::try_from(w).map_err(|_| errors::input("color: too wide"))?,
        u32::try_from(h).map_err(|_| errors::input("color: too tall"))?,
    );
    let depth = match depth {
        Some(d) => {
            let want: Vec<usize> = shape[..shape.len() - 1].to_vec();
            if d.shape() != want.as_slice() {
                return Err(errors::input(format!(
                    "depth: expected shape {want:?} to match color {shape:?}, got {:?}",
                    d.shape()
                )));
            }
            Some(values(d))
        }
        None => None,
    };
    Ok(Planes {
        n,
        width,
        height,
        color: pixels_of::<P>(color),
        depth,
    })
}

/// A pixel type made of four channels of an array's element type, with no padding
/// (both `Pod`), so that arrays are read as pixels in place.
pub trait Channels: Pixel {
    type Channel: numpy::Element + bytemuck::Pod;
    /// The working layer of the last composite on this thread, kept for the next one
    /// (its memory is then already mapped: no allocation, no page faults).
    fn kept() -> &'static LocalKey<RefCell<Option<Layer<Self>>>>;
}

thread_local! {
    static KEPT8: RefCell<Option<Layer<[u8; 4]>>> = const { RefCell::new(None) };
    static KEPT32: RefCell<Option<Layer<[f32; 4]>>> = const { RefCell::new(None) };
}

impl Channels for [u8; 4] {
    type Channel = u8;
    fn kept() -> &'static LocalKey<RefCell<Option<Layer<Self>>>> {
        &KEPT8
    }
}

impl Channels for [f32; 4] {
    type Channel = f32;
    fn kept() -> &'static LocalKey<RefCell<Option<Layer<Self>>>> {
        &KEPT32
    }
}

/// Fresh arrays for an image, color (h, w, 4) and depth (h, w), to be filled by Rust.
pub type ImageArrays<'py, P> = (
    Bound<'py, PyArray3<<P as Channels>::Channel>>,
    Bound<'py, PyArray2<f32>>,
);

/// [`ImageArrays`] on memory kept from earlier calls ([`crate::pool`]: no page faults
/// once the caller's last result is freed), left uninitialised (as `numpy.empty`: no
/// pass over the memory before the one that writes it). Every caller writes every
/// element before the arrays reach Python (`serial_into`, `gather_into` on the root, a
/// copy of a whole layer) and drops them unseen on error.
pub fn image_arrays<P: Channels>(
    py: Python<'_>,
    width: u32,
    height: u32,
) -> PyResult<ImageArrays<'_, P>> {
    let (h, w) = (height as usize, width as usize);
    // SAFETY: plain numbers (u8, f32), written whole before Python sees them (above).
    unsafe {
        Ok((
            pool::empty_array::<P::Channel, _>(py, Dim([h, w, 4]))?,
            pool::empty_array::<f32, _>(py, Dim([h, w]))?,
        ))
    }
}

/// The planes of fresh [`image_arrays`] to write into.
pub fn planes_mut<'a, P: Channels>(
    color: &'a mut PyReadwriteArray3<'_, P::Channel>,
    depth: &'a mut PyReadwriteArray2<'_, f32>,
) -> (&'a mut [P], &'a mut [f32]) {
    (
        bytemuck::cast_slice_mut(color.as_slice_mut().expect("a fresh array is contiguous")),
        depth.as_slice_mut().expect("a fresh array is contiguous"),
    )
}

/// A layer as (color (h, w, 4), depth (h, w)) arrays.
pub fn layer_arrays<P: Channels>(py: Python<'_>, l: &Layer<P>) -> PyResult<(PyObject, PyObject)> {
    let (c, d) = image_arrays::<P>(py, l.width, l.height)?;
    {
        let (mut cw, mut dw) = (c.readwrite(), d.readwrite());
        let (oc, od) = planes_mut::<P>(&mut cw, &mut dw);
        oc.copy_from_slice(&l.color);
        od.copy_from_slice(&l.depth);
    }
    Ok((c.into_any().unbind(), d.into_any().unbind()))
}

/// The compositing order (`order[position] = rank`, front first) checked against `n`.
pub fn check_order(order: &Option<Vec<usize>>, n: usize) -> PyResult<()> {
    if let Some(o) = order {
        let mut seen = vec![false; n];
        let ok = o.len() == n
            && o.iter()
                .all(|&r| r < n && !std::mem::replace(&mut seen[r], true));
        if !ok {
            return Err(errors::input(format!(
                "order: must list each of the {n} layers (ranks) once, front first; got {o:?}"
            )));
        }
    }
    Ok(())
}

fn serial_of<P: Channels>(
    py: Python<'_>,
    color: &Bound<'_, PyAny>,
    depth: Option<PyReadonlyArrayDyn<'_, f32>>,
    op: Operator,
    order: Option<Vec<usize>>,
    tiles: Option<&[TileSpec]>,
) -> PyResult<PyObject> {
    let c: PyReadonlyArrayDyn<'_, P::Channel> = color.extract()?;
    let pl = planes::<P>(&c, depth.as_ref())?;
    check_order(&order, pl.n)?;
    let (w, h) = (pl.width, pl.height);
    // Straight from the arrays' memory into the result's.
    let run = |oc: &mut [P], od: &mut [f32]| -> PyResult<()> {
        pl.check_depth()?;
        let far = if pl.depth.is_none() {
            vec![composite::FAR; pl.pixels()]
        } else {
            Vec::new()
        };
        let views: Vec<LayerRef<'_, P>> = (0..pl.n).map(|k| pl.layer(k, &far)).collect();
        composite::serial_into(&views, op, order.as_deref(), oc, od);
        Ok(())
    };
    match tiles {
        None => {
            let (c, d) = image_arrays::<P>(py, w, h)?;
            {
                let (mut cw, mut dw) = (c.readwrite(), d.readwrite());
                let (oc, od) = planes_mut::<P>(&mut cw, &mut dw);
                py.allow_threads(|| run(oc, od))?;
            }
            Ok((c, d).into_pyobject(py)?.into_any().unbind())
        }
        Some(tiles) => {
            let mut out = Layer::<P>::new(w, h);
            py.allow_threads(|| run(&mut out.color, &mut out.depth))?;
            let ranks = tiles.iter().map(|t| t.0 + 1).max().unwrap_or(1);
            let l = layout(tiles, w, h, ranks)?;
            let list = pyo3::types::PyList::empty(py);
            for t in &l.tiles {
                list.append(layer_arrays(py, &DisplayLayout::crop(&out, t))?)?;
            }
            Ok(list.into_any().unbind())
        }
    }
}

/// A tile of a display wall: (rank, x, y, width, height).
pub type TileSpec = (usize, u32, u32, u32, u32);

/// The display layout of `tiles` over a `width` x `height` image, checked for `ranks`
/// ranks (`DisplayLayout::validate`: tiles inside the image, one per rank).
pub fn layout(
    tiles: &[TileSpec],
    width: u32,
    height: u32,
    ranks: usize,
) -> PyResult<DisplayLayout> {
    let layout = DisplayLayout {
        width,
        height,
        tiles: tiles
            .iter()
            .map(|&(rank, x, y, width, height)| DisplayTile {
                rank,
                x,
                y,
                width,
                height,
            })
            .collect(),
    };
    layout
        .validate(ranks, width, height)
        .map_err(|e| errors::input(format!("tiles: {e}")))?;
    Ok(layout)
}

/// The tiles of a `columns` x `rows` display grid over a `width` x `height` image,
/// driven by ranks 0, 1, ... row by row, each widened by `overlap` pixels into its
/// neighbours (edge-blended projectors), as `irradia wall` lays them out.
#[pyfunction]
#[pyo3(signature = (width, height, columns, rows, overlap=0))]
pub fn display_grid(
    width: u32,
    height: u32,
    columns: u32,
    rows: u32,
    overlap: u32,
) -> PyResult<Vec<TileSpec>> {
    let l = DisplayLayout::grid(width, height, columns, rows, overlap).map_err(errors::input)?;
    Ok(l.tiles
        .iter()
        .map(|t| (t.rank, t.x, t.y, t.width, t.height))
        .collect())
}

/// The layers of one process composited one after another (front first in `order`);
/// with `tiles`, the composite cut into each tile, in the order given.
#[pyfunction]
#[pyo3(signature = (color, depth=None, *, op="depth", order=None, tiles=None))]
pub fn _composite_serial(
    py: Python<'_>,
    color: &Bound<'_, PyAny>,
    depth: Option<&Bound<'_, PyAny>>,
    op: &str,
    order: Option<Vec<usize>>,
    tiles: Option<Vec<TileSpec>>,
) -> PyResult<PyObject> {
    let op = operator(op)?;
    let depth = depth_array(depth)?;
    if color.extract::<PyReadonlyArrayDyn<'_, u8>>().is_ok() {
        serial_of::<[u8; 4]>(py, color, depth, op, order, tiles.as_deref())
    } else if color.extract::<PyReadonlyArrayDyn<'_, f32>>().is_ok() {
        serial_of::<[f32; 4]>(py, color, depth, op, order, tiles.as_deref())
    } else {
        Err(errors::input(
            "color: expected a uint8 or float32 numpy array (premultiplied RGBA)",
        ))
    }
}

/// Whether this build composites over MPI (cargo feature `mpi`).
#[pyfunction]
pub fn mpi_available() -> bool {
    cfg!(feature = "mpi")
}
