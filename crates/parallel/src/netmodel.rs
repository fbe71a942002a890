//! The alpha-beta network model (Hockney 1994): a message of n bytes costs
//! `alpha + n / beta`. Applied to the messages a job recorded, it predicts how long the
//! communication stages would take on another network: each rank has one full-duplex
//! link that sends one message at a time and receives one at a time, so a stage takes
//! the longest per-rank sum of send costs or of receive costs. [`crate::comm::LocalOptions::delay`]
//! charges the same cost live, for runs that should feel the network.

use crate::comm::MessageRecord;
use serde::{Deserialize, Serialize};

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
}
