//! Binary-swap compositing benchmark over MPI (bench/composite/run.sh runs it):
//! `mpirun -np P composite_bench [--width 1280] [--height 720] [--reps 9]`.
//!
//! Measures, in one run: the MPI ping-pong bandwidth for a message the size of a whole
//! RGBA8 + f32-depth image; binary swap (the reduce-scatter, without the final gather)
//! of a dense image and of a 10%-active one; and the bytes-over-bandwidth bound
//! S(1 - 1/p) / bandwidth. Times are the slowest rank's, median over the repetitions,
//! each started after a barrier. Rank 0 prints `RESULT key=value ...` lines.

use irradia_parallel::comm::{Comm, MpiComm};
use irradia_parallel::composite::{self, CompositeOptions, Layer, Strategy};
use std::time::{Duration, Instant};

fn arg(name: &str, default: usize) -> usize {
    let a: Vec<String> = std::env::args().collect();
    a.iter()
        .position(|x| x == name)
        .and_then(|i| a.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn hash(i: u64) -> u32 {
    let mut z = i.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    (z ^ (z >> 31)) as u32
}

/// A layer whose pixels are active inside a centred rectangle covering `fraction`.
fn layer(w: u32, h: u32, rank: usize, fraction: f64) -> Layer<[u8; 4]> {
    let mut l = Layer::<[u8; 4]>::new(w, h);
    let s = fraction.sqrt();
    let (rw, rh) = ((w as f64 * s) as u32, (h as f64 * s) as u32);
    let (x0, y0) = ((w - rw) / 2, (h - rh) / 2);
    for y in y0..y0 + rh {
        for x in x0..x0 + rw {
            let i = (y * w + x) as usize;
            let v = hash(i as u64 ^ ((rank as u64) << 40));
            l.color[i] = v.to_le_bytes();
            l.color[i][3] = 255;
            l.depth[i] = (v >> 8) as f32 / (1u32 << 24) as f32;
        }
    }
    l
}

fn slowest<C: Comm>(c: &C, t: f64) -> f64 {
    let all = c
        .gather(0, &t.to_le_bytes())
        .unwrap_or_else(|_| std::process::exit(3));
    all.iter()
        .map(|b| f64::from_le_bytes(b[..8].try_into().unwrap()))
        .fold(0.0, f64::max)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

fn main() {
    let comm = MpiComm::init(Duration::from_secs(60)).expect("MPI initialises once");
    let (w, h, reps) = (
        arg("--width", 1280) as u32,
        arg("--height", 720) as u32,
        arg("--reps", 9),
    );
    let (rank, p) = (comm.rank(), comm.size());
    let image_bytes = w as usize * h as usize * 8;

    // Ping-pong between ranks 0 and 1 with a whole image.
    let mut bw = f64::NAN;
    if p >= 2 {
        let msg = vec![7u8; image_bytes];
        let mut times = Vec::new();
        for _ in 0..reps.max(3) {
            comm.barrier().unwrap_or_else(|e| comm.fail(&e));
            let t0 = Instant::now();
            if rank == 0 {
                comm.send(1, 1, &msg).unwrap_or_else(|e| comm.fail(&e));
                comm.recv(1, 2).unwrap_or_else(|e| comm.fail(&e));
            } else if rank == 1 {
                let m = comm.recv(0, 1).unwrap_or_else(|e| comm.fail(&e));
                comm.send(0, 2, &m).unwrap_or_else(|e| comm.fail(&e));
            }
            times.push(t0.elapsed().as_secs_f64() / 2.0);
        }
        bw = image_bytes as f64 / median(times);
    }

    let mut results = Vec::new();
    for (name, fraction) in [("dense", 1.0), ("active10", 0.10)] {
        let base = layer(w, h, rank, fraction);
        let opts = CompositeOptions::default();
        let mut times = Vec::new();
        for _ in 0..reps {
            let l = base.clone();
            comm.barrier().unwrap_or_else(|e| comm.fail(&e));
            let t0 = Instant::now();
            let (out, span) = composite::reduce(&comm, Strategy::BinarySwap, l, &opts)
                .unwrap_or_else(|e| comm.fail(&e));
            let t = t0.elapsed().as_secs_f64();
            std::hint::black_box((out, span));
            times.push(slowest(&comm, t));
        }
        results.push((name, median(times)));
    }
    if rank == 0 {
        let pw = if p.is_power_of_two() {
            p
        } else {
            p.next_power_of_two() / 2
        };
        let bytes_per_rank = image_bytes as f64 * (1.0 - 1.0 / pw as f64);
        let bound = bytes_per_rank / bw;
        println!(
            "RESULT np={p} width={w} height={h} pingpong_gbps={:.3} bound_ms={:.3}",
            bw / 1e9,
            bound * 1e3
        );
        for (name, t) in &results {
            println!(
                "RESULT np={p} case={name} median_ms={:.3} over_bound={:.2}",
                t * 1e3,
                t / bound
            );
        }
        let dense = results[0].1;
        let sparse = results[1].1;
        println!("RESULT np={p} dense_over_active10={:.2}", dense / sparse);
    }
}
