//! The tiled wall over MPI against the same wall on threads: run under
//! `mpirun -np 4` (scripts/test-mpi.sh does). Every rank renders, corrects and writes its
//! display of a 2 x 2 wall (different projector responses, overlaps) with `MpiComm`;
//! rank 0 writes the photographs; then rank 0 runs the same job with `LocalComm` (4
//! threads) into another folder and compares every file byte for byte; both with the
//! displays rendered per display and sort-last (composited onto the displays). Prints one line
//! per check and a closing `N passed, N failed`; exits 1 on any failure.

use irradia_parallel::comm::{run_local, Comm, LocalOptions, MpiComm};
use irradia_parallel::composite::Strategy;
use irradia_parallel::wall::{job, WallConfig, WallRendering, WallSource};
use irradia_parallel::workload::Workload;
use std::path::{Path, PathBuf};
use std::time::Duration;

const WALL: &str = r#"
columns = 2
rows = 2
width = 40
height = 30
overlap = 8

[[projector]]
gamma = 2.4
matrix = [[0.92, 0.06, 0.02], [0.04, 0.90, 0.06], [0.01, 0.07, 0.80]]
black = [0.010, 0.011, 0.013]
vignetting = 0.3

[[projector]]
gamma = 1.9
black = [0.02, 0.018, 0.015]

[[projector]]
vignetting = 0.15
"#;

fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .expect("output folder")
        .map(|e| {
            let e = e.expect("folder entry");
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).expect("readable file"),
            )
        })
        .collect();
    v.sort();
    v
}

fn main() {
    let comm = MpiComm::init(Duration::from_secs(20)).expect("MPI initialises once");
    let c = WallConfig::parse(WALL).expect("wall file");
    let src = WallSource::Workload(Workload::by_name("teapot", 2000).expect("teapot"));
    if comm.size() != c.displays() {
        if comm.rank() == 0 {
            println!("FAIL wall: run with mpirun -np {}", c.displays());
            println!("0 passed, 1 failed");
        }
        drop(comm);
        std::process::exit(1);
    }
    // Rank 0 picks the folders and tells the others.
    let root = std::env::temp_dir().join(format!("irradia-mpi-wall-{}", std::process::id()));
    let root = comm
        .broadcast(0, root.to_string_lossy().as_bytes())
        .unwrap_or_else(|e| comm.fail(&e));
    let root = PathBuf::from(String::from_utf8(root).expect("utf-8 path"));
    let renderings = [
        ("per-display", WallRendering::PerDisplay),
        ("sort-last", WallRendering::SortLast(Strategy::BinarySwap)),
    ];
    let dirs = |label: &str| (root.join(label).join("mpi"), root.join(label).join("local"));
    if comm.rank() == 0 {
        for (label, _) in renderings {
            let (mpi_dir, local_dir) = dirs(label);
            std::fs::create_dir_all(&mpi_dir).expect("temporary folder");
            std::fs::create_dir_all(&local_dir).expect("temporary folder");
        }
    }
    comm.barrier().unwrap_or_else(|e| comm.fail(&e));
    for (label, rendering) in renderings {
        match job::run_with(&comm, &c, &src, &dirs(label).0, rendering) {
            Ok(_) => {}
            Err(job::WallError::Comm(e)) => comm.fail(&e),
            Err(e) => comm.fail(&irradia_parallel::comm::CommError::Aborted(e.to_string())),
        }
    }
    comm.barrier().unwrap_or_else(|e| comm.fail(&e));
    if comm.rank() != 0 {
        return;
    }
    let (mut passed, mut failed) = (0, 0);
    for (label, rendering) in renderings {
        let (mpi_dir, local_dir) = dirs(label);
        let local = run_local(c.displays(), LocalOptions::default(), |l| {
            job::run_with(l, &c, &src, &local_dir, rendering).map(|_| ())
        });
        let threads_ok = local.iter().all(|r| matches!(r, Ok(Ok(()))));
        let (a, b) = (files(&mpi_dir), files(&local_dir));
        let names: Vec<&str> = a.iter().map(|(n, _)| n.as_str()).collect();
        let same = threads_ok && a == b && a.len() == c.displays() + 2;
        if same {
            passed += 1;
            println!(
                "ok   wall {label} np={}: {} files identical to the threads' run ({})",
                c.displays(),
                a.len(),
                names.join(", ")
            );
        } else {
            failed += 1;
            let differ: Vec<&str> = a
                .iter()
                .filter(|x| !b.contains(x))
                .map(|(n, _)| n.as_str())
                .collect();
            println!(
                "FAIL wall {label} np={}: MPI wrote {names:?}, differing from the threads' run: {differ:?} (threads ok: {threads_ok})",
                c.displays()
            );
        }
    }
    let _ = std::fs::remove_dir_all(&root);
    println!("{passed} passed, {failed} failed");
    if failed > 0 {
        std::process::exit(1);
    }
}
