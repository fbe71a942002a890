//! `irradia bench scale`: predicted times of compositing, path tracing and radiosity at
//! 64 to 32,768 ranks (`irradia_parallel::scale`), from an alpha-beta network (the one
//! `pingpong` measured here, or any other) and computation rates measured now on this
//! machine with one thread. Prints a markdown table and writes a CSV.

use crate::error::CliError;
use clap::Args;
use irradia_parallel::composite::{depth, radix_k};
use irradia_parallel::netmodel::NetModel;
use irradia_parallel::scale::{self, CompositeCase, PathJob, Predicted, RadiosityJob};
use irradia_radiosity::solver::hierarchical::{self, HierarchicalOptions};
use std::path::PathBuf;
use std::time::Instant;

pub const EXAMPLES: &str = "\
Examples:
  irradia bench scale                                  # gigabit ethernet
  irradia bench scale --latency-us 0.45 --bandwidth-mbit 52000 -o scale.csv
  mpirun -np 2 target/release/examples/pingpong        # measures --latency-us and --bandwidth-mbit here

The rates (blending, path-traced samples, hierarchical radiosity) are measured on this
machine with one thread before the table is printed (about ten seconds).
Exit codes: 0 done, 1 failure while working, 2 bad input.";

#[derive(Args, Debug)]
#[command(after_long_help = EXAMPLES)]
pub struct BenchScaleArgs {
    /// Network latency per message in microseconds (alpha).
    #[arg(long, default_value_t = 50.0)]
    pub latency_us: f64,
    /// Network bandwidth in megabits per second (beta).
    #[arg(long, default_value_t = 1000.0)]
    pub bandwidth_mbit: f64,
    /// Threads per rank in the predicted runs.
    #[arg(long, default_value_t = 1)]
    pub threads_per_rank: u64,
    /// Write the table as CSV here too.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
}

/// Computation rates of this machine, one thread.
struct Rates {
    blend_s: f64,
    sample_s: f64,
    /// Hierarchical radiosity per leaf: seconds of links and of solution, links and
    /// nodes; and its iteration count.
    link_leaf_s: f64,
    solve_leaf_s: f64,
    links_per_leaf: f64,
    nodes_per_leaf: f64,
    iterations: u64,
}

fn measure() -> Result<Rates, CliError> {
    let fail = |m: String| CliError::Failure(m);
    // Depth blending of two 1280x720 RGBA8 layers (hashed depths), best of 5.
    let n = 1280 * 720;
    let hash = |i: usize| ((i as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 40) as f32;
    let (colors, depths): (Vec<[u8; 4]>, Vec<f32>) =
        (0..n).map(|i| ([i as u8; 4], hash(i))).unzip();
    let mut blend_s = f64::INFINITY;
    for _ in 0..5 {
        let (mut lc, mut ld) = (
            vec![[0u8; 4]; n],
            (0..n).map(|i| hash(i + 7)).collect::<Vec<_>>(),
        );
        let t = Instant::now();
        depth::blend(&mut lc, &mut ld, &colors, &depths, true);
        blend_s = blend_s.min(t.elapsed().as_secs_f64() / n as f64);
    }
    // Path tracing: the built-in Cornell box, 64x64 at 16 samples, one thread.
    let mut scene = irradia_scene::builtin::load("cornell").map_err(|e| fail(e.to_string()))?;
    scene.settings.width = 64;
    scene.settings.height = 64;
    scene.settings.spp = 16;
    let opts = irradia_render::RenderOptions {
        threads: Some(1),
        ..Default::default()
    };
    let t = Instant::now();
    irradia_render::render(&scene, &opts).map_err(|e| fail(e.to_string()))?;
    let sample_s = t.elapsed().as_secs_f64() / (64.0 * 64.0 * 16.0);
    // Hierarchical radiosity: the measured Cornell box at about 10,000 leaves.
    let specs = irradia_radiosity::scenes::cornell_measured();
    let mesh = irradia_radiosity::Mesh::build(&specs, Default::default())
        .map_err(|e| fail(e.to_string()))?;
    let hopts = HierarchicalOptions {
        target_leaves: Some(10_000),
        ..Default::default()
    };
    let r = irradia_render::pool::with_threads(Some(1), || hierarchical::solve(&mesh, hopts, None))
        .map_err(|e| fail(e.to_string()))?
        .map_err(|e| fail(e.to_string()))?;
    let leaves = r.mesh.len().max(1) as f64;
    Ok(Rates {
        blend_s,
        sample_s,
        link_leaf_s: r.link_time.as_secs_f64() / leaves,
        solve_leaf_s: r.solve_time.as_secs_f64() / leaves,
        links_per_leaf: r.links as f64 / leaves,
        nodes_per_leaf: r.nodes as f64 / leaves,
        iterations: r.solution.history.len() as u64,
    })
}

pub fn run(a: BenchScaleArgs) -> Result<(), CliError> {
    if !(a.latency_us >= 0.0 && a.bandwidth_mbit > 0.0 && a.threads_per_rank >= 1) {
        return Err(CliError::Input(
            "--latency-us must be >= 0, --bandwidth-mbit > 0 and --threads-per-rank >= 1".into(),
        ));
    }
    let model = NetModel {
        alpha: a.latency_us * 1e-6,
        beta: a.bandwidth_mbit * 1e6 / 8.0,
    };
    eprintln!("measuring this machine's rates (one thread) ...");
    let r = measure()?;
    let threads = a.threads_per_rank;
    // Kendall et al. (EGPGV 2010): 64 Mpixels (8192 x 8192); here RGBA8 + f32 depth.
    let dense = CompositeCase {
        pixels: 8192 * 8192,
        bytes_per_pixel: 8,
        bricks: false,
        gather: true,
    };
    // As the radix-k benchmarks time it: volume bricks, each rank keeps its span.
    let bricks = CompositeCase {
        bricks: true,
        gather: false,
        ..dense
    };
    let path = PathJob {
        pixels: 3840 * 2160,
        spp: 256,
        sample_s: r.sample_s,
        tile_pixels: 32 * 32,
        chunk_tiles: threads,
        threads,
        result_bytes_per_pixel: 40,
        result_bytes_fixed: 1024,
        scene_bytes: 1 << 20,
    };
    let rad = RadiosityJob {
        elements: 1_000_000,
        rounds: HierarchicalOptions::default().rounds as u64,
        iterations: r.iterations,
        link_s: r.link_leaf_s * 1e6,
        solve_s: r.solve_leaf_s * 1e6,
        threads,
        links_per_element: r.links_per_leaf,
        nodes_per_element: r.nodes_per_leaf,
    };
    println!(
        "network: alpha {:.2} us, beta {:.0} MB/s; rates (1 thread): blend {:.2} ns/pixel, \
         path-traced sample {:.0} ns, hierarchical radiosity {:.1} + {:.1} us/leaf (links + solution; \
         {:.1} links, {:.2} nodes a leaf, {} iterations)",
        model.alpha * 1e6,
        model.beta / 1e6,
        r.blend_s * 1e9,
        r.sample_s * 1e9,
        r.link_leaf_s * 1e6,
        r.solve_leaf_s * 1e6,
        r.links_per_leaf,
        r.nodes_per_leaf,
        r.iterations
    );
    println!(
        "\n| ranks | binary swap, dense + gather (s) | radix-8, bricks, no gather (s) | binary swap, bricks, no gather (s) | direct send, bricks, no gather (s) | path tracing 4K x 256 spp (s) | radiosity 1M elements (s) |"
    );
    println!("|---|---|---|---|---|---|---|");
    let mut csv = String::from("ranks,job,compute_s,network_s,total_s\n");
    let cell = |p: Predicted| {
        format!(
            "{:.4} ({:.0}% net)",
            p.total_s,
            100.0 * p.network_s / p.total_s.max(1e-300)
        )
    };
    for &p in scale::RANKS.iter() {
        let bs = scale::composite_time(model, p, 2, dense, r.blend_s);
        let rk = scale::composite_time(model, p, 8, bricks, r.blend_s);
        let bb = scale::composite_time(model, p, 2, bricks, r.blend_s);
        let ds = scale::composite_time(model, p, p, bricks, r.blend_s);
        let pt = scale::path_trace_time(model, p, &path);
        let ra = scale::radiosity_time(model, p, &rad);
        println!(
            "| {p} | {} | {} | {} | {} | {} | {} |",
            cell(bs),
            cell(rk),
            cell(bb),
            cell(ds),
            cell(pt),
            cell(ra)
        );
        for (job, x) in [
            ("binary-swap-dense-gather", bs),
            ("radix-8-bricks", rk),
            ("binary-swap-bricks", bb),
            ("direct-send-bricks", ds),
            ("path-trace", pt),
            ("radiosity", ra),
        ] {
            csv.push_str(&format!(
                "{p},{job},{:.6},{:.6},{:.6}\n",
                x.compute_s, x.network_s, x.total_s
            ));
        }
    }
    let one_thread_s = path.pixels as f64 * path.spp as f64 * r.sample_s;
    println!(
        "\npath tracing on one thread would take {:.0} s; radix-8 rounds at 32,768 ranks: {:?}",
        one_thread_s,
        radix_k::factors(32768, 8)
    );
    if let Some(path) = &a.output {
        irradia_core::io::write_atomic(path, csv.as_bytes())
            .map_err(|e| CliError::Failure(format!("{}: {e}", path.display())))?;
    }
    Ok(())
}
