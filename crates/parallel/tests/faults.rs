//! A rank that never answers, or dies, ends the job on every rank with an error naming
//! it, within the timeout; never a hang.

use irradia_parallel::comm::{run_local, Comm, CommError, LocalOptions};
use irradia_parallel::composite::{self, CompositeOptions, Layer, Strategy};
use std::time::{Duration, Instant};

/// A hang guard, not a speed check: a job that deadlocks never ends, and a loaded 2-core
/// CI machine may take many times the timeout to notice a silent rank, so the bound is
/// generous. The errors' content is what these tests check.
const HANG_GUARD: Duration = Duration::from_secs(60);

fn opts() -> LocalOptions {
    LocalOptions {
        timeout: Duration::from_millis(200),
        delay: None,
    }
}

#[test]
fn a_silent_rank_is_named_on_every_rank() {
    for s in [
        Strategy::BinarySwap,
        Strategy::DirectSend,
        Strategy::Tree,
        Strategy::RadixK(4),
    ] {
        let t0 = Instant::now();
        let out = run_local(5, opts(), |c| {
            if c.rank() == 2 {
                std::thread::sleep(Duration::from_millis(600));
                return Ok(None);
            }
            let l = Layer::<[u8; 4]>::new(16, 8);
            composite::composite(c, s, l, &CompositeOptions::default())
        });
        assert!(
            t0.elapsed() < HANG_GUARD,
            "{}: took {:?}",
            s.name(),
            t0.elapsed()
        );
        for (r, res) in out.into_iter().enumerate() {
            if r == 2 {
                continue;
            }
            let e = res.unwrap().expect_err("the job must fail");
            assert_eq!(e.culprit(), Some(2), "{}: rank {r} blamed {e}", s.name());
            assert!(e.to_string().contains("rank 2"), "{e}");
        }
    }
}

#[test]
fn a_dead_rank_is_named() {
    let out = run_local(4, opts(), |c| {
        if c.rank() == 3 {
            panic!("simulated crash");
        }
        c.barrier()?;
        Ok::<(), CommError>(())
    });
    assert!(out[3].is_err());
    for res in &out[..3] {
        let e = res
            .as_ref()
            .unwrap()
            .as_ref()
            .expect_err("the job must fail");
        assert_eq!(e.culprit(), Some(3), "{e}");
    }
}

#[test]
fn barrier_and_all_to_all_work() {
    let out = run_local(6, LocalOptions::default(), |c| {
        c.barrier().unwrap();
        let bufs: Vec<Vec<u8>> = (0..c.size())
            .map(|j| vec![c.rank() as u8, j as u8])
            .collect();
        c.all_to_all(&bufs).unwrap()
    });
    for (r, got) in out.into_iter().enumerate() {
        let got = got.unwrap();
        for (j, b) in got.iter().enumerate() {
            assert_eq!(b, &vec![j as u8, r as u8]);
        }
    }
}
