//! The full Whitted ray tracer over a distributed scene (object-parallel, with ray
//! forwarding): each rank owns a block of the objects, as in sort-last rendering, yet
//! the image has shadows, reflection, refraction and area-light samples, and equals
//! the serial `irradia render` (Whitted) bit for bit.
//!
//! The lecture's "Sort Last" slide assigns objects to units and composites the results
//! at the end, and "Mapping to Clusters" warns that on distributed memory the
//! communication cost must be evaluated. For a ray tracer, compositing suffices only for
//! ray casting (`crate::raytrace_last`): a secondary or shadow ray may hit any object,
//! and the objects live on other ranks, so the rays (or the objects) must travel. Reinhard and Jansen (1997, "Rendering large scenes using
//! parallel ray tracing") forward the rays to the processors owning the data they
//! cross ("data-parallel" tasks) while the shading stays where the ray tree lives;
//! Navrátil et al. (2014) schedule such ray exchanges in rounds across the whole
//! machine. Both keep each ray's state (its pixel, weight and pending shading) alive
//! while it travels. This module does the same with the recursive tracer unchanged,
//! by **deterministic replay in generations**:
//!
//! 1. Camera, lights, materials, settings and the object table (names, materials) are
//!    replicated; the geometry is not: each rank builds the acceleration structure of
//!    its own block of objects only (`crate::frame::block`, as `crate::raytrace_last`).
//! 2. Each rank shades the pixels of its screen regions (`crate::raytrace_first`'s
//!    layout). The Whitted tracer of `irradia-render` asks its geometry through
//!    [`irradia_render::whitted::RayQuery`]; here that is a [`cache::Replay`], which
//!    answers from the pixel's log of resolved queries (what its last trace asked, in
//!    order) and records every other query as a miss, answering it with a placeholder
//!    (no hit, not blocked) so that the rest of the pixel's tree is still explored and
//!    its queries found in the same pass.
//! 3. After each pass, [`resolve::resolve`] sends every rank's missed queries to every
//!    rank whose objects' box the ray may cross ([`domain`]; an all-to-all), each rank
//!    answers them against its own objects, and the answers return (a second
//!    all-to-all) to be merged: the nearest hit (an equal `t` goes to the lower rank)
//!    or any blocker ([`wire`]); they are filled into the logs of the pixels that asked.
//! 4. Pixels traced without a miss are finished: every answer they used was the
//!    scene's, and their random numbers come from the pixel alone, so their colour is
//!    the serial one. Only unfinished pixels are traced again. When no rank asked
//!    anything, every pixel is finished and the regions are gathered at the root.
//!
//! Each pass resolves at least the first query (in the serial tracer's order) of every
//! unfinished pixel that was not answered yet, so the passes end; in practice they
//! resolve whole levels of the ray tree at once. For a scene of opaque objects the
//! number of exchanges is at most `max_depth + 1` (one per level of the tree, plus the
//! shadow rays of the deepest level). Transparent objects add sequential steps (a
//! shadow ray first asks whether anything blocks it, then whether an opaque object
//! does, then walks the clear surfaces one by one), and area-light samples draw random
//! numbers, whose sequence in a glass object's reflected subtree is known only once
//! its refracted subtree is: these scenes need a few more exchanges (reported).
//!
//! The price of replay is recomputation (a pixel is traced once per pass until it
//! finishes, its earlier levels from its log) and memory for the logs of unfinished
//! pixels (dropped as they finish); the gain is
//! that no ray state ever travels (30 bytes per query, 1 or 65 per answer) and that the
//! serial tracer is the distributed one.

pub mod cache;
pub mod domain;
pub mod resolve;
pub mod wire;

use crate::comm::{Comm, CommError};
use crate::composite::{Layer, Operator};
use crate::frame::block;
use crate::raytrace_first;
use crate::raytrace_last::sub_scene;
use crate::sort_first::{gather_tiles, Tiling};
use cache::{Log, Replay};
use domain::Domain;
use irradia_render::whitted::{RayQuery, SceneGeometry};
use irradia_render::{driver, Whitted};
use irradia_scene::Scene;
use rayon::prelude::*;
use resolve::{resolve, Owned, Traffic};
use std::time::Instant;
use wire::Query;

/// Pixels traced by one task with one [`Replay`] (its miss list is not shared).
const PIXELS_PER_TASK: usize = 32;

/// One generation (a tracing pass and the exchange after it), seen from one rank.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Generation {
    /// Pixels this rank traced in the pass, and how many of them finished.
    pub traced: u64,
    pub finished: u64,
    /// Rays the pass traced (camera, shadow, reflected, refracted; placeholders count).
    pub rays: u64,
    /// The exchange after the pass (no queries: the last generation).
    pub traffic: Traffic,
    /// Seconds of tracing and of exchanging on this rank.
    pub trace_seconds: f64,
    pub exchange_seconds: f64,
}

/// What one rank did: the image (at the root) and every generation.
pub struct ForwardResult {
    pub image: Option<Layer<[f32; 4]>>,
    pub generations: Vec<Generation>,
    /// The most resolved queries this rank held at once (in its unfinished pixels'
    /// logs; a pixel's log is dropped when it finishes).
    pub peak_log_entries: usize,
}

impl ForwardResult {
    /// Exchanges that moved queries (the last generation only confirms that none is
    /// left).
    pub fn exchanges(&self) -> usize {
        self.generations
            .iter()
            .filter(|g| g.traffic.queries_total > 0)
            .count()
    }
}

/// Which objects are closed solids, for the whole scene: every rank tells the others
/// about its own block (one byte per object), as it would if the geometry had never
/// been replicated.
fn solid_table<C: Comm>(comm: &C, owned: &Owned<'_>, count: usize) -> Result<Vec<bool>, CommError> {
    let mine: Vec<u8> = (0..count as u32)
        .map(|i| owned.geometry.as_ref().is_some_and(|g| g.is_solid(i)) as u8)
        .collect();
    let all = comm.all_to_all(&vec![mine; comm.size()])?;
    Ok(all.concat().into_iter().map(|b| b == 1).collect())
}

/// Every rank's [`Domain`], each rank telling the others its own.
fn domain_table<C: Comm>(
    comm: &C,
    scene: &Scene,
    objects: std::ops::Range<usize>,
) -> Result<Vec<Domain>, CommError> {
    let mut mine = Vec::with_capacity(domain::DOMAIN_BYTES);
    Domain::of(scene, objects).encode(&mut mine);
    let all = comm.all_to_all(&vec![mine; comm.size()])?;
    all.iter()
        .enumerate()
        .map(|(rank, b)| {
            Domain::decode(b).ok_or_else(|| CommError::Malformed {
                rank,
                message: format!("{} bytes are not a domain", b.len()),
            })
        })
        .collect()
}

/// Renders `scene` with the Whitted tracer, each rank owning a block of the objects and
/// shading the pixels of its regions of `tiling`; rays are forwarded as queries. The
/// image (linear RGB, alpha 1) arrives at `root`. Collective over `comm`.
pub fn render<C: Comm>(
    comm: &C,
    scene: &Scene,
    tiling: Tiling,
    root: usize,
) -> Result<ForwardResult, CommError> {
    comm.log().begin_stage("render");
    let (me, p) = (comm.rank(), comm.size());
    let objects = block(scene.objects.len(), me, p);
    let own_scene = (!objects.is_empty()).then(|| sub_scene(scene, objects.clone()));
    let owned = Owned {
        geometry: own_scene.as_ref().map(SceneGeometry::new),
        first: objects.start as u32,
    };
    let solid = solid_table(comm, &owned, objects.len())?;
    let domains = domain_table(comm, scene, objects)?;

    let (w, h) = (scene.settings.width, scene.settings.height);
    let layout = raytrace_first::layout(scene, p, tiling);
    let mut pending: Vec<Pending> = layout
        .mine(me)
        .flat_map(|r| (r.y0..r.y1).flat_map(move |y| (r.x0..r.x1).map(move |x| (x, y))))
        .map(|pixel| Pending {
            pixel,
            log: Log::new(),
        })
        .collect();
    let mut layer = Layer::<[f32; 4]>::new(w, h);
    let mut generations = Vec::new();
    let mut most_held = 0;
    loop {
        comm.log().begin_stage("render");
        let start = Instant::now();
        let traced = pending.len() as u64;
        let passes: Vec<_> = std::mem::take(&mut pending)
            .into_par_iter()
            .chunks(PIXELS_PER_TASK)
            .map(|pixels| trace_pass(scene, &solid, pixels))
            .collect();
        let mut g = Generation {
            traced,
            ..Generation::default()
        };
        let mut still = Vec::new();
        let mut misses = Vec::new();
        for pass in passes {
            g.rays += pass.rays;
            for ((x, y), c) in pass.finished {
                let i = y as usize * w as usize + x as usize;
                layer.color[i] = [c.r, c.g, c.b, 1.0];
                layer.depth[i] = 0.0;
                g.finished += 1;
            }
            still.extend(pass.unfinished);
            misses.extend(pass.misses);
        }
        misses.par_sort_unstable();
        misses.dedup();
        pending = still;
        most_held = most_held.max(pending.iter().map(|p| p.log.len()).sum::<usize>());
        g.trace_seconds = start.elapsed().as_secs_f64();

        comm.log().begin_stage("forward");
        let start = Instant::now();
        let mut answered = Vec::new();
        g.traffic = resolve(comm, &owned, &domains, &misses, &mut answered)?;
        // Fill the answers into the logs of the pixels that asked (`misses` is sorted).
        pending.par_iter_mut().for_each(|p| {
            for (q, a) in &mut p.log {
                if a.is_none() {
                    *a = misses.binary_search(q).ok().map(|i| answered[i]);
                }
            }
        });
        g.exchange_seconds = start.elapsed().as_secs_f64();
        generations.push(g);
        if g.traffic.queries_total == 0 {
            debug_assert!(
                pending.is_empty(),
                "a pixel is unfinished only after a miss"
            );
            break;
        }
    }
    comm.log().begin_stage("gather");
    let image = gather_tiles(comm, &layer, &layout, root, Operator::Depth)?;
    comm.log().end_stage();
    Ok(ForwardResult {
        image,
        generations,
        peak_log_entries: most_held,
    })
}

/// A pixel still to finish, with the queries its last trace asked.
struct Pending {
    pixel: (u32, u32),
    log: Log,
}

/// What one task's pass over its pixels produced.
struct Pass {
    finished: Vec<((u32, u32), irradia_core::Rgb)>,
    unfinished: Vec<Pending>,
    misses: Vec<Query>,
    rays: u64,
}

/// Traces `pixels` exactly as `irradia render` does (`driver::render_region` of one
/// pixel: the same samples, and with adaptive sampling the same decision from the
/// neighbours' centre samples), answering geometry from each pixel's log.
fn trace_pass(scene: &Scene, solid: &[bool], pixels: Vec<Pending>) -> Pass {
    let tracer = Whitted::with_geometry(scene, Replay::new(solid));
    let mut pass = Pass {
        finished: Vec::new(),
        unfinished: Vec::new(),
        misses: Vec::new(),
        rays: 0,
    };
    for Pending { pixel: (x, y), log } in pixels {
        tracer.geometry().begin(log);
        let (colour, stats) = driver::render_region(&tracer, scene, x, y, 1, 1);
        pass.rays += stats.total_rays();
        let (log, missed) = tracer.geometry().end();
        if missed {
            pass.misses
                .extend(log.iter().filter(|e| e.1.is_none()).map(|e| e.0));
            pass.unfinished.push(Pending { pixel: (x, y), log });
        } else {
            pass.finished.push(((x, y), colour[0]));
        }
    }
    pass
}
