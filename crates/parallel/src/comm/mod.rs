//! The communicator every parallel algorithm is written against.
//!
//! A [`Comm`] is a group of `size` ranks that exchange byte buffers. [`LocalComm`] runs
//! the ranks as threads of one process (tests, one machine); `MpiComm` (cargo feature
//! `mpi`) runs the same code under `mpirun`. Algorithms never know which one they have.
//!
//! Every receive has a deadline: a rank that dies or never answers ends the job on every
//! rank with a [`CommError`] naming it, never a hang. Every message is recorded in a
//! [`MessageLog`] under the current stage, from which the per-rank [`crate::report`] and
//! the alpha-beta [`crate::netmodel`] are computed.

pub mod local;
#[cfg(feature = "mpi")]
pub mod mpi;

pub use local::{run_local, LocalComm, LocalOptions};
#[cfg(feature = "mpi")]
pub use mpi::MpiComm;

use std::sync::Mutex;
use std::time::{Duration, Instant};
use thiserror::Error;

/// Why a communication failed. Every variant names the rank at fault.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum CommError {
    #[error("rank {rank} did not answer within {seconds:.3} s (noticed by rank {waiting_rank}, tag {tag:#x})")]
    Timeout {
        rank: usize,
        waiting_rank: usize,
        tag: u32,
        seconds: f64,
    },
    #[error("rank {rank} died (its end of the connection closed)")]
    RankDied { rank: usize },
    #[error("job aborted: {0}")]
    Aborted(String),
    #[error("rank {rank} is out of range for a communicator of {size} ranks")]
    BadRank { rank: usize, size: usize },
    #[error("malformed message from rank {rank}: {message}")]
    Malformed { rank: usize, message: String },
}

impl CommError {
    /// The rank this error blames (the one that died, never answered or sent garbage).
    pub fn culprit(&self) -> Option<usize> {
        match self {
            CommError::Timeout { rank, .. }
            | CommError::RankDied { rank }
            | CommError::BadRank { rank, .. }
            | CommError::Malformed { rank, .. } => Some(*rank),
            CommError::Aborted(_) => None,
        }
    }
}

/// One message as seen by the rank that sent or received it.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MessageRecord {
    pub stage: String,
    pub src: usize,
    pub dst: usize,
    pub bytes: usize,
    /// True on the sending side.
    pub sent: bool,
}

/// The messages one rank sent and received, grouped by named stage, with the wall time
/// each stage took on this rank.
#[derive(Default)]
pub struct MessageLog {
    inner: Mutex<LogInner>,
    /// Told each stage's name as it begins ([`MessageLog::on_stage`]).
    observer: Mutex<Option<StageObserver>>,
}

/// What [`MessageLog::on_stage`] calls.
pub type StageObserver = Box<dyn Fn(&str) + Send>;

impl std::fmt::Debug for MessageLog {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MessageLog")
            .field("inner", &self.inner)
            .finish_non_exhaustive()
    }
}

#[derive(Debug, Default)]
struct LogInner {
    stage: String,
    stage_start: Option<Instant>,
    records: Vec<MessageRecord>,
    /// (stage, seconds) in the order stages ended.
    times: Vec<(String, f64)>,
}

impl MessageLog {
    /// Ends the current stage (recording its time) and starts `name`.
    pub fn begin_stage(&self, name: &str) {
        {
            let mut g = self.inner.lock().unwrap();
            if let Some(t0) = g.stage_start.take() {
                let s = g.stage.clone();
                g.times.push((s, t0.elapsed().as_secs_f64()));
            }
            g.stage = name.to_string();
            g.stage_start = Some(Instant::now());
        }
        if let Some(tell) = self.observer.lock().unwrap().as_ref() {
            tell(name);
        }
    }

    /// Calls `tell` with each stage's name as it begins, from the rank's own thread (a
    /// front end's progress display; replaces an earlier observer).
    pub fn on_stage(&self, tell: impl Fn(&str) + Send + 'static) {
        *self.observer.lock().unwrap() = Some(Box::new(tell));
    }

    /// Ends the current stage without starting another.
    pub fn end_stage(&self) {
        let mut g = self.inner.lock().unwrap();
        if let Some(t0) = g.stage_start.take() {
            let s = g.stage.clone();
            g.times.push((s, t0.elapsed().as_secs_f64()));
        }
        g.stage.clear();
    }

    pub fn record(&self, src: usize, dst: usize, bytes: usize, sent: bool) {
        let mut g = self.inner.lock().unwrap();
        let stage = g.stage.clone();
        g.records.push(MessageRecord {
            stage,
            src,
            dst,
            bytes,
            sent,
        });
    }

    /// All messages recorded so far.
    pub fn records(&self) -> Vec<MessageRecord> {
        self.inner.lock().unwrap().records.clone()
    }

    /// Stage times recorded so far, in order.
    pub fn stage_times(&self) -> Vec<(String, f64)> {
        self.inner.lock().unwrap().times.clone()
    }

    /// Forgets everything (between benchmark repetitions).
    pub fn clear(&self) {
        let mut g = self.inner.lock().unwrap();
        g.records.clear();
        g.times.clear();
        g.stage_start = None;
        g.stage.clear();
    }
}

/// The error for piece `piece` of an [`Comm::exchange_pieces`] that arrived with `got`
/// bytes instead of `want`.
pub(crate) fn check_piece_len(
    src: usize,
    piece: usize,
    got: usize,
    want: usize,
) -> Result<(), CommError> {
    if got == want {
        Ok(())
    } else {
        Err(CommError::Malformed {
            rank: src,
            message: format!("piece {piece} has {got} bytes, expected {want}"),
        })
    }
}

/// What [`Comm::exchange_pieces`] calls as each received piece is complete: the piece's
/// index and the pieces received so far (`0..=index`).
pub type PieceArrived<'a> = dyn FnMut(usize, &[&[u8]]) -> Result<(), CommError> + 'a;

/// What [`Comm::exchange_pieces_many`] calls as each received piece is complete: the
/// index of its source in `recvs`, the piece's index, and that source's pieces received
/// so far (`0..=index`).
pub type PiecesArrived<'a> = dyn FnMut(usize, usize, &[&[u8]]) -> Result<(), CommError> + 'a;

/// Pieces to send to one rank: `(rank, pieces)`.
pub type PiecesOut<'a> = (usize, Vec<&'a [u8]>);
/// Buffers for the pieces of one rank: `(rank, buffers)`.
pub type PiecesIn<'a> = (usize, Vec<&'a mut [u8]>);

/// Tags below this are free for algorithms; the ones above are used by the defaults here.
pub const TAG_BARRIER: u32 = 0x7fff_0000;
pub const TAG_ALL_TO_ALL: u32 = 0x7fff_0001;
pub const TAG_GATHER: u32 = 0x7fff_0002;
pub const TAG_BCAST: u32 = 0x7fff_0003;

/// A group of ranks exchanging byte buffers (see the module documentation).
pub trait Comm {
    fn rank(&self) -> usize;
    fn size(&self) -> usize;

    /// How long a receive waits before it blames the silent rank.
    fn timeout(&self) -> Duration;

    /// Sends `data` to `dest` with `tag`. May return before `dest` received it, but an
    /// implementation may also block until it is matched: use [`Comm::exchange`] when two
    /// ranks send to each other.
    fn send(&self, dest: usize, tag: u32, data: &[u8]) -> Result<(), CommError>;

    /// Sends `data` to `dest` with `tag` without waiting for `dest` to receive it,
    /// however large (the buffer is kept until it is delivered): for protocols in
    /// which two ranks may send to each other at any time (a master and its workers).
    /// The default sends with [`Comm::send`], which is right where sends never wait.
    fn post(&self, dest: usize, tag: u32, data: Vec<u8>) -> Result<(), CommError> {
        self.send(dest, tag, &data)
    }

    /// Moves this rank's posted sends along. MPI delivers a large message only while
    /// its sender is inside an MPI call, so a rank that computes for long after
    /// [`Comm::post`] calls this now and then. The default has nothing to do.
    fn progress(&self) {}

    /// Receives the next message from `src` with `tag`, or fails after [`Comm::timeout`].
    fn recv(&self, src: usize, tag: u32) -> Result<Vec<u8>, CommError>;

    /// The message log of this rank.
    fn log(&self) -> &MessageLog;

    /// The next message with `tag` from any rank of `sources` that has one waiting,
    /// with the rank it came from; `None` when none has arrived (does not wait).
    fn try_recv_any(
        &self,
        sources: &[usize],
        tag: u32,
    ) -> Result<Option<(usize, Vec<u8>)>, CommError>;

    /// The next message with `tag` from whichever rank of `sources` sends first, with
    /// that rank (a master handing out work to whoever finishes). Fails after
    /// [`Comm::timeout`] blaming the first of `sources`.
    fn recv_any(&self, sources: &[usize], tag: u32) -> Result<(usize, Vec<u8>), CommError> {
        let deadline = Instant::now() + self.timeout();
        let mut spins = 0u32;
        loop {
            if let Some(m) = self.try_recv_any(sources, tag)? {
                return Ok(m);
            }
            let culprit = *sources
                .first()
                .ok_or(CommError::Aborted("recv_any from no rank".into()))?;
            if Instant::now() >= deadline {
                return Err(CommError::Timeout {
                    rank: culprit,
                    waiting_rank: self.rank(),
                    tag,
                    seconds: self.timeout().as_secs_f64(),
                });
            }
            // Spin briefly (a reply is often microseconds away), then sleep in short
            // slices so that a waiting rank leaves its core to the renderers.
            spins += 1;
            if spins < 64 {
                std::thread::yield_now();
            } else {
                std::thread::sleep(Duration::from_micros(200));
            }
        }
    }

    /// Sends each `(dest, bytes)` and receives one message from each of `sources`, all
    /// with `tag`, without deadlock whatever the pattern. Returns the received buffers in
    /// the order of `sources`.
    fn exchange(
        &self,
        sends: &[(usize, &[u8])],
        sources: &[usize],
        tag: u32,
    ) -> Result<Vec<Vec<u8>>, CommError> {
        for (d, b) in sends {
            self.send(*d, tag, b)?;
        }
        sources.iter().map(|&s| self.recv(s, tag)).collect()
    }

    /// [`Comm::exchange`] that receives into `into` (one buffer per source, resized to
    /// each message), so that a caller exchanging every frame reuses its allocations.
    /// The default receives through `exchange`; `MpiComm` receives in place.
    fn exchange_into(
        &self,
        sends: &[(usize, &[u8])],
        sources: &[usize],
        tag: u32,
        into: &mut Vec<Vec<u8>>,
    ) -> Result<(), CommError> {
        *into = self.exchange(sends, sources, tag)?;
        Ok(())
    }

    /// A pairwise exchange in pieces, for overlapping the transfer with work on what has
    /// already arrived: sends every piece of `sends` to `partner` and receives the
    /// partner's pieces into `recvs` (piece i must arrive with exactly `recvs[i].len()`
    /// bytes), all with `tag`. As soon as piece i and every earlier one are in, calls
    /// `arrived(i, pieces)` with the received pieces `0..=i`, while later pieces may still
    /// be in flight. Pieces from one sender arrive in order. It is
    /// [`Comm::exchange_pieces_many`] with one partner each way.
    fn exchange_pieces(
        &self,
        partner: usize,
        tag: u32,
        sends: &[&[u8]],
        recvs: &mut [&mut [u8]],
        arrived: &mut PieceArrived<'_>,
    ) -> Result<(), CommError> {
        let out = [(partner, sends.to_vec())];
        let mut into = [(partner, recvs.iter_mut().map(|r| &mut **r).collect())];
        self.exchange_pieces_many(tag, &out, &mut into, &mut |_, i, done| arrived(i, done))
    }

    /// [`Comm::exchange_pieces`] with any number of partners, each way: sends the pieces
    /// of every `sends` entry to its rank and receives every `recvs` entry's pieces from
    /// its rank into its buffers (exact lengths), all with `tag`. The ranks sent to and
    /// received from need not be the same (a one-way transfer has an empty side). Pieces
    /// are taken in the order of `recvs` (all of the first source's, then the second's):
    /// `arrived(j, i, pieces)` runs when piece i of source j is in, with that source's
    /// pieces `0..=i`, while later pieces may still be in flight, so that a receiver can
    /// composite its sources in a fixed visibility order.
    ///
    /// The default goes through [`Comm::exchange`] and copies; `MpiComm` receives in place.
    fn exchange_pieces_many(
        &self,
        tag: u32,
        sends: &[PiecesOut<'_>],
        recvs: &mut [PiecesIn<'_>],
        arrived: &mut PiecesArrived<'_>,
    ) -> Result<(), CommError> {
        let out: Vec<(usize, &[u8])> = sends
            .iter()
            .flat_map(|(d, ps)| ps.iter().map(move |p| (*d, *p)))
            .collect();
        let from: Vec<usize> = recvs
            .iter()
            .flat_map(|(s, ps)| std::iter::repeat_n(*s, ps.len()))
            .collect();
        let mut got = self.exchange(&out, &from, tag)?.into_iter();
        for (j, (src, ps)) in recvs.iter_mut().enumerate() {
            for i in 0..ps.len() {
                let piece = got.next().expect("one message per expected piece");
                check_piece_len(*src, i, piece.len(), ps[i].len())?;
                ps[i].copy_from_slice(&piece);
                let done: Vec<&[u8]> = ps[..=i].iter().map(|r| &**r).collect();
                arrived(j, i, &done)?;
            }
        }
        Ok(())
    }

    /// Dissemination barrier (Hensgen, Finkel, Manber 1988): ceil(log2 p) rounds.
    fn barrier(&self) -> Result<(), CommError> {
        let (r, p) = (self.rank(), self.size());
        let mut k = 1;
        while k < p {
            let to = (r + k) % p;
            let from = (r + p - k) % p;
            let empty: &[u8] = &[];
            self.exchange(&[(to, empty)], &[from], TAG_BARRIER)?;
            k <<= 1;
        }
        Ok(())
    }

    /// Personalised all-to-all: `bufs[j]` goes to rank j; returns what each rank sent here.
    fn all_to_all(&self, bufs: &[Vec<u8>]) -> Result<Vec<Vec<u8>>, CommError> {
        let (r, p) = (self.rank(), self.size());
        assert_eq!(bufs.len(), p, "all_to_all needs one buffer per rank");
        let sends: Vec<(usize, &[u8])> = (0..p)
            .filter(|&j| j != r)
            .map(|j| (j, bufs[j].as_slice()))
            .collect();
        let sources: Vec<usize> = (0..p).filter(|&j| j != r).collect();
        let got = self.exchange(&sends, &sources, TAG_ALL_TO_ALL)?;
        let mut out = Vec::with_capacity(p);
        let mut it = got.into_iter();
        for j in 0..p {
            if j == r {
                out.push(bufs[r].clone());
            } else {
                out.push(it.next().unwrap());
            }
        }
        Ok(out)
    }

    /// Gathers one buffer from every rank at `root` (others get an empty vector).
    fn gather(&self, root: usize, data: &[u8]) -> Result<Vec<Vec<u8>>, CommError> {
        let (r, p) = (self.rank(), self.size());
        if r == root {
            let mut out = Vec::with_capacity(p);
            for j in 0..p {
                if j == root {
                    out.push(data.to_vec());
                } else {
                    out.push(self.recv(j, TAG_GATHER)?);
                }
            }
            Ok(out)
        } else {
            self.send(root, TAG_GATHER, data)?;
            Ok(Vec::new())
        }
    }

    /// Broadcasts `data` from `root` (linear; used only for small control messages).
    fn broadcast(&self, root: usize, data: &[u8]) -> Result<Vec<u8>, CommError> {
        let (r, p) = (self.rank(), self.size());
        if r == root {
            for j in (0..p).filter(|&j| j != root) {
                self.send(j, TAG_BCAST, data)?;
            }
            Ok(data.to_vec())
        } else {
            self.recv(root, TAG_BCAST)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::MessageLog;
    use std::sync::{Arc, Mutex};

    #[test]
    fn the_stage_observer_hears_every_stage_in_order() {
        let log = MessageLog::default();
        log.begin_stage("before anyone listens");
        let heard = Arc::new(Mutex::new(Vec::new()));
        let h = heard.clone();
        log.on_stage(move |s| h.lock().unwrap().push(s.to_string()));
        for s in ["render", "composite", "gather"] {
            log.begin_stage(s);
        }
        log.end_stage();
        assert_eq!(*heard.lock().unwrap(), ["render", "composite", "gather"]);
        let times: Vec<String> = log.stage_times().into_iter().map(|t| t.0).collect();
        assert_eq!(
            times,
            ["before anyone listens", "render", "composite", "gather"]
        );
    }
}
