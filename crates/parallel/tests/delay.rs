//! `LocalComm`'s delay mode (alpha-beta emulation of a network) against the alpha-beta
//! model (`netmodel`, Hockney 1994) applied to the messages a job recorded.
//!
//! Timing assertions here are lower bounds that the delay mode's sleeps guarantee
//! (a message cannot be delivered before `alpha + bytes / beta` after it was sent, and a
//! sender's link carries one message at a time), plus upper bounds that are hang guards,
//! not speed checks: ten times the model plus five seconds, so that only a delay mode
//! charging far too much (or a hang) fails them, never a loaded 2-core CI machine.

use irradia_parallel::comm::{run_local, Comm, LocalOptions};
use irradia_parallel::composite::{self, CompositeOptions, Layer, Strategy};
use irradia_parallel::netmodel::NetModel;
use std::time::{Duration, Instant};

fn delayed(model: NetModel) -> LocalOptions {
    LocalOptions {
        timeout: Duration::from_secs(30),
        delay: Some((model.alpha, model.beta)),
    }
}

/// Seconds from the earliest start to the latest end over the ranks.
fn span_of(times: &[(Instant, Instant)]) -> f64 {
    let start = times.iter().map(|t| t.0).min().unwrap();
    let end = times.iter().map(|t| t.1).max().unwrap();
    (end - start).as_secs_f64()
}

#[test]
fn a_message_takes_at_least_alpha_plus_bytes_over_beta() {
    let model = NetModel {
        alpha: 0.030,
        beta: 1e6,
    };
    let bytes = 40_000; // 30 ms + 40 ms
    let out = run_local(2, delayed(model), |c| {
        if c.rank() == 0 {
            let sent = Instant::now();
            c.send(1, 7, &vec![1u8; bytes]).unwrap();
            sent
        } else {
            let m = c.recv(0, 7).unwrap();
            assert_eq!(m.len(), bytes);
            Instant::now()
        }
    });
    let (sent, got) = (*out[0].as_ref().unwrap(), *out[1].as_ref().unwrap());
    let took = (got - sent).as_secs_f64();
    let want = model.message(bytes);
    assert!(want > 0.069 && want < 0.071);
    assert!(
        took >= want,
        "delivered after {took:.4} s, model {want:.4} s"
    );
    assert!(took <= 10.0 * want + 5.0, "delivered after {took:.4} s");

    // Without the delay mode the same message is not held back.
    let fast = run_local(2, LocalOptions::default(), |c| {
        let t = Instant::now();
        if c.rank() == 0 {
            c.send(1, 7, &vec![1u8; bytes]).unwrap();
        } else {
            c.recv(0, 7).unwrap();
        }
        t.elapsed().as_secs_f64()
    });
    // (Only a hang guard: load can slow a send, the delay mode's absence is the point.)
    assert!(LocalOptions::default().delay.is_none());
    assert!(fast
        .iter()
        .all(|t| *t.as_ref().unwrap() < 10.0 * want + 5.0));
}

#[test]
fn a_link_carries_one_message_at_a_time_and_the_model_agrees() {
    // A ring: every rank sends `m` messages to the next and receives `m` from the
    // previous. The model charges m (alpha + n / beta) per link; the emulation overlaps
    // the latencies but not the wire times, so the last message lands at least
    // alpha + m n / beta after the first was sent.
    let model = NetModel {
        alpha: 0.004,
        beta: 1e6,
    };
    let (p, m, n) = (3, 3, 12_000); // 12 ms of wire per message
    let out = run_local(p, delayed(model), |c| {
        let (r, p) = (c.rank(), c.size());
        c.barrier().unwrap();
        let t0 = Instant::now();
        c.log().begin_stage("ring");
        for _ in 0..m {
            c.send((r + 1) % p, 9, &vec![r as u8; n]).unwrap();
        }
        for _ in 0..m {
            let got = c.recv((r + p - 1) % p, 9).unwrap();
            assert_eq!(got.len(), n);
        }
        c.log().end_stage();
        ((t0, Instant::now()), c.log().records())
    });
    let out: Vec<_> = out.into_iter().map(|o| o.unwrap()).collect();
    let times: Vec<_> = out.iter().map(|o| o.0).collect();
    let records: Vec<_> = out.iter().flat_map(|o| o.1.clone()).collect();
    let measured = span_of(&times);
    let predicted = model.stage_time(&records, "ring", p);
    let wire = n as f64 / model.beta;
    assert!((predicted - m as f64 * (model.alpha + wire)).abs() < 1e-9);
    assert!(
        measured >= model.alpha + m as f64 * wire,
        "ring took {measured:.4} s"
    );
    // The model and the emulation differ only by the overlapped latencies.
    assert!(
        predicted <= 2.0 * measured,
        "model {predicted:.4} s, ran {measured:.4} s"
    );
    assert!(
        measured <= 10.0 * predicted + 5.0,
        "model {predicted:.4} s, ran {measured:.4} s"
    );
}

#[test]
fn binary_swap_under_the_delay_mode_matches_the_model_of_its_messages() {
    let model = NetModel {
        alpha: 0.002,
        beta: 2e6,
    };
    let (w, h, p) = (64u32, 48u32, 4);
    let out = run_local(p, delayed(model), |c| {
        // Dense layers with distinct depths: every rank sends the same bytes.
        let mut l = Layer::<[u8; 4]>::new(w, h);
        for (i, (c8, d)) in l.color.iter_mut().zip(&mut l.depth).enumerate() {
            let v = (i * 7 + c.rank() * 13) % 251;
            *c8 = [v as u8, 0, 0, 255];
            *d = v as f32 + c.rank() as f32 * 0.5;
        }
        c.barrier().unwrap();
        let t0 = Instant::now();
        c.log().begin_stage("swap");
        let opts = CompositeOptions {
            rle: false,
            ..Default::default()
        };
        let (_, span) = composite::reduce(c, Strategy::BinarySwap, l, &opts).unwrap();
        c.log().end_stage();
        ((t0, Instant::now()), c.log().records(), span.len())
    });
    let out: Vec<_> = out.into_iter().map(|o| o.unwrap()).collect();
    assert_eq!(out.iter().map(|o| o.2).sum::<usize>(), (w * h) as usize);
    let times: Vec<_> = out.iter().map(|o| o.0).collect();
    let records: Vec<_> = out.iter().flat_map(|o| o.1.clone()).collect();
    let sent: usize = records.iter().filter(|r| r.sent).map(|r| r.bytes).sum();
    // Each rank gives away 3/4 of a 64x48 RGBA8 + depth image, plus a 32-byte header
    // in each of its 2 rounds.
    let payload = p * (w * h) as usize * 8 * 3 / 4;
    assert!(
        sent >= payload && sent <= payload + 2 * 32 * p,
        "sent {sent}"
    );
    let measured = span_of(&times);
    let predicted = model.stage_time(&records, "swap", p);
    // The two rounds are sequential and each needs the partner's header and pieces, so
    // the run takes at least 2 alpha + the wire time per round: at least half the model
    // (which charges alpha per message, the emulation only once per round trip).
    let wire = (w * h) as f64 * 8.0 * 3.0 / 4.0 / model.beta;
    assert!(measured >= 4.0 * model.alpha + wire, "ran {measured:.4} s");
    assert!(
        predicted <= 2.0 * measured,
        "model {predicted:.4} s, ran {measured:.4} s"
    );
    assert!(
        measured <= 10.0 * predicted + 5.0,
        "model {predicted:.4} s, ran {measured:.4} s"
    );
}
