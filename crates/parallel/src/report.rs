//! What a parallel job measured, per rank and stage: bytes and messages sent and
//! received, wall time, and the load imbalance (slowest rank over the mean). Gathered at
//! rank 0 and serialisable to JSON (`--report FILE.json`).

use crate::comm::{Comm, CommError, MessageRecord};
use serde::{Deserialize, Serialize};

/// One rank's share of one stage.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RankStage {
    pub rank: usize,
    pub seconds: f64,
    pub bytes_sent: u64,
    pub bytes_received: u64,
    pub messages_sent: u64,
    pub messages_received: u64,
}

/// One stage over all ranks.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StageReport {
    pub name: String,
    pub ranks: Vec<RankStage>,
    /// Slowest rank's time over the mean time (1 = perfectly balanced).
    pub load_imbalance: f64,
    pub max_seconds: f64,
    pub total_bytes_sent: u64,
}

/// The whole job.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Report {
    pub ranks: usize,
    pub stages: Vec<StageReport>,
    /// Every message as recorded by its sender (for the network model).
    pub messages: Vec<MessageRecord>,
}

/// One rank's log: its message records and its (stage name, seconds) times.
#[derive(Serialize, Deserialize)]
pub struct RankLog {
    rank: usize,
    records: Vec<MessageRecord>,
    times: Vec<(String, f64)>,
}

impl Report {
    /// Builds the report from every rank's log (collective; `Some` at rank 0).
    pub fn gather<C: Comm>(comm: &C) -> Result<Option<Report>, CommError> {
        let mine = RankLog {
            rank: comm.rank(),
            records: comm.log().records(),
            times: comm.log().stage_times(),
        };
        let bytes = serde_json::to_vec(&mine).expect("serialising a log cannot fail");
        let all = comm.gather(0, &bytes)?;
        if comm.rank() != 0 {
            return Ok(None);
        }
        let mut logs = Vec::with_capacity(all.len());
        for (r, b) in all.iter().enumerate() {
            let l: RankLog = serde_json::from_slice(b).map_err(|e| CommError::Malformed {
                rank: r,
                message: format!("report: {e}"),
            })?;
            logs.push(l);
        }
        Ok(Some(Self::from_logs(&logs)))
    }

    /// Builds the report from every rank's log, index = rank.
    pub fn from_logs(logs: &[RankLog]) -> Report {
        let mut names: Vec<String> = Vec::new();
        for RankLog { records, times, .. } in logs {
            for (n, _) in times {
                if !names.contains(n) {
                    names.push(n.clone());
                }
            }
            for m in records {
                if !names.contains(&m.stage) {
                    names.push(m.stage.clone());
                }
            }
        }
        let stages = names
            .iter()
            .map(|name| {
                let ranks: Vec<RankStage> = logs
                    .iter()
                    .enumerate()
                    .map(|(rank, RankLog { records, times, .. })| {
                        let mut s = RankStage {
                            rank,
                            ..Default::default()
                        };
                        s.seconds = times
                            .iter()
                            .filter(|(n, _)| n == name)
                            .map(|(_, t)| t)
                            .sum();
                        for m in records.iter().filter(|m| &m.stage == name) {
                            if m.sent {
                                s.bytes_sent += m.bytes as u64;
                                s.messages_sent += 1;
                            } else {
                                s.bytes_received += m.bytes as u64;
                                s.messages_received += 1;
                            }
                        }
                        s
                    })
                    .collect();
                let max = ranks.iter().map(|r| r.seconds).fold(0.0, f64::max);
                let mean = ranks.iter().map(|r| r.seconds).sum::<f64>() / ranks.len().max(1) as f64;
                StageReport {
                    name: name.clone(),
                    load_imbalance: if mean > 0.0 { max / mean } else { 1.0 },
                    max_seconds: max,
                    total_bytes_sent: ranks.iter().map(|r| r.bytes_sent).sum(),
                    ranks,
                }
            })
            .collect();
        let messages = logs
            .iter()
            .flat_map(|l| l.records.iter().filter(|m| m.sent).cloned())
            .collect();
        Report {
            ranks: logs.len(),
            stages,
            messages,
        }
    }

    pub fn stage(&self, name: &str) -> Option<&StageReport> {
        self.stages.iter().find(|s| s.name == name)
    }

    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("serialising a report cannot fail")
    }
}
