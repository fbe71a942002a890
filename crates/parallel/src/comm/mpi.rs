//! `MpiComm`: the same [`Comm`] over MPI (rsmpi on OpenMPI), for `mpirun -np N`.
//!
//! Receives probe (`MPI_Improbe`) until the message arrives or the timeout passes, so a
//! silent rank is named instead of hanging the job. MPI cannot cancel a half-finished
//! exchange safely, so a communication error here is fatal: [`MpiComm::fail`] prints the
//! error naming the culprit and calls `MPI_Abort`, which ends every rank of the job. A
//! rank that dies outright (signal, exit without finalize) is noticed by `mpirun`
//! itself, which then kills the remaining ranks and names the dead one.

use super::{check_piece_len, Comm, CommError, MessageLog, PiecesArrived, PiecesIn, PiecesOut};
use mpi::datatype::Equivalence;
use mpi::point_to_point::{Destination, MatchedReceiveVec, Source};
use mpi::topology::{Communicator, SimpleCommunicator};
use std::collections::VecDeque;
use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// How many pieces of an [`Comm::exchange_pieces_many`] have receives posted at once
/// (`IRRADIA_MPI_PIECE_WINDOW`, default 2; 0 = all).
fn piece_window() -> usize {
    static W: OnceLock<usize> = OnceLock::new();
    *W.get_or_init(|| {
        match std::env::var("IRRADIA_MPI_PIECE_WINDOW")
            .ok()
            .and_then(|v| v.parse().ok())
        {
            Some(0) => usize::MAX,
            Some(w) => w,
            None => 2,
        }
    })
}

/// One rank of an MPI job: `MPI_COMM_WORLD` of a program that initialised MPI here
/// ([`MpiComm::init`], exactly one per process), or a communicator of an MPI that
/// someone else initialised: a duplicate made here ([`MpiComm::from_raw_dup`]) or one
/// the caller keeps ([`MpiComm::from_raw_borrowed`], the Python binding's cached
/// duplicate of an mpi4py communicator).
pub struct MpiComm {
    /// Finalises MPI when dropped (`None` when the caller owns MPI's lifetime).
    _universe: Option<mpi::environment::Universe>,
    /// Freed in `drop` when `owned` (before `_universe` finalises MPI).
    world: std::mem::ManuallyDrop<SimpleCommunicator>,
    /// Whether dropping this comm frees `world` (false for a borrowed handle).
    owned: bool,
    timeout: Duration,
    log: MessageLog,
    /// Sends of [`Comm::post`] still in flight, with their buffers (leaked when posted,
    /// freed once the send completes).
    posted: std::cell::RefCell<Vec<Posted>>,
}

/// One non-blocking send of [`Comm::post`]: its request, the buffer it reads (owned
/// here: a leaked `Box<[u8]>`) and its destination.
struct Posted {
    request: mpi::request::Request<'static, [u8]>,
    buffer: *mut [u8],
    dest: usize,
}

impl Drop for MpiComm {
    /// Waits for the posted sends (a request must complete before it is dropped).
    fn drop(&mut self) {
        let deadline = Instant::now() + self.timeout;
        while !self.posted.borrow().is_empty() {
            self.reap();
            if Instant::now() >= deadline {
                let dest = self.posted.borrow()[0].dest;
                self.fail(&CommError::Timeout {
                    rank: dest,
                    waiting_rank: self.rank(),
                    tag: 0,
                    seconds: self.timeout.as_secs_f64(),
                });
            }
            std::thread::yield_now();
        }
        if self.owned {
            // SAFETY: dropped once, here, and never used again.
            unsafe { std::mem::ManuallyDrop::drop(&mut self.world) };
        }
    }
}

impl MpiComm {
    /// Initialises MPI. Returns `None` when MPI was already initialised.
    pub fn init(timeout: Duration) -> Option<Self> {
        let universe = mpi::initialize()?;
        let world = universe.world();
        Some(Self {
            _universe: Some(universe),
            world: std::mem::ManuallyDrop::new(world),
            owned: true,
            timeout,
            log: MessageLog::default(),
            posted: Default::default(),
        })
    }

    /// A comm over a duplicate (`MPI_Comm_dup`) of `comm`, a live intra-communicator of
    /// an MPI that someone else initialised and will finalise (mpi4py): Irradia's
    /// messages then never match the caller's, and the duplicate is freed when this is
    /// dropped (which must happen before MPI is finalised).
    ///
    /// # Safety
    /// `comm` must be a valid intra-communicator handle (not `MPI_COMM_NULL`), MPI must
    /// be initialised, and every rank of `comm` must call this together (the duplicate
    /// is collective).
    pub unsafe fn from_raw_dup(comm: mpi::ffi::MPI_Comm, timeout: Duration) -> Self {
        use mpi::raw::FromRaw;
        let mut dup = std::mem::MaybeUninit::<mpi::ffi::MPI_Comm>::uninit();
        mpi::ffi::MPI_Comm_dup(comm, dup.as_mut_ptr());
        let world = SimpleCommunicator::from_raw(dup.assume_init());
        Self {
            _universe: None,
            world: std::mem::ManuallyDrop::new(world),
            owned: true,
            timeout,
            log: MessageLog::default(),
            posted: Default::default(),
        }
    }

    /// A comm over `comm` itself, which the caller keeps and frees: dropping this comm
    /// leaves the handle alone. Unlike [`MpiComm::from_raw_dup`] it costs nothing and
    /// is not collective (`MPI_Comm_dup` is: OpenMPI agrees on a context id with
    /// nonblocking allreduces), for a caller that duplicates a communicator once and
    /// composites over the duplicate frame after frame.
    ///
    /// # Safety
    /// `comm` must be a valid intra-communicator handle (not `MPI_COMM_NULL`) of an
    /// initialised MPI, used by nothing else while this comm lives, and freed (if ever)
    /// only after this comm is dropped.
    pub unsafe fn from_raw_borrowed(comm: mpi::ffi::MPI_Comm, timeout: Duration) -> Self {
        use mpi::raw::FromRaw;
        Self {
            _universe: None,
            world: std::mem::ManuallyDrop::new(SimpleCommunicator::from_raw(comm)),
            owned: false,
            timeout,
            log: MessageLog::default(),
            posted: Default::default(),
        }
    }

    /// Frees the buffers of the posted sends that have completed.
    fn reap(&self) {
        let mut posted = self.posted.borrow_mut();
        let mut still = Vec::with_capacity(posted.len());
        for p in posted.drain(..) {
            match p.request.test() {
                Ok(_) => {
                    // SAFETY: `buffer` came from `Box::leak` in `post` and its send has
                    // completed, so nothing reads it any more; it is freed once.
                    drop(unsafe { Box::from_raw(p.buffer) });
                }
                Err(request) => still.push(Posted { request, ..p }),
            }
        }
        *posted = still;
    }

    /// Prints `error` (naming the rank at fault) and ends every rank of the job.
    pub fn fail(&self, error: &CommError) -> ! {
        eprintln!(
            "irradia: rank {}: {error}; aborting the MPI job",
            self.world.rank()
        );
        self.world.abort(3)
    }

    /// Calls `poll` until it returns something: a few quick polls, then the processor
    /// is yielded between polls (so that with more ranks than cores the rank being
    /// waited for can run). Past `deadline` it gives up with a timeout naming
    /// `culprit`, the rank waited for.
    fn poll_until<T>(
        &self,
        culprit: usize,
        tag: u32,
        deadline: Instant,
        mut poll: impl FnMut() -> Option<T>,
    ) -> Result<T, CommError> {
        let mut spins = 0u32;
        loop {
            if let Some(x) = poll() {
                return Ok(x);
            }
            spins += 1;
            if spins > 64 {
                if Instant::now() >= deadline {
                    return Err(CommError::Timeout {
                        rank: culprit,
                        waiting_rank: self.rank(),
                        tag,
                        seconds: self.timeout.as_secs_f64(),
                    });
                }
                std::thread::yield_now();
            }
        }
    }

    /// Waits for a posted request (`test` is its `MPI_Test`). Posted requests cannot be
    /// abandoned, so a timeout ends the whole job here.
    fn wait_request<R, T>(
        &self,
        culprit: usize,
        tag: u32,
        deadline: Instant,
        request: R,
        test: impl Fn(R) -> Result<T, R>,
    ) -> T {
        let mut pending = Some(request);
        let waited = self.poll_until(culprit, tag, deadline, || {
            match test(pending.take().expect("request still pending")) {
                Ok(x) => Some(x),
                Err(again) => {
                    pending = Some(again);
                    None
                }
            }
        });
        waited.unwrap_or_else(|e| self.fail(&e))
    }

    /// Posts every send without blocking, calls `receive(i, source, deadline)` for each
    /// source in order, then waits for the sends. A receive that fails ends the whole
    /// job here: outstanding sends cannot be abandoned.
    fn exchange_with(
        &self,
        sends: &[(usize, &[u8])],
        sources: &[usize],
        tag: u32,
        mut receive: impl FnMut(usize, usize, Instant) -> Result<(), CommError>,
    ) -> Result<(), CommError> {
        for &(d, _) in sends {
            self.check(d)?;
        }
        for &s in sources {
            self.check(s)?;
        }
        mpi::request::scope(|scope| {
            let requests: Vec<_> = sends
                .iter()
                .map(|&(d, b)| {
                    self.log.record(self.rank(), d, b.len(), true);
                    self.world
                        .process_at_rank(d as i32)
                        .immediate_send_with_tag(scope, b, tag as i32)
                })
                .collect();
            for (i, &src) in sources.iter().enumerate() {
                if let Err(e) = receive(i, src, Instant::now() + self.timeout) {
                    self.fail(&e);
                }
            }
            let deadline = Instant::now() + self.timeout;
            for (r, &(d, _)) in requests.into_iter().zip(sends) {
                self.wait_request(d, tag, deadline, r, |r| r.test());
            }
            Ok(())
        })
    }

    fn check(&self, rank: usize) -> Result<(), CommError> {
        if rank >= self.size() {
            return Err(CommError::BadRank {
                rank,
                size: self.size(),
            });
        }
        Ok(())
    }
}

impl Comm for MpiComm {
    fn rank(&self) -> usize {
        self.world.rank() as usize
    }
    fn size(&self) -> usize {
        self.world.size() as usize
    }
    fn timeout(&self) -> Duration {
        self.timeout
    }
    fn log(&self) -> &MessageLog {
        &self.log
    }

    fn send(&self, dest: usize, tag: u32, data: &[u8]) -> Result<(), CommError> {
        self.check(dest)?;
        self.log.record(self.rank(), dest, data.len(), true);
        self.world
            .process_at_rank(dest as i32)
            .send_with_tag(data, tag as i32);
        Ok(())
    }

    fn post(&self, dest: usize, tag: u32, data: Vec<u8>) -> Result<(), CommError> {
        self.check(dest)?;
        self.reap();
        self.log.record(self.rank(), dest, data.len(), true);
        let buffer: &'static mut [u8] = Box::leak(data.into_boxed_slice());
        let ptr: *mut [u8] = buffer;
        // SAFETY: the buffer stays alive (leaked) until `reap` sees the send complete.
        let request = self
            .world
            .process_at_rank(dest as i32)
            .immediate_send_with_tag(mpi::request::StaticScope, unsafe { &*ptr }, tag as i32);
        self.posted.borrow_mut().push(Posted {
            request,
            buffer: ptr,
            dest,
        });
        Ok(())
    }

    fn progress(&self) {
        self.reap();
    }

    fn try_recv_any(
        &self,
        sources: &[usize],
        tag: u32,
    ) -> Result<Option<(usize, Vec<u8>)>, CommError> {
        for &src in sources {
            self.check(src)?;
            let p = self.world.process_at_rank(src as i32);
            if let Some(m) = p.immediate_matched_probe_with_tag(tag as i32) {
                let (v, _) = m.matched_receive_vec::<u8>();
                self.log.record(src, self.rank(), v.len(), false);
                return Ok(Some((src, v)));
            }
        }
        Ok(None)
    }

    fn recv(&self, src: usize, tag: u32) -> Result<Vec<u8>, CommError> {
        self.check(src)?;
        let p = self.world.process_at_rank(src as i32);
        let deadline = Instant::now() + self.timeout;
        let m = self.poll_until(src, tag, deadline, || {
            p.immediate_matched_probe_with_tag(tag as i32)
        })?;
        let (v, _) = m.matched_receive_vec::<u8>();
        self.log.record(src, self.rank(), v.len(), false);
        Ok(v)
    }

    /// As [`Comm::exchange`], each message received straight into its reused buffer
    /// (the probe gives its size).
    fn exchange_into(
        &self,
        sends: &[(usize, &[u8])],
        sources: &[usize],
        tag: u32,
        into: &mut Vec<Vec<u8>>,
    ) -> Result<(), CommError> {
        into.resize_with(sources.len(), Vec::new);
        self.exchange_with(sends, sources, tag, |i, src, deadline| {
            let p = self.world.process_at_rank(src as i32);
            let (m, status) = self.poll_until(src, tag, deadline, || {
                p.immediate_matched_probe_with_tag(tag as i32)
            })?;
            let n = status.count(u8::equivalent_datatype()) as usize;
            let buf = &mut into[i];
            buf.resize(n, 0);
            m.matched_receive_into(&mut buf[..]);
            self.log.record(src, self.rank(), n, false);
            Ok(())
        })
    }

    /// Non-blocking sends, then probed receives: no deadlock whatever the pattern.
    fn exchange(
        &self,
        sends: &[(usize, &[u8])],
        sources: &[usize],
        tag: u32,
    ) -> Result<Vec<Vec<u8>>, CommError> {
        let mut out = Vec::with_capacity(sources.len());
        self.exchange_with(sends, sources, tag, |_, src, _| {
            out.push(self.recv(src, tag)?);
            Ok(())
        })?;
        Ok(out)
    }

    /// Non-blocking receives posted straight into the caller's buffers, `window` pieces
    /// ahead in the order of `recvs` (so that the single-copy transfer of a piece, done
    /// by the receiver's CPU when it polls, lands just before that piece is used, while
    /// it is still in cache), and every send posted at once straight from the caller's
    /// memory (with shared memory, OpenMPI's single-copy CMA path moves each piece
    /// once); the receives are tested in order and `arrived` runs on each piece while
    /// the later ones travel.
    fn exchange_pieces_many(
        &self,
        tag: u32,
        sends: &[PiecesOut<'_>],
        recvs: &mut [PiecesIn<'_>],
        arrived: &mut PiecesArrived<'_>,
    ) -> Result<(), CommError> {
        for r in sends.iter().map(|s| s.0).chain(recvs.iter().map(|r| r.0)) {
            self.check(r)?;
        }
        let me = self.rank();
        let wants: Vec<usize> = recvs
            .iter()
            .flat_map(|(_, ps)| ps.iter().map(|p| p.len()))
            .collect();
        let deadline = Instant::now() + self.timeout;
        let window = piece_window();
        let world = &self.world;
        mpi::request::scope(|scope| {
            let mut buffers = recvs.iter_mut().enumerate().flat_map(|(j, (src, ps))| {
                let src = *src;
                ps.iter_mut()
                    .enumerate()
                    .map(move |(i, b)| (j, i, src, &mut **b))
            });
            macro_rules! post {
                ($x:expr) => {{
                    let (j, i, src, b) = $x;
                    let r = world
                        .process_at_rank(src as i32)
                        .immediate_receive_into_with_tag(scope, b, tag as i32);
                    (j, i, src, r)
                }};
            }
            let mut receives = VecDeque::with_capacity(wants.len());
            for b in buffers.by_ref().take(window) {
                receives.push_back(post!(b));
            }
            let sent: Vec<_> = sends
                .iter()
                .flat_map(|(d, ps)| ps.iter().map(move |b| (*d, *b)))
                .map(|(d, b)| {
                    self.log.record(me, d, b.len(), true);
                    (
                        d,
                        world
                            .process_at_rank(d as i32)
                            .immediate_send_with_tag(scope, b, tag as i32),
                    )
                })
                .collect();
            let mut done: Vec<&[u8]> = Vec::new();
            let mut source = usize::MAX;
            for &want in &wants {
                let (j, i, src, r) = receives.pop_front().expect("a receive is posted");
                if j != source {
                    done.clear();
                    source = j;
                }
                let (status, data) =
                    self.wait_request(src, tag, deadline, r, |r| r.test_with_data());
                let got = status.count(u8::equivalent_datatype()) as usize;
                if let Err(e) = check_piece_len(src, i, got, want) {
                    self.fail(&e);
                }
                self.log.record(src, me, got, false);
                done.push(data);
                if let Some(b) = buffers.next() {
                    receives.push_back(post!(b));
                }
                // Outstanding requests cannot be abandoned: an error ends the job here.
                if let Err(e) = arrived(j, i, &done) {
                    self.fail(&e);
                }
            }
            for (d, r) in sent {
                self.wait_request(d, tag, deadline, r, |r| r.test());
            }
            Ok(())
        })
    }
}
