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
use irradia_parallel::composite::{self, Layer, Operator, Pixel, Strategy};
use irradia_parallel::display_tiles::{DisplayLayout, DisplayTile};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;

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

/// The layers of a colour array of shape (h, w, 4) (one) or (n, h, w, 4) (a stack),
/// with depth (h, w) / (n, h, w) or the background depth everywhere.
pub fn layers<P: Channels>(
    color: &PyReadonlyArrayDyn<'_, P::Channel>,
    depth: Option<&PyReadonlyArrayDyn<'_, f32>>,
) -> PyResult<Vec<Layer<P>>> {
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
    let (wu, hu) = (
        u32::try_from(w).map_err(|_| errors::input("color: too wide"))?,
        u32::try_from(h).map_err(|_| errors::input("color: too tall"))?,
    );
    let c = values(color);
    let d: Option<Vec<f32>> = match depth {
        Some(d) => {
            let want: Vec<usize> = shape[..shape.len() - 1].to_vec();
            if d.shape() != want.as_slice() {
                return Err(errors::input(format!(
                    "depth: expected shape {want:?} to match color {shape:?}, got {:?}",
                    d.shape()
                )));
            }
            let v = values(d).into_owned();
            if v.iter().any(|x| x.is_nan()) {
                return Err(errors::input(
                    "depth: NaN is not a depth (use inf for the background)",
                ));
            }
            Some(v)
        }
        None => None,
    };
    let px = h * w;
    Ok((0..n)
        .map(|k| Layer {
            width: wu,
            height: hu,
            // P is four channels with no padding (both are Pod): one copy.
            color: bytemuck::cast_slice::<P::Channel, P>(&c[4 * k * px..4 * (k + 1) * px]).to_vec(),
            depth: match &d {
                Some(d) => d[k * px..(k + 1) * px].to_vec(),
                None => vec![composite::FAR; px],
            },
        })
        .collect())
}

/// A pixel type made of four channels of an array's element type, with no padding
/// (both `Pod`), so that layers and arrays convert by one copy.
pub trait Channels: Pixel {
    type Channel: numpy::Element + bytemuck::Pod;
}

impl Channels for [u8; 4] {
    type Channel = u8;
}

impl Channels for [f32; 4] {
    type Channel = f32;
}

/// A layer as (color (h, w, 4), depth (h, w)) arrays.
pub fn layer_arrays<P: Channels>(py: Python<'_>, l: &Layer<P>) -> PyResult<(PyObject, PyObject)> {
    let (h, w) = (l.height as usize, l.width as usize);
    let color = PyArray1::from_slice(py, bytemuck::cast_slice::<P, P::Channel>(&l.color))
        .reshape([h, w, 4])?
        .into_any()
        .unbind();
    let depth = PyArray1::from_slice(py, &l.depth)
        .reshape([h, w])?
        .into_any()
        .unbind();
    Ok((color, depth))
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
    let ls = layers::<P>(&c, depth.as_ref())?;
    check_order(&order, ls.len())?;
    let (w, h) = (ls[0].width, ls[0].height);
    let out = py.allow_threads(|| composite::serial(&ls, op, order.as_deref()));
    match tiles {
        None => Ok(layer_arrays(py, &out)?
            .into_pyobject(py)?
            .into_any()
            .unbind()),
        Some(tiles) => {
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
    depth: Option<PyReadonlyArrayDyn<'_, f32>>,
    op: &str,
    order: Option<Vec<usize>>,
    tiles: Option<Vec<TileSpec>>,
) -> PyResult<PyObject> {
    let op = operator(op)?;
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
