//! Predicted times at rank counts this machine cannot run: the alpha-beta model
//! ([`NetModel`], Hockney 1994) applied in closed form to the message pattern of each
//! distributed algorithm here, plus its computation at rates measured on this machine.
//! Each rank has one full-duplex link that sends one message at a time and receives one
//! at a time (as [`NetModel::stage_time`] charges recorded messages); computation
//! divides evenly except where the algorithm's granularity stops it.
//!
//! * Compositing ([`composite_time`]): radix-k (Peterka et al. 2009) with binary swap
//!   (k = 2) and direct send (one round of p) as its extremes, dense pixels, then the
//!   gather of the final image at the root. The message pattern is the one
//!   `composite::radix_k` sends; `tests/scale.rs` checks the closed form against the
//!   model applied to the messages a real run recorded.
//! * Path tracing ([`path_trace_time`]): `progressive::render_distributed`, whose rank
//!   0 hands out chunks of tiles and receives every chunk's film pixels.
//! * Radiosity ([`radiosity_time`]): `radiosity::solve_distributed`, whose rank 0
//!   collects and deals every round's links and whose every iteration ends with each
//!   rank sending its radiosities to every other.

use crate::composite::gather::DENSE_HEADER_BYTES;
use crate::composite::pairwise::{piece_count, HEADER_BYTES};
use crate::composite::radix_k::factors;
use crate::netmodel::NetModel;

/// Rank counts of the prediction tables: 64 to 32,768 (powers of two).
pub const RANKS: [usize; 10] = [64, 128, 256, 512, 1024, 2048, 4096, 8192, 16384, 32768];

/// Time of one predicted run, split into its parts.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Predicted {
    pub compute_s: f64,
    pub network_s: f64,
    pub total_s: f64,
}

/// What a composite starts from and where it ends.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct CompositeCase {
    pub pixels: u64,
    pub bytes_per_pixel: u64,
    /// Each rank drew one brick of a volume split in p: its active pixels cover
    /// p^(-2/3) of the screen, a group of m merged bricks (m/p)^(2/3), and only active
    /// pixels travel (bounding rectangles and run lengths, as Kendall et al. 2010 and
    /// IceT send them). False: every pixel of every span travels (dense).
    pub bricks: bool,
    /// Gather the final image at one root (false: each rank keeps its span, as the
    /// radix-k benchmarks time it).
    pub gather: bool,
}

/// Sort-last compositing of `case` on `ranks` ranks, rounds of at most `k` partners
/// (2: binary swap; `ranks`: direct send), blending at `blend_s` seconds a pixel,
/// message for message as `composite::composite` sends dense spans: to each round
/// partner a header and the part in pieces of a colour and a depth message; to the
/// root one message of the final span (12-byte header); a dissemination barrier.
pub fn composite_time(
    model: NetModel,
    ranks: usize,
    k: usize,
    case: CompositeCase,
    blend_s: f64,
) -> Predicted {
    let (mut net, mut compute) = (0.0, 0.0);
    let mut span = case.pixels as f64;
    let mut merged = 1.0;
    let p = ranks as f64;
    let bpp = case.bytes_per_pixel as f64;
    if ranks > 1 {
        for f in factors(ranks, k.max(2)) {
            let part = span / f as f64;
            let active = if case.bricks {
                (merged / p).powf(2.0 / 3.0).min(1.0)
            } else {
                1.0
            };
            let sent = part * active;
            let messages = 1 + 2 * piece_count(sent.ceil() as usize);
            let bytes = HEADER_BYTES as f64 + sent * bpp;
            // f - 1 partners, each sent (and sending) a header and the pieces.
            net += (f - 1) as f64 * (messages as f64 * model.alpha + bytes / model.beta);
            compute += (f - 1) as f64 * sent * blend_s;
            span = part;
            merged *= f as f64;
        }
        if case.gather {
            // Each other rank sends its span to the root as a header and the colour and
            // depth planes (composite/gather.rs).
            let bytes = DENSE_HEADER_BYTES as f64 + span * bpp;
            net += (ranks - 1) as f64 * (3.0 * model.alpha + bytes / model.beta);
        }
        net += p.log2().ceil() * model.alpha;
    }
    Predicted {
        compute_s: compute,
        network_s: net,
        total_s: compute + net,
    }
}

/// A path-traced image as `progressive::render_distributed` splits it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PathJob {
    pub pixels: u64,
    pub spp: u64,
    /// Seconds one thread takes for one sample (measured).
    pub sample_s: f64,
    /// Pixels of a tile and tiles of a chunk (the threads of a rank).
    pub tile_pixels: u64,
    pub chunk_tiles: u64,
    /// Threads per rank.
    pub threads: u64,
    /// Bytes a chunk's result carries per pixel (film pixels) and once (counters).
    pub result_bytes_per_pixel: u64,
    pub result_bytes_fixed: u64,
    /// Bytes of the scene every rank must hold (sent by a binomial-tree broadcast).
    pub scene_bytes: u64,
}

/// One image of `job` on `ranks` ranks: the slower of the workers' share of the samples
/// (plus the last chunk, which nobody can share) and rank 0's link, which receives
/// every chunk's pixels and sends every chunk's assignment; plus the scene broadcast.
pub fn path_trace_time(model: NetModel, ranks: usize, job: &PathJob) -> Predicted {
    let tiles = job.pixels.div_ceil(job.tile_pixels.max(1));
    let chunks = tiles.div_ceil(job.chunk_tiles.max(1));
    let chunk_pixels = (job.tile_pixels * job.chunk_tiles).min(job.pixels) as f64;
    let chunk_s = chunk_pixels * job.spp as f64 * job.sample_s / job.threads.max(1) as f64;
    let total_s = job.pixels as f64 * job.spp as f64 * job.sample_s;
    // Ranks beyond the chunk count idle: the work cannot split finer than a chunk.
    let busy = (ranks as u64).min(chunks).max(1) as f64;
    let compute = (total_s / (busy * job.threads.max(1) as f64)).max(chunk_s) + chunk_s;
    let levels = (ranks as f64).log2().ceil();
    let broadcast = levels * model.message(job.scene_bytes as usize);
    let result = chunk_pixels as u64 * job.result_bytes_per_pixel + job.result_bytes_fixed;
    let root_recv = chunks as f64 * model.message(result as usize);
    let root_send = chunks as f64 * model.message(16);
    let root_link = root_recv.max(root_send);
    // Rank 0's link works while the ranks compute: the slower of the two bounds.
    Predicted {
        compute_s: compute,
        network_s: broadcast + root_link,
        total_s: broadcast + compute.max(root_link),
    }
}

/// A hierarchical radiosity solve as `radiosity::solve_distributed` splits it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct RadiosityJob {
    pub elements: u64,
    /// Refinement rounds, and Jacobi iterations over all rounds.
    pub rounds: u64,
    pub iterations: u64,
    /// One thread's seconds for all rounds' link refinement and for all iterations
    /// (measured), which divide over the ranks' threads.
    pub link_s: f64,
    pub solve_s: f64,
    pub threads: u64,
    /// Links and tree nodes per element.
    pub links_per_element: f64,
    pub nodes_per_element: f64,
}

/// Bytes of one link on the wire (receiver, source: u32; form factor: f64).
pub const LINK_BYTES: f64 = 16.0;

/// `job` on `ranks` ranks: the link refinement and the iterations divide over the
/// ranks' threads (no finer than an element a thread); each round every link passes
/// through rank 0's link twice (collected from the workers, dealt to the receivers'
/// owners); each iteration every rank sends its nodes' radiosities (3 f64) to every
/// other rank.
pub fn radiosity_time(model: NetModel, ranks: usize, job: &RadiosityJob) -> Predicted {
    let workers = (ranks as u64 * job.threads.max(1)).min(job.elements.max(1)) as f64;
    let compute = (job.link_s + job.solve_s) / workers;
    let p = ranks as f64;
    let mut network = 0.0;
    if ranks > 1 {
        let links = job.elements as f64 * job.links_per_element;
        let root = job.rounds as f64 * 2.0 * links * LINK_BYTES / model.beta;
        let nodes = job.elements as f64 * job.nodes_per_element;
        let exchange = (p - 1.0) * model.alpha + nodes * 24.0 * (p - 1.0) / p / model.beta;
        network = root + job.iterations as f64 * exchange;
    }
    Predicted {
        compute_s: compute,
        network_s: network,
        total_s: compute + network,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const NET: NetModel = NetModel {
        alpha: 1e-6,
        beta: 1e9,
    };

    #[test]
    fn binary_swap_halves_and_direct_send_sends_p_minus_one() {
        // 4 ranks of 4096 pixels x 1 byte. Binary swap: rounds of 2048 pixels (header +
        // 2 pieces of colour and depth) and 1024 (header + 1 piece), the gather of 3
        // spans of 1024 (each a header and the two planes: 3 messages),
        // 2 barrier rounds.
        let h = HEADER_BYTES;
        let case = CompositeCase {
            pixels: 4096,
            bytes_per_pixel: 1,
            bricks: false,
            gather: true,
        };
        let gather = 3.0 * (3.0 * NET.alpha + (DENSE_HEADER_BYTES + 1024) as f64 / NET.beta);
        let b = composite_time(NET, 4, 2, case, 0.0);
        let want = 5.0 * NET.alpha
            + (h + 2048) as f64 / NET.beta
            + 3.0 * NET.alpha
            + (h + 1024) as f64 / NET.beta
            + gather
            + 2.0 * NET.alpha;
        assert!((b.network_s - want).abs() < 1e-15, "{} {want}", b.network_s);
        // Direct send: one round of 3 partners of 1024 pixels, the same gather.
        let d = composite_time(NET, 4, 4, case, 0.0);
        let want =
            3.0 * (3.0 * NET.alpha + (h + 1024) as f64 / NET.beta) + gather + 2.0 * NET.alpha;
        assert!((d.network_s - want).abs() < 1e-15);
        assert_eq!(composite_time(NET, 1, 2, case, 1.0).total_s, 0.0);
        // Bricks: 8 ranks in one round of 8 (direct send) send (1/8)^(2/3) = 1/4 of each
        // eighth: 32768 pixels, 4 pieces (9 messages) to each of 7 partners.
        let bricks = CompositeCase {
            bricks: true,
            gather: false,
            pixels: 1 << 20,
            ..case
        };
        let sparse = composite_time(NET, 8, 8, bricks, 0.0);
        let want = 7.0 * (9.0 * NET.alpha + (h + 32768) as f64 / NET.beta) + 3.0 * NET.alpha;
        assert!(
            (sparse.network_s - want).abs() < 1e-12,
            "{} {want}",
            sparse.network_s
        );
    }

    #[test]
    fn path_tracing_stops_scaling_at_the_chunk_count_and_the_root_link() {
        let job = PathJob {
            pixels: 1 << 20,
            spp: 64,
            sample_s: 1e-6,
            tile_pixels: 256,
            chunk_tiles: 1,
            threads: 1,
            result_bytes_per_pixel: 40,
            result_bytes_fixed: 0,
            scene_bytes: 0,
        };
        let t = |p| path_trace_time(NET, p, &job).total_s;
        // 4096 chunks: doubling the ranks below that nearly halves the time ...
        assert!(t(512) / t(1024) > 1.7);
        // ... beyond it nothing changes but the broadcast.
        assert!((t(8192) - t(16384)).abs() < 1e-4 * t(8192));
        // The root receives 40 MB: at 1 GB/s no run beats 40 ms.
        assert!(t(32768) >= 0.04);
    }

    #[test]
    fn radiosity_divides_compute_and_pays_the_root_and_the_exchanges() {
        let job = RadiosityJob {
            elements: 1 << 20,
            rounds: 3,
            iterations: 30,
            link_s: 60.0,
            solve_s: 4.0,
            threads: 1,
            links_per_element: 20.0,
            nodes_per_element: 1.0,
        };
        let p = radiosity_time(NET, 64, &job);
        assert!((p.compute_s - 1.0).abs() < 1e-12);
        let n = (1 << 20) as f64;
        let root = 3.0 * 2.0 * n * 20.0 * LINK_BYTES / NET.beta;
        let exchange = 63.0 * NET.alpha + n * 24.0 * 63.0 / 64.0 / NET.beta;
        assert!((p.network_s - (root + 30.0 * exchange)).abs() < 1e-9);
        assert_eq!(radiosity_time(NET, 1, &job).network_s, 0.0);
    }
}
