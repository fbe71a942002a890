//! `irradia bench parallel`: the lecture's sort-first against sort-last study. Sweeps
//! workloads, triangle counts, rank counts and modes on threads, models the network
//! (gigabit ethernet by default) with the alpha-beta model, and writes a CSV and a PNG
//! chart.

use crate::error::CliError;
use crate::output;
use clap::{Args, Subcommand};
use irradia_parallel::composite::Strategy;
use irradia_parallel::job::Mode;
use irradia_parallel::netmodel::NetModel;
use irradia_parallel::study;
use irradia_parallel::workload::Workload;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct BenchArgs {
    #[command(subcommand)]
    pub what: BenchWhat,
}

#[derive(Subcommand, Debug)]
pub enum BenchWhat {
    /// Sort-first vs sort-middle vs sort-last as triangles grow (CSV + PNG chart).
    Parallel(BenchParallelArgs),
    /// Predicted compositing, path tracing and radiosity times at 64 to 32,768 ranks
    /// (alpha-beta network model, this machine's measured rates).
    Scale(super::bench_scale::BenchScaleArgs),
}

const EXAMPLES: &str = "\
Examples:
  irradia bench parallel --triangles 2000,10000 --workloads teapot -o bench-small   # seconds
  irradia bench parallel --ranks 2,4,6 --modes sort-first,sort-middle,sort-last
  irradia bench parallel --bandwidth-mbit 10000 --latency-us 5 -o bench-10g        # a faster network

Every point renders one frame on threads and adds the modelled network time
(alpha + bytes / beta per message). The folder receives parallel.csv (one row per
workload, triangle count, rank count and mode) and parallel.png (the chart).
Exit codes: 0 done, 1 failure while working, 2 bad input.";

#[derive(Args, Debug)]
#[command(after_long_help = EXAMPLES)]
pub struct BenchParallelArgs {
    /// Rank counts to sweep (comma-separated); the lecture's cluster had 6 nodes.
    #[arg(long, default_value = "6", value_delimiter = ',')]
    pub ranks: Vec<usize>,
    /// Triangle counts to sweep (comma-separated).
    #[arg(long, default_value = "2000,10000,50000,200000", value_delimiter = ',')]
    pub triangles: Vec<usize>,
    /// Workloads (comma-separated).
    #[arg(
        long,
        default_value = "random-triangles,teapot,marching-cubes",
        value_delimiter = ','
    )]
    pub workloads: Vec<String>,
    /// Modes (comma-separated).
    #[arg(long, default_value = "sort-first,sort-last", value_delimiter = ',')]
    pub modes: Vec<String>,
    /// Compositor for sort-last.
    #[arg(long, default_value = "binary-swap")]
    pub compositor: String,
    /// Screen size (the lecture's projectors were 1024x768).
    #[arg(long, default_value_t = 1024)]
    pub width: u32,
    #[arg(long, default_value_t = 768)]
    pub height: u32,
    /// Network latency in microseconds.
    #[arg(long, default_value_t = 50.0)]
    pub latency_us: f64,
    /// Network bandwidth in megabits per second.
    #[arg(long, default_value_t = 1000.0)]
    pub bandwidth_mbit: f64,
    /// Output folder for parallel.csv and parallel.png (created if missing).
    #[arg(short, long, value_name = "DIR", default_value = "bench-parallel")]
    pub output: PathBuf,
    /// Print nothing but errors (no line per point).
    #[arg(short, long, help_heading = "General options")]
    pub quiet: bool,
}

pub fn run(a: BenchArgs) -> Result<(), CliError> {
    match a.what {
        BenchWhat::Parallel(b) => parallel(b),
        BenchWhat::Scale(b) => super::bench_scale::run(b),
    }
}

fn parallel(a: BenchParallelArgs) -> Result<(), CliError> {
    let bad = |m: String| CliError::Input(m);
    let modes: Vec<Mode> = a
        .modes
        .iter()
        .map(|m| Mode::parse(m).ok_or_else(|| bad(format!("--modes: unknown mode {m:?}"))))
        .collect::<Result<_, _>>()?;
    let strategy = Strategy::parse(&a.compositor)
        .ok_or_else(|| bad(format!("--compositor {:?}: unknown", a.compositor)))?;
    if a.ranks.iter().any(|&r| r == 0 || r > 64) {
        return Err(bad("--ranks: expected counts from 1 to 64".into()));
    }
    if !(a.latency_us >= 0.0 && a.bandwidth_mbit > 0.0) {
        return Err(bad(
            "--latency-us must be >= 0 and --bandwidth-mbit > 0".into()
        ));
    }
    for w in &a.workloads {
        Workload::by_name(w, 1)
            .ok_or_else(|| bad(format!("--workloads: unknown workload {w:?}")))?;
    }
    let model = NetModel {
        alpha: a.latency_us * 1e-6,
        beta: a.bandwidth_mbit * 1e6 / 8.0,
    };
    output::prepare_folder("-o", &a.output)?;
    let mut rows = Vec::new();
    for w in &a.workloads {
        for &t in &a.triangles {
            let wl = Workload::by_name(w, t).expect("checked");
            for &ranks in &a.ranks {
                for &mode in &modes {
                    let row =
                        study::run_point(&wl, mode, ranks, a.width, a.height, strategy, model)
                            .map_err(|e| CliError::Failure(e.to_string()))?;
                    if !a.quiet {
                        eprintln!(
                        "{:<17} {:>8} tris {:<11} {:>2} ranks: compute {:>8.2} ms + network {:>8.2} ms = {:>8.2} ms",
                        row.workload,
                        row.triangles,
                        row.mode,
                        ranks,
                        row.compute_s * 1e3,
                        row.network_s * 1e3,
                        row.total_s * 1e3
                    );
                    }
                    rows.push(row);
                }
            }
        }
    }
    let csv = a.output.join("parallel.csv");
    irradia_core::io::write_atomic(&csv, study::csv(&rows).as_bytes())
        .map_err(|e| CliError::Failure(format!("{}: {e}", csv.display())))?;
    let png = a.output.join("parallel.png");
    study::chart(&rows, &png).map_err(|e| CliError::Failure(format!("{}: {e}", png.display())))?;
    if !a.quiet {
        eprintln!("wrote {} and {}", csv.display(), png.display());
    }
    Ok(())
}
