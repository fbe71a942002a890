//! The alpha-beta network model (Hockney 1994): a message of n bytes costs
//! `alpha + n / beta`. Applied to the messages a job recorded, it predicts how long the
//! communication stages would take on another network: each rank has one full-duplex
//! link that sends one message at a time and receives one at a time, so a stage takes
//! the longest per-rank sum of send costs or of receive costs. [`crate::comm::LocalOptions::delay`]
//! charges the same cost live, for runs that should feel the network.

use crate::comm::{Comm, CommError, MessageRecord};
use serde::{Deserialize, Serialize};
use std::time::Instant;

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct NetModel {
    /// Latency per message in seconds.
    pub alpha: f64,
    /// Bandwidth in bytes per second.
    pub beta: f64,
}

impl NetModel {
    /// Gigabit ethernet as in the lecture's cluster study: 50 us, 125 MB/s.
    pub const GIGABIT_ETHERNET: NetModel = NetModel {
        alpha: 50e-6,
        beta: 125e6,
    };

    pub fn message(&self, bytes: usize) -> f64 {
        self.alpha + bytes as f64 / self.beta
    }

    /// Predicted time of the messages of `stage` (sender-side records) among `ranks`.
    pub fn stage_time(&self, messages: &[MessageRecord], stage: &str, ranks: usize) -> f64 {
        let mut send = vec![0.0; ranks];
        let mut recv = vec![0.0; ranks];
        for m in messages.iter().filter(|m| m.sent && m.stage == stage) {
            let t = self.message(m.bytes);
            send[m.src] += t;
            recv[m.dst] += t;
        }
        send.iter().chain(&recv).cloned().fold(0.0, f64::max)
    }
}

/// One size of a ping-pong: the median one-way time of `bytes`-byte messages.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PingPoint {
    pub bytes: usize,
    pub seconds: f64,
}

impl NetModel {
    /// Hockney's fit of `alpha + n / beta` to measured one-way times: least squares of
    /// the *relative* error (weights 1/t^2), so that the latency-bound small messages
    /// and the bandwidth-bound large ones count alike. `None` with fewer than two sizes
    /// or when the times do not grow with size.
    pub fn fit(points: &[PingPoint]) -> Option<NetModel> {
        // Minimise sum w (a + b n - t)^2 with w = 1/t^2 over (a, b): 2x2 normal equations.
        let (mut sw, mut sn, mut snn, mut st, mut snt) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for p in points.iter().filter(|p| p.seconds > 0.0) {
            let (n, t) = (p.bytes as f64, p.seconds);
            let w = 1.0 / (t * t);
            sw += w;
            sn += w * n;
            snn += w * n * n;
            st += w * t;
            snt += w * n * t;
        }
        let det = sw * snn - sn * sn;
        if points.len() < 2 || det <= 0.0 {
            return None;
        }
        let b = (sw * snt - sn * st) / det;
        let a = (st - b * sn) / sw;
        (b > 0.0).then_some(NetModel {
            alpha: a.max(0.0),
            beta: 1.0 / b,
        })
    }
}

/// Ping-pong between ranks 0 and 1 (the others wait at the final barrier): for each
/// size, `reps` round trips after one warm-up; the one-way time is half the median
/// round trip. Rank 0 gets the points, the others an empty list.
pub fn ping_pong<C: Comm>(
    comm: &C,
    sizes: &[usize],
    reps: usize,
) -> Result<Vec<PingPoint>, CommError> {
    const TAG: u32 = 0x7e00;
    let mut out = Vec::new();
    if comm.size() >= 2 && comm.rank() < 2 {
        let other = 1 - comm.rank();
        for &bytes in sizes {
            let msg = vec![0x5au8; bytes];
            let mut trips = Vec::with_capacity(reps);
            for r in 0..=reps.max(1) {
                let t = Instant::now();
                if comm.rank() == 0 {
                    comm.send(other, TAG, &msg)?;
                    comm.recv(other, TAG)?;
                } else {
                    let m = comm.recv(other, TAG)?;
                    comm.send(other, TAG, &m)?;
                }
                if r > 0 {
                    trips.push(t.elapsed().as_secs_f64());
                }
            }
            trips.sort_by(f64::total_cmp);
            out.push(PingPoint {
                bytes,
                seconds: trips[trips.len() / 2] / 2.0,
            });
        }
    }
    comm.barrier()?;
    Ok(if comm.rank() == 0 { out } else { Vec::new() })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn m(src: usize, dst: usize, bytes: usize) -> MessageRecord {
        MessageRecord {
            stage: "s".into(),
            src,
            dst,
            bytes,
            sent: true,
        }
    }

    #[test]
    fn alpha_beta_sums_per_link() {
        let n = NetModel {
            alpha: 1.0,
            beta: 10.0,
        };
        // rank 0 sends 2 messages of 10 bytes: 2 * (1 + 1) = 4; rank 2 receives both.
        let msgs = vec![m(0, 2, 10), m(0, 2, 10), m(1, 3, 0)];
        assert!((n.stage_time(&msgs, "s", 4) - 4.0).abs() < 1e-12);
        assert_eq!(n.stage_time(&msgs, "other", 4), 0.0);
    }

    #[test]
    fn the_fit_recovers_a_model_from_its_own_times() {
        let truth = NetModel {
            alpha: 1.7e-6,
            beta: 6.0e9,
        };
        let pts: Vec<PingPoint> = [8, 512, 32_768, 1 << 20, 1 << 23]
            .iter()
            .map(|&b| PingPoint {
                bytes: b,
                seconds: truth.message(b),
            })
            .collect();
        let f = NetModel::fit(&pts).unwrap();
        assert!((f.alpha / truth.alpha - 1.0).abs() < 1e-9, "{f:?}");
        assert!((f.beta / truth.beta - 1.0).abs() < 1e-9, "{f:?}");
        assert!(NetModel::fit(&pts[..1]).is_none());
    }

    #[test]
    fn ping_pong_over_threads_measures_growing_times() {
        use crate::comm::{run_local, LocalOptions};
        let out = run_local(3, LocalOptions::default(), |c| {
            ping_pong(c, &[8, 1 << 22], 5).unwrap()
        });
        let pts = out[0].as_ref().unwrap();
        assert_eq!(pts.len(), 2);
        assert!(
            pts[0].seconds > 0.0 && pts[1].seconds > pts[0].seconds,
            "{pts:?}"
        );
        assert!(out[1].as_ref().unwrap().is_empty() && out[2].as_ref().unwrap().is_empty());
    }
}
