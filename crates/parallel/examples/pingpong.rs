//! Ping-pong between MPI ranks 0 and 1 through Irradia's `Comm` (the path every
//! distributed job here takes), and Hockney's alpha-beta fit of the one-way times:
//! `mpirun -np 2 pingpong [--reps 200]`. Rank 0 prints one line per size and
//! `RESULT alpha_us=... bandwidth_mbit=...`, the arguments `irradia bench scale` takes
//! (bench/scale/run.sh runs both).

use irradia_parallel::comm::{Comm, MpiComm};
use irradia_parallel::netmodel::{ping_pong, NetModel};
use std::time::Duration;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let reps = a
        .iter()
        .position(|x| x == "--reps")
        .and_then(|i| a.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(200);
    let comm = MpiComm::init(Duration::from_secs(60)).expect("MPI initialises once");
    if comm.size() < 2 {
        eprintln!("pingpong: run it on 2 ranks (mpirun -np 2 pingpong)");
        std::process::exit(2);
    }
    let sizes: Vec<usize> = (0..=22).step_by(2).map(|e| 8usize << e).collect();
    let points = ping_pong(&comm, &sizes, reps).expect("ping-pong");
    if comm.rank() == 0 {
        let model = NetModel::fit(&points).expect("times grow with size");
        for p in &points {
            let m = model.message(p.bytes);
            println!(
                "bytes={} one_way_us={:.3} model_us={:.3} error={:+.1}%",
                p.bytes,
                p.seconds * 1e6,
                m * 1e6,
                100.0 * (m / p.seconds - 1.0)
            );
        }
        println!(
            "RESULT alpha_us={:.3} bandwidth_mbit={:.0}",
            model.alpha * 1e6,
            model.beta * 8.0 / 1e6
        );
    }
}
