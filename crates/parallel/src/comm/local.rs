//! `LocalComm`: the ranks of a job as threads of one process, joined by channels.
//!
//! One channel per ordered pair of ranks keeps messages from one source in order;
//! messages with another tag wait in a per-source queue until asked for. A receive
//! polls in short slices so that it can notice a job-wide abort, and gives up after the
//! timeout, blaming the silent rank; the first fault is shared with every rank, so the
//! whole job ends with the same error naming the culprit.
//!
//! The delay mode charges each message `alpha + bytes / beta` (a sender's link carries
//! one message at a time), so the lecture's cluster study can be re-enacted on one
//! machine; see [`crate::netmodel`].

use super::{Comm, CommError, MessageLog};
use std::collections::VecDeque;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError, Sender};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Options of a local job.
#[derive(Clone, Debug)]
pub struct LocalOptions {
    /// How long a receive waits before blaming the silent rank.
    pub timeout: Duration,
    /// Simulated network: (latency in seconds, bandwidth in bytes per second).
    pub delay: Option<(f64, f64)>,
}

impl Default for LocalOptions {
    fn default() -> Self {
        Self {
            timeout: Duration::from_secs(30),
            delay: None,
        }
    }
}

struct Envelope {
    tag: u32,
    data: Vec<u8>,
    deliver_at: Option<Instant>,
}

/// One rank of a [`run_local`] job.
pub struct LocalComm {
    rank: usize,
    size: usize,
    options: LocalOptions,
    to: Vec<Sender<Envelope>>,
    from: Vec<Mutex<Receiver<Envelope>>>,
    pending: Vec<Mutex<VecDeque<Envelope>>>,
    abort: Arc<Mutex<Option<CommError>>>,
    link_free_at: Mutex<Instant>,
    /// Shared wait-for graph: `waiting_on[r]` is the rank r is blocked on (or `IDLE`).
    waiting_on: Arc<Vec<AtomicUsize>>,
    log: MessageLog,
}

const IDLE: usize = usize::MAX;

impl LocalComm {
    /// Ends the job on every rank with `error` (the first fault wins).
    pub fn abort(&self, error: CommError) {
        let mut g = self.abort.lock().unwrap();
        if g.is_none() {
            *g = Some(error);
        }
    }

    /// The fault that ended the job, if any.
    pub fn aborted(&self) -> Option<CommError> {
        self.abort.lock().unwrap().clone()
    }

    /// Follows the wait-for chain from `src`: the first rank that is not itself waiting
    /// is the one that never answered (a ring of waiters blames `src`).
    fn blame(&self, src: usize) -> usize {
        let mut r = src;
        for _ in 0..self.size {
            let next = self.waiting_on[r].load(Ordering::SeqCst);
            if next == IDLE {
                return r;
            }
            r = next;
        }
        src
    }

    fn take_pending(&self, src: usize, tag: u32) -> Option<Envelope> {
        let mut q = self.pending[src].lock().unwrap();
        let i = q.iter().position(|e| e.tag == tag)?;
        q.remove(i)
    }

    fn deliver(&self, src: usize, e: Envelope) -> Vec<u8> {
        if let Some(t) = e.deliver_at {
            let now = Instant::now();
            if t > now {
                std::thread::sleep(t - now);
            }
        }
        self.log.record(src, self.rank, e.data.len(), false);
        e.data
    }
}

impl Comm for LocalComm {
    fn rank(&self) -> usize {
        self.rank
    }
    fn size(&self) -> usize {
        self.size
    }
    fn timeout(&self) -> Duration {
        self.options.timeout
    }
    fn log(&self) -> &MessageLog {
        &self.log
    }

    fn send(&self, dest: usize, tag: u32, data: &[u8]) -> Result<(), CommError> {
        if dest >= self.size {
            return Err(CommError::BadRank {
                rank: dest,
                size: self.size,
            });
        }
        if let Some(e) = self.aborted() {
            return Err(e);
        }
        let deliver_at = self.options.delay.map(|(alpha, beta)| {
            let now = Instant::now();
            let mut free = self.link_free_at.lock().unwrap();
            let start = (*free).max(now);
            let wire = Duration::from_secs_f64(data.len() as f64 / beta);
            *free = start + wire;
            start + wire + Duration::from_secs_f64(alpha)
        });
        self.log.record(self.rank, dest, data.len(), true);
        self.to[dest]
            .send(Envelope {
                tag,
                data: data.to_vec(),
                deliver_at,
            })
            .map_err(|_| {
                let e = CommError::RankDied { rank: dest };
                self.abort(e.clone());
                e
            })
    }

    fn try_recv_any(
        &self,
        sources: &[usize],
        tag: u32,
    ) -> Result<Option<(usize, Vec<u8>)>, CommError> {
        if let Some(e) = self.aborted() {
            return Err(e);
        }
        for &src in sources {
            if src >= self.size {
                return Err(CommError::BadRank {
                    rank: src,
                    size: self.size,
                });
            }
            if let Some(e) = self.take_pending(src, tag) {
                return Ok(Some((src, self.deliver(src, e))));
            }
            let rx = self.from[src].lock().unwrap();
            loop {
                match rx.try_recv() {
                    Ok(e) if e.tag == tag => return Ok(Some((src, self.deliver(src, e)))),
                    Ok(e) => self.pending[src].lock().unwrap().push_back(e),
                    Err(std::sync::mpsc::TryRecvError::Empty) => break,
                    Err(std::sync::mpsc::TryRecvError::Disconnected) => {
                        let e = CommError::RankDied { rank: src };
                        self.abort(e.clone());
                        return Err(e);
                    }
                }
            }
        }
        Ok(None)
    }

    fn recv(&self, src: usize, tag: u32) -> Result<Vec<u8>, CommError> {
        if src >= self.size {
            return Err(CommError::BadRank {
                rank: src,
                size: self.size,
            });
        }
        if let Some(e) = self.take_pending(src, tag) {
            return Ok(self.deliver(src, e));
        }
        let start = Instant::now();
        let deadline = start + self.options.timeout;
        let rx = self.from[src].lock().unwrap();
        self.waiting_on[self.rank].store(src, Ordering::SeqCst);
        let result = self.recv_loop(&rx, src, tag, deadline);
        self.waiting_on[self.rank].store(IDLE, Ordering::SeqCst);
        result
    }
}

impl LocalComm {
    fn recv_loop(
        &self,
        rx: &Receiver<Envelope>,
        src: usize,
        tag: u32,
        deadline: Instant,
    ) -> Result<Vec<u8>, CommError> {
        loop {
            if let Some(e) = self.aborted() {
                return Err(e);
            }
            let now = Instant::now();
            if now >= deadline {
                let e = CommError::Timeout {
                    rank: self.blame(src),
                    waiting_rank: self.rank,
                    tag,
                    seconds: self.options.timeout.as_secs_f64(),
                };
                self.abort(e.clone());
                return Err(e);
            }
            let slice = (deadline - now).min(Duration::from_millis(20));
            match rx.recv_timeout(slice) {
                Ok(e) if e.tag == tag => return Ok(self.deliver(src, e)),
                Ok(e) => self.pending[src].lock().unwrap().push_back(e),
                Err(RecvTimeoutError::Timeout) => {}
                Err(RecvTimeoutError::Disconnected) => {
                    if let Some(e) = self.aborted() {
                        return Err(e);
                    }
                    let e = CommError::RankDied { rank: src };
                    self.abort(e.clone());
                    return Err(e);
                }
            }
        }
    }
}

/// Runs `f` on `size` ranks, each a thread with its own [`LocalComm`], and returns what
/// each rank returned (rank order). A rank that panics aborts the job: the others' next
/// receive fails with an error naming it, and its own entry is `Err` with the message.
pub fn run_local<T, F>(size: usize, options: LocalOptions, f: F) -> Vec<Result<T, CommError>>
where
    T: Send,
    F: Fn(&LocalComm) -> T + Sync,
{
    assert!(size >= 1, "a job needs at least one rank");
    let abort = Arc::new(Mutex::new(None));
    let waiting_on: Arc<Vec<AtomicUsize>> =
        Arc::new((0..size).map(|_| AtomicUsize::new(IDLE)).collect());
    // channel (src -> dst): senders[src][dst], receivers[dst][src]
    let mut senders: Vec<Vec<Sender<Envelope>>> = (0..size).map(|_| Vec::new()).collect();
    let mut receivers: Vec<Vec<Option<Receiver<Envelope>>>> = (0..size)
        .map(|_| (0..size).map(|_| None).collect())
        .collect();
    for (src, row) in senders.iter_mut().enumerate() {
        for (dst, rx_row) in receivers.iter_mut().enumerate() {
            let (tx, rx) = channel();
            row.push(tx);
            rx_row[src] = Some(rx);
            let _ = dst;
        }
    }
    let comms: Vec<LocalComm> = senders
        .into_iter()
        .zip(receivers)
        .enumerate()
        .map(|(rank, (to, from))| LocalComm {
            rank,
            size,
            options: options.clone(),
            to,
            from: from.into_iter().map(|r| Mutex::new(r.unwrap())).collect(),
            pending: (0..size).map(|_| Mutex::new(VecDeque::new())).collect(),
            abort: abort.clone(),
            link_free_at: Mutex::new(Instant::now()),
            waiting_on: waiting_on.clone(),
            log: MessageLog::default(),
        })
        .collect();
    let f = &f;
    std::thread::scope(|s| {
        let handles: Vec<_> = comms
            .into_iter()
            .map(|comm| {
                s.spawn(move || {
                    let r = catch_unwind(AssertUnwindSafe(|| f(&comm)));
                    match r {
                        Ok(v) => Ok(v),
                        Err(payload) => {
                            let msg = payload
                                .downcast_ref::<String>()
                                .cloned()
                                .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                                .unwrap_or_else(|| "panic".into());
                            let e = CommError::Aborted(format!("rank {} died: {msg}", comm.rank));
                            comm.abort(CommError::RankDied { rank: comm.rank });
                            Err(e)
                        }
                    }
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|_| Err(CommError::Aborted("thread lost".into())))
            })
            .collect()
    })
}
