//! Tiled display walls (the lecture's "Power Walls": colour matching, vignetting,
//! alignment, overlap areas, synching, dark field): one rank per display renders its
//! own off-axis frustum of the wall's view, blends its edges ([`blend`]), corrects its
//! colour response ([`color`]), waits at a frame barrier, and sends its frame to rank 0,
//! which makes a simulated photograph ([`photo`]). [`job`] is the whole job as
//! `irradia wall` runs it, on threads or under `mpirun`: every rank writes its own
//! display's image, rank 0 the photographs. The displays' images are rendered per
//! display or sort-last ([`sort_last`]: objects split over the ranks, composited onto
//! the displays' tiles).

pub mod blend;
pub mod color;
pub mod config;
pub mod job;
pub mod photo;
pub mod sort_last;

pub use config::{Projector, WallConfig};
pub use sort_last::WallRendering;

use crate::comm::{Comm, CommError};
use crate::workload::Workload;
use color::Correction;
use glam::{Mat4, Vec3, Vec4};
use irradia_raster::{ColorBuffer, ColorFormat, Framebuffer, Pipeline};

/// What the wall shows.
#[derive(Clone, Debug)]
pub enum WallSource {
    /// One linear colour everywhere (calibration patterns).
    Uniform(Vec3),
    /// A rendered workload seen through the whole wall as one screen.
    Workload(Workload),
}

/// The pipeline of display `i`: the wall's view with the projection narrowed to the
/// display's rectangle of the wall (an off-axis frustum).
pub fn display_pipeline(wall: &Pipeline, c: &WallConfig, i: usize) -> Pipeline {
    let (ww, wh) = c.wall_size();
    let (ox, oy) = c.origin(i);
    let (l, r) = (
        2.0 * ox as f32 / ww as f32 - 1.0,
        2.0 * (ox + c.width) as f32 / ww as f32 - 1.0,
    );
    let (t, b) = (
        1.0 - 2.0 * oy as f32 / wh as f32,
        1.0 - 2.0 * (oy + c.height) as f32 / wh as f32,
    );
    let s = Mat4::from_cols(
        Vec4::new(2.0 / (r - l), 0.0, 0.0, 0.0),
        Vec4::new(0.0, 2.0 / (t - b), 0.0, 0.0),
        Vec4::new(0.0, 0.0, 1.0, 0.0),
        Vec4::new(-(r + l) / (r - l), -(t + b) / (t - b), 0.0, 1.0),
    );
    let mut p = wall.clone();
    p.width = c.width;
    p.height = c.height;
    p.view.proj = s * wall.view.proj;
    p
}

/// The linear colour display `i` should contribute at each of its pixels.
pub fn render_display(c: &WallConfig, src: &WallSource, i: usize) -> Vec<Vec3> {
    match src {
        WallSource::Uniform(v) => vec![*v; (c.width * c.height) as usize],
        WallSource::Workload(w) => {
            let (ww, wh) = c.wall_size();
            let p = display_pipeline(&w.pipeline(ww, wh), c, i);
            let mut fb =
                Framebuffer::new(c.width, c.height, ColorFormat::Rgba32F).expect("checked size");
            p.render_triangles(&w.triangles(), &mut fb)
                .expect("framebuffer matches");
            match fb.color {
                ColorBuffer::Rgba32F(px) => px
                    .iter()
                    .map(|q| Vec3::new(q[0], q[1], q[2]).clamp(Vec3::ZERO, Vec3::ONE))
                    .collect(),
                _ => unreachable!("asked for RGBA32F"),
            }
        }
    }
}

/// What rank 0 gets back.
pub struct WallFrame {
    /// Each display's drive values in [0, 1], row-major.
    pub frames: Vec<Vec<Vec3>>,
    /// The simulated photograph over the whole wall, in linear colour.
    pub photo: Vec<Vec3>,
    pub correction: Correction,
}

/// The drive values of display `i` in [0, 1] (row-major): its part of the wall's image,
/// blended and colour-corrected, or (`corrected = false`) gamma-encoded naively.
pub fn display_frame(c: &WallConfig, src: &WallSource, i: usize, corrected: bool) -> Vec<Vec3> {
    drive_values(c, i, render_display(c, src, i), corrected)
}

/// The drive values of display `i` for the linear colour `want` it should show: blended
/// and colour-corrected, or (`corrected = false`) gamma-encoded naively.
pub fn drive_values(c: &WallConfig, i: usize, want: Vec<Vec3>, corrected: bool) -> Vec<Vec3> {
    if !corrected {
        return want
            .iter()
            .map(|v| v.clamp(Vec3::ZERO, Vec3::ONE).powf(1.0 / 2.2))
            .collect();
    }
    let weights: Vec<Vec<f32>> = (0..c.displays()).map(|j| blend::weights(c, j)).collect();
    let corr = Correction::plan(c, &weights);
    (0..c.height)
        .flat_map(|y| (0..c.width).map(move |x| (x, y)))
        .map(|(x, y)| {
            let k = (y * c.width + x) as usize;
            corr.drive(c, i, x, y, weights[i][k], want[k])
        })
        .collect()
}

/// One wall frame on `comm` (one rank per display). `corrected = false` drives every
/// projector naively (no blending, no matching) to show what the correction fixes.
pub fn frame<C: Comm>(
    comm: &C,
    c: &WallConfig,
    src: &WallSource,
    corrected: bool,
) -> Result<Option<WallFrame>, CommError> {
    Ok(frame_and_own(comm, c, src, corrected)?.1)
}

/// [`frame`], also returning this rank's own drive values (every rank gets them).
pub fn frame_and_own<C: Comm>(
    comm: &C,
    c: &WallConfig,
    src: &WallSource,
    corrected: bool,
) -> Result<(Vec<Vec3>, Option<WallFrame>), CommError> {
    frame_and_own_with(comm, c, src, corrected, WallRendering::PerDisplay)
}

/// [`frame_and_own`] with a choice of how the displays' images are rendered.
pub fn frame_and_own_with<C: Comm>(
    comm: &C,
    c: &WallConfig,
    src: &WallSource,
    corrected: bool,
    rendering: WallRendering,
) -> Result<(Vec<Vec3>, Option<WallFrame>), CommError> {
    if comm.size() != c.displays() {
        return Err(CommError::Aborted(format!(
            "a wall of {} displays needs one rank per display, not {}",
            c.displays(),
            comm.size()
        )));
    }
    let i = comm.rank();
    comm.log().begin_stage("render");
    let want = match rendering {
        WallRendering::PerDisplay => render_display(c, src, i),
        WallRendering::SortLast(strategy) => sort_last::render_tile(comm, c, src, strategy)?,
    };
    let drive = drive_values(c, i, want, corrected);
    // Frame barrier: no display swaps before every display has its frame.
    comm.log().begin_stage("swap-barrier");
    comm.barrier()?;
    comm.log().begin_stage("gather");
    let bytes: Vec<u8> =
        bytemuck::cast_slice(&drive.iter().map(|v| v.to_array()).collect::<Vec<_>>()).to_vec();
    let all = comm.gather(0, &bytes)?;
    comm.log().end_stage();
    if i != 0 {
        return Ok((drive, None));
    }
    let mut frames = Vec::new();
    for (r, b) in all.iter().enumerate() {
        if b.len() != (c.width * c.height) as usize * 12 {
            return Err(CommError::Malformed {
                rank: r,
                message: "frame of the wrong size".into(),
            });
        }
        let f: Vec<[f32; 3]> = bytemuck::pod_collect_to_vec(b);
        frames.push(f.into_iter().map(Vec3::from).collect());
    }
    let weights: Vec<Vec<f32>> = (0..c.displays()).map(|j| blend::weights(c, j)).collect();
    let corr = Correction::plan(c, &weights);
    let photo = photo::photograph(c, &corr, &frames);
    Ok((
        drive,
        Some(WallFrame {
            frames,
            photo,
            correction: corr,
        }),
    ))
}
