//! One parallel frame by mode name: the dispatcher the CLI and the study use.

use crate::comm::{Comm, CommError};
use crate::composite::{CompositeOptions, Layer, Strategy};
use crate::{sort_first, sort_last, sort_middle};
use irradia_raster::{Pipeline, Triangle};

#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Mode {
    SortFirst,
    SortMiddle,
    SortLast,
}

impl Mode {
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "sort-first" => Some(Mode::SortFirst),
            "sort-middle" => Some(Mode::SortMiddle),
            "sort-last" => Some(Mode::SortLast),
            _ => None,
        }
    }
    pub fn name(&self) -> &'static str {
        match self {
            Mode::SortFirst => "sort-first",
            Mode::SortMiddle => "sort-middle",
            Mode::SortLast => "sort-last",
        }
    }
    /// Stages that move data over the network (the rest are computation).
    pub fn network_stages() -> &'static [&'static str] {
        &["redistribute", "composite", "gather"]
    }
}

/// Renders one frame in `mode`; the image arrives at rank 0.
pub fn run<C: Comm>(
    comm: &C,
    mode: Mode,
    p: &Pipeline,
    tris: &[Triangle],
    strategy: Strategy,
) -> Result<Option<Layer<[u8; 4]>>, CommError> {
    match mode {
        Mode::SortFirst => sort_first::render(comm, p, tris, 0),
        Mode::SortMiddle => sort_middle::render(comm, p, tris, 0),
        Mode::SortLast => sort_last::render(comm, p, tris, strategy, &CompositeOptions::default()),
    }
}

/// An image (at rank 0) and the sort-first layout, if any.
pub type TiledImage = (Option<Layer<[u8; 4]>>, Option<sort_first::TileLayout>);

/// [`run`] with sort-first regions cut by `tiling`; also returns the sort-first layout
/// (`None` for the other modes).
pub fn run_tiled<C: Comm>(
    comm: &C,
    mode: Mode,
    p: &Pipeline,
    tris: &[Triangle],
    strategy: Strategy,
    tiling: sort_first::Tiling,
) -> Result<TiledImage, CommError> {
    match mode {
        Mode::SortFirst => {
            sort_first::render_tiled_layout(comm, p, tris, 0, tiling).map(|(i, l)| (i, Some(l)))
        }
        _ => run(comm, mode, p, tris, strategy).map(|i| (i, None)),
    }
}
