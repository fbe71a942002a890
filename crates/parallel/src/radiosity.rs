//! Hierarchical radiosity on the ranks of a [`Comm`]: `irradia radiosity --solver
//! hierarchical --comm local|mpi`, with the same result as one process, bit for bit.
//!
//! The solver is Hanrahan, Salzman and Aupperle's (1991, "A rapid hierarchical radiosity
//! algorithm"; `irradia_radiosity::solver::hierarchical`): every round refines the links
//! of every pair of patches by the BF criterion from the top, then Jacobi iterations of
//! gather and push-pull run until the largest change is small. Its parallel form here
//! follows the two observations of the parallel hierarchical radiosity literature
//! (Funkhouser 1996, "Coarse-grained parallelism for hierarchical radiosity using group
//! iterative methods"; Podehl, Rauber and Rünger 1998, "A shared-memory implementation
//! of the hierarchical radiosity method"): the refinement of one patch pair depends
//! only on the radiosities of the round, and the gather of one receiving patch only on
//! its own links and the radiosities of the last iteration.
//!
//! * **Tree.** Every rank builds the same node tree from the same mesh (the hierarchy is
//!   a pure function of the patches and options), so node numbers mean the same on every
//!   rank and no subdivision ever has to travel.
//! * **Links** (the oracle, the form factors and the shadow rays: about 95% of the time).
//!   Rank 0 hands out chunks of patch pairs to whichever rank asks (master-worker
//!   self-scheduling, as `progressive.rs` does with tiles), two chunks in flight per
//!   worker, largest first by the link count each pair had in the last round, and
//!   computes chunks of its own meanwhile. The workers send back each pair's links.
//! * **Ownership.** Rank 0 puts each patch's links in the one-process order (its pairs
//!   by source patch, stably sorted by receiving node) and deals the patches to the ranks
//!   by links and nodes, largest first to the least loaded rank; each rank gets its
//!   patches' links and the owner of every patch.
//! * **Gather.** Each iteration every rank gathers and pushes-pulls its own patches and
//!   sends the new radiosity of their nodes, with its largest change, to every rank (an
//!   all-gather); every rank then holds the same radiosities and stops on the same
//!   iteration, because the largest change is a maximum (exact in any order).
//!
//! A node's gather sums the same links in the same order with the same arithmetic as one
//! process ([`Hierarchy::iterate_patch`] is the one-process code), so the radiosities
//! are equal bit for bit for any number of ranks and any assignment. Every receive has
//! the communicator's deadline: a rank that dies or goes silent ends the job with an
//! error naming it.

use crate::comm::{Comm, CommError};
use crate::slot::Slot;
use crate::wire::{put_u32, Reader};
use irradia_radiosity::mesh::Mesh;
use irradia_radiosity::solver::hierarchical::{
    HierarchicalOptions, HierarchicalResult, Hierarchy, Link, SolveRecord,
};
use irradia_radiosity::RadiosityError;
use rayon::prelude::*;
use std::collections::VecDeque;
use std::time::{Duration, Instant};

/// Tag of the work messages (rank 0 to a worker: pairs to link, or stop).
const TAG_WORK: u32 = 0x7e10;
/// Tag of the finished pairs (a worker to rank 0).
const TAG_DONE: u32 = 0x7e11;
/// Tag of the owner table and a rank's links (rank 0 to a worker).
const TAG_LINKS: u32 = 0x7e12;
/// Tag of the radiosities of an iteration (every rank to every rank).
const TAG_B: u32 = 0x7e13;
/// Chunks a worker holds at once: one it computes, one waiting.
const IN_FLIGHT: usize = 2;
/// Chunks per rank in a round (at least): small enough for the last ones to even out.
const CHUNKS_PER_RANK: u64 = 16;
/// How often a rank's main thread looks for messages while its pool computes.
const POLL: Duration = Duration::from_millis(1);

/// Solves `mesh`'s patches hierarchically on every rank of `comm` (each on its current
/// rayon pool). Rank 0 returns the result, equal bit for bit to
/// `irradia_radiosity::solver::hierarchical::solve`; the other ranks return `None`.
/// Bad options fail the same way on every rank before any message is sent.
pub fn solve_distributed<C: Comm>(
    comm: &C,
    mesh: &Mesh,
    opts: HierarchicalOptions,
) -> Result<Option<HierarchicalResult>, RadiosityError> {
    let h = Hierarchy::new(mesh, opts)?;
    let failure = |e: CommError| RadiosityError::Failure(e.to_string());
    let opts = *h.options();
    let pairs = h.pairs();
    let mut b = h.initial_radiosity();
    // Rank 0: the links each pair had in the last round (the cost of linking it), and
    // those links sorted by (receiver, source), whose form factors the next round reuses
    // wherever the pair is linked (they travel with the pair).
    let mut cost = vec![1u32; pairs.len()];
    let mut known: Vec<Vec<Link>> =
        vec![Vec::new(); if comm.rank() == 0 { pairs.len() } else { 0 }];
    let mut rec = SolveRecord {
        residual: f64::INFINITY,
        ..Default::default()
    };
    for round in 0..opts.rounds.max(1) {
        let t_link = Instant::now();
        let share = if comm.rank() == 0 {
            let per_pair = deal_pairs(comm, &h, &pairs, &cost, &known, &b).map_err(failure)?;
            for (c, l) in cost.iter_mut().zip(&per_pair) {
                *c = (l.len() as u32).saturating_add(1);
            }
            if round + 1 < opts.rounds {
                known.clone_from(&per_pair);
                known
                    .par_iter_mut()
                    .for_each(|k| k.sort_unstable_by_key(|l| (l.recv, l.src)));
            }
            let np = h.patches();
            let mut it = per_pair.into_iter();
            let links: Vec<Vec<Link>> = (0..np)
                .map(|_| h.patch_links(it.by_ref().take(np - 1)))
                .collect();
            rec.links = links.iter().map(Vec::len).sum();
            share_links(comm, &h, links).map_err(failure)?
        } else {
            serve_pairs(comm, &h, &pairs, &b).map_err(failure)?;
            let msg = comm.recv(0, TAG_LINKS).map_err(failure)?;
            decode_share(&msg, &h, comm.size())
                .map_err(|message| failure(CommError::Malformed { rank: 0, message }))?
        };
        rec.link_time += t_link.elapsed();
        let t_solve = Instant::now();
        for _ in 0..opts.max_iterations {
            let change = iterate(comm, &h, &share, &mut b).map_err(failure)?;
            rec.history.push(change);
            rec.residual = change;
            if change < opts.tolerance {
                break;
            }
        }
        rec.solve_time += t_solve.elapsed();
    }
    Ok((comm.rank() == 0).then(|| h.finish(mesh, &b, rec)))
}

/// A rank's part of the gather: the owner of every patch, and its own patches (in
/// increasing order) with their links.
struct Share {
    owner: Vec<u32>,
    mine: Vec<(usize, Vec<Link>)>,
}

/// One Jacobi iteration over the ranks: this rank's patches, then the all-gather of
/// every patch's new radiosity into `b`. Returns the largest change relative to the
/// largest emission, the same on every rank.
fn iterate<C: Comm>(
    c: &C,
    h: &Hierarchy<'_>,
    share: &Share,
    b: &mut Vec<[f64; 3]>,
) -> Result<f64, CommError> {
    let old: &[[f64; 3]] = b;
    let values: Vec<Vec<[f64; 3]>> = share
        .mine
        .par_iter()
        .map(|(p, links)| h.iterate_patch(*p, links, old))
        .collect();
    let mut nb = vec![[0.0f64; 3]; h.nodes()];
    let mut change: f64 = 0.0;
    let mut msg = Vec::with_capacity(8 + 24 * values.iter().map(Vec::len).sum::<usize>());
    for ((p, _), v) in share.mine.iter().zip(&values) {
        change = change.max(h.store_patch(*p, v, old, &mut nb));
    }
    // Wire: f64 largest change | per own patch, increasing: its nodes' 3 f64.
    msg.extend_from_slice(&change.to_le_bytes());
    for v in &values {
        for x in v {
            for c in x {
                msg.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    let (r, size) = (c.rank(), c.size());
    let others: Vec<usize> = (0..size).filter(|&j| j != r).collect();
    let sends: Vec<(usize, &[u8])> = others.iter().map(|&j| (j, msg.as_slice())).collect();
    let got = c.exchange(&sends, &others, TAG_B)?;
    for (&j, m) in others.iter().zip(&got) {
        let theirs: Vec<usize> = (0..h.patches())
            .filter(|&p| share.owner[p] as usize == j)
            .collect();
        let want = 8 + 24 * theirs.iter().map(|&p| h.patch_size(p)).sum::<usize>();
        if m.len() != want {
            return Err(CommError::Malformed {
                rank: j,
                message: format!("radiosities of {} bytes, expected {want}", m.len()),
            });
        }
        let bad = |message| CommError::Malformed { rank: j, message };
        let mut rd = Reader(m);
        change = change.max(rd.f64().map_err(bad)?);
        for p in theirs {
            for i in h.patch_nodes(p) {
                let mut v = [0.0; 3];
                for x in &mut v {
                    *x = rd.f64().map_err(bad)?;
                }
                nb[i] = v;
            }
        }
    }
    *b = nb;
    Ok(change / h.emission_scale())
}

/// Rank 0: deals the owners out (largest patch first to the least loaded rank, by links
/// plus nodes), sends each worker the owner table and its patches' links, and returns
/// its own share.
fn share_links<C: Comm>(
    c: &C,
    h: &Hierarchy<'_>,
    links: Vec<Vec<Link>>,
) -> Result<Share, CommError> {
    let size = c.size();
    let weight = |p: usize| links[p].len() + h.patch_size(p);
    let mut order: Vec<usize> = (0..h.patches()).collect();
    order.sort_by_key(|&p| std::cmp::Reverse(weight(p)));
    let mut load = vec![0usize; size];
    let mut owner = vec![0u32; h.patches()];
    for p in order {
        let r = (0..size).min_by_key(|&r| (load[r], r)).unwrap_or(0);
        load[r] += weight(p);
        owner[p] = r as u32;
    }
    let mut mine = Vec::new();
    let mut parts: Vec<Vec<(usize, Vec<Link>)>> = vec![Vec::new(); size];
    for (p, l) in links.into_iter().enumerate() {
        parts[owner[p] as usize].push((p, l));
    }
    for (w, part) in parts.into_iter().enumerate() {
        if w == 0 {
            mine = part;
            continue;
        }
        // Wire: u32 patches | per patch: u32 owner | u32 own patches | per own patch:
        // u32 patch | u32 links | per link: u32 recv, u32 src, f64 f.
        let mut m = Vec::new();
        put_u32(&mut m, owner.len() as u32);
        for &o in &owner {
            put_u32(&mut m, o);
        }
        put_u32(&mut m, part.len() as u32);
        for (p, l) in &part {
            put_u32(&mut m, *p as u32);
            put_links(&mut m, l);
        }
        c.send(w, TAG_LINKS, &m)?;
    }
    Ok(Share { owner, mine })
}

/// A worker's share from rank 0's message, checked against the hierarchy.
fn decode_share(msg: &[u8], h: &Hierarchy<'_>, size: usize) -> Result<Share, String> {
    let mut r = Reader(msg);
    let np = r.u32()? as usize;
    if np != h.patches() {
        return Err(format!("{np} patches, expected {}", h.patches()));
    }
    let owner = (0..np)
        .map(|_| {
            let o = r.u32()?;
            if o as usize >= size {
                return Err(format!("owner rank {o} of {size}"));
            }
            Ok(o)
        })
        .collect::<Result<Vec<u32>, String>>()?;
    let count = r.u32()? as usize;
    let mut mine = Vec::with_capacity(count.min(np));
    for _ in 0..count {
        let p = r.u32()? as usize;
        if p >= np || mine.last().is_some_and(|(q, _)| *q >= p) {
            return Err(format!("patch {p} out of order"));
        }
        mine.push((p, decode_links(&mut r, h, p, None)?));
    }
    Ok(Share { owner, mine })
}

/// Rank 0's link phase: every pair's links, indexed as `pairs`.
fn deal_pairs<C: Comm>(
    c: &C,
    h: &Hierarchy<'_>,
    pairs: &[(u32, u32)],
    cost: &[u32],
    known: &[Vec<Link>],
    b: &[[f64; 3]],
) -> Result<Vec<Vec<Link>>, CommError> {
    let link = |k: usize| h.link_pair_reusing(pairs[k].0, pairs[k].1, b, &known[k]);
    if c.size() == 1 {
        return Ok((0..pairs.len()).into_par_iter().map(link).collect());
    }
    // Largest first (by last round's links), cut into chunks of about equal cost.
    let mut order: Vec<usize> = (0..pairs.len()).collect();
    order.sort_by_key(|&k| std::cmp::Reverse(cost[k]));
    let total: u64 = cost.iter().map(|&x| x as u64).sum();
    let target = (total / (c.size() as u64 * CHUNKS_PER_RANK)).max(1);
    let mut chunks: Vec<Vec<usize>> = Vec::new();
    let mut acc = u64::MAX;
    for k in order {
        if acc >= target {
            chunks.push(Vec::new());
            acc = 0;
        }
        chunks.last_mut().expect("a chunk").push(k);
        acc += cost[k] as u64;
    }
    let mut results: Vec<Vec<Link>> = vec![Vec::new(); pairs.len()];
    // Workers take chunks from the front (the costly ones), rank 0 from the back: its
    // own chunks stay short, so that it answers the workers often even when it has a
    // single thread that computes between answers (thread ranks).
    let mut chunks: VecDeque<Vec<usize>> = chunks.into();
    let workers: Vec<usize> = (1..c.size()).collect();
    let mut queue: Vec<VecDeque<Vec<usize>>> = vec![VecDeque::new(); c.size()];
    let post = |w: usize, chunk: Vec<usize>, queue: &mut [VecDeque<Vec<usize>>]| {
        // Wire: u8 1 | u32 pairs | per pair: u32 index, its last round's links
        // (`put_links`).  Stop: u8 0.
        let mut m = vec![1u8];
        put_u32(&mut m, chunk.len() as u32);
        for &k in &chunk {
            put_u32(&mut m, k as u32);
            put_links(&mut m, &known[k]);
        }
        queue[w].push_back(chunk);
        c.post(w, TAG_WORK, m)
    };
    for _ in 0..IN_FLIGHT {
        for &w in &workers {
            if let Some(chunk) = chunks.pop_front() {
                post(w, chunk, &mut queue)?;
            }
        }
    }
    // This thread talks and stores; rank 0's own chunks compute on its pool meanwhile.
    type Done = Vec<(usize, Vec<Link>)>;
    let here: Slot<Done> = Slot::new();
    let mut quiet_since = Instant::now();
    let outcome = rayon::in_place_scope(|scope| -> Result<(), CommError> {
        let mut working_here = false;
        loop {
            let mut idle = true;
            let busy: Vec<usize> = workers
                .iter()
                .copied()
                .filter(|&w| !queue[w].is_empty())
                .collect();
            while let Some((w, msg)) = c.try_recv_any(&busy, TAG_DONE)? {
                let chunk = queue[w].pop_front().ok_or_else(|| CommError::Malformed {
                    rank: w,
                    message: "links of pairs it was not given".into(),
                })?;
                let done = decode_done(&msg, h, pairs, &chunk)
                    .map_err(|message| CommError::Malformed { rank: w, message })?;
                for (k, l) in done {
                    results[k] = l;
                }
                if let Some(next) = chunks.pop_front() {
                    post(w, next, &mut queue)?;
                }
                idle = false;
            }
            if working_here {
                if let Some(done) = here.take() {
                    for (k, l) in done {
                        results[k] = l;
                    }
                    working_here = false;
                    idle = false;
                }
            }
            if !working_here {
                if let Some(chunk) = chunks.pop_back() {
                    let here = &here;
                    scope.spawn(move |_| {
                        let done: Done = chunk.into_par_iter().map(|k| (k, link(k))).collect();
                        here.put(done);
                    });
                    working_here = true;
                    idle = false;
                }
            }
            let busy: Vec<usize> = workers
                .iter()
                .copied()
                .filter(|&w| !queue[w].is_empty())
                .collect();
            if !working_here && busy.is_empty() {
                return Ok(());
            }
            if !idle {
                quiet_since = Instant::now();
                continue;
            }
            if !working_here && quiet_since.elapsed() >= c.timeout() {
                return Err(CommError::Timeout {
                    rank: busy[0],
                    waiting_rank: 0,
                    tag: TAG_DONE,
                    seconds: c.timeout().as_secs_f64(),
                });
            }
            c.progress();
            // On a pool's own thread (ranks as threads) compute here; otherwise (the
            // main thread under MPI) wait for this rank's chunk, or a little.
            if rayon::yield_now() != Some(rayon::Yield::Executed) {
                if working_here {
                    here.wait(POLL);
                } else {
                    std::thread::sleep(POLL);
                }
            }
        }
    });
    outcome?;
    for &w in &workers {
        c.post(w, TAG_WORK, vec![0u8])?;
    }
    Ok(results)
}

/// A worker's link phase: links the pairs rank 0 sends until it says stop.
fn serve_pairs<C: Comm>(
    c: &C,
    h: &Hierarchy<'_>,
    pairs: &[(u32, u32)],
    b: &[[f64; 3]],
) -> Result<(), CommError> {
    loop {
        let msg = c.recv(0, TAG_WORK)?;
        let chunk = decode_work(&msg, h, pairs)
            .map_err(|message| CommError::Malformed { rank: 0, message })?;
        let Some(chunk) = chunk else {
            return Ok(());
        };
        // The pairs compute on the pool while this thread keeps the last chunk's
        // links moving to rank 0 (MPI calls stay on this thread).
        let finished: Slot<Vec<(usize, Vec<Link>)>> = Slot::new();
        let done = rayon::in_place_scope(|s| {
            s.spawn(|_| {
                finished.put(
                    chunk
                        .par_iter()
                        .map(|(k, known)| {
                            (*k, h.link_pair_reusing(pairs[*k].0, pairs[*k].1, b, known))
                        })
                        .collect(),
                );
            });
            loop {
                if let Some(done) = finished.take() {
                    break done;
                }
                c.progress();
                if rayon::yield_now() != Some(rayon::Yield::Executed) {
                    finished.wait(POLL);
                }
            }
        });
        // Wire: u32 pairs | per pair: u32 index | u32 links | per link: u32 recv,
        // u32 src, f64 f.
        let mut m = Vec::new();
        put_u32(&mut m, done.len() as u32);
        for (k, l) in &done {
            put_u32(&mut m, *k as u32);
            put_links(&mut m, l);
        }
        c.post(0, TAG_DONE, m)?;
    }
}

// --- Wire format (little-endian), as written at each encoder above ---

fn put_links(b: &mut Vec<u8>, links: &[Link]) {
    put_u32(b, links.len() as u32);
    for l in links {
        put_u32(b, l.recv);
        put_u32(b, l.src);
        b.extend_from_slice(&l.f.to_le_bytes());
    }
}

/// A work message, the pairs with their last round's links: `None` for stop.
type Work = Vec<(usize, Vec<Link>)>;
fn decode_work(
    msg: &[u8],
    h: &Hierarchy<'_>,
    pairs: &[(u32, u32)],
) -> Result<Option<Work>, String> {
    let mut r = Reader(msg);
    if r.u8()? == 0 {
        return Ok(None);
    }
    let npairs = pairs.len();
    let n = r.u32()? as usize;
    let mut chunk = Vec::with_capacity(n.min(npairs));
    for _ in 0..n {
        let k = r.u32()? as usize;
        if k >= npairs {
            return Err(format!("pair {k} of {npairs}"));
        }
        let (p, q) = pairs[k];
        let known = decode_links(&mut r, h, p as usize, Some(q as usize))?;
        if !known.is_sorted_by_key(|l| (l.recv, l.src)) {
            return Err(format!("the known links of pair {k} are not sorted"));
        }
        chunk.push((k, known));
    }
    Ok(Some(chunk))
}

/// A worker's finished chunk, which must hold exactly the pairs of `chunk`, in order.
fn decode_done(
    msg: &[u8],
    h: &Hierarchy<'_>,
    pairs: &[(u32, u32)],
    chunk: &[usize],
) -> Result<Vec<(usize, Vec<Link>)>, String> {
    let mut r = Reader(msg);
    let n = r.u32()? as usize;
    if n != chunk.len() {
        return Err(format!("{n} pairs, expected {}", chunk.len()));
    }
    let mut out = Vec::with_capacity(n);
    for &want in chunk {
        let k = r.u32()? as usize;
        if k != want {
            return Err(format!("pair {k}, expected {want}"));
        }
        let (p, q) = pairs[k];
        out.push((k, decode_links(&mut r, h, p as usize, Some(q as usize))?));
    }
    Ok(out)
}

/// Links received by patch `p` (from patch `q` when given, else from any node).
fn decode_links(
    r: &mut Reader<'_>,
    h: &Hierarchy<'_>,
    p: usize,
    q: Option<usize>,
) -> Result<Vec<Link>, String> {
    let n = r.count(16)?;
    let mut out = Vec::with_capacity(n);
    for _ in 0..n {
        let (recv, src) = (r.u32()?, r.u32()?);
        let f = r.f64()?;
        let src_ok = match q {
            Some(q) => h.in_patch(src, q),
            None => (src as usize) < h.nodes(),
        };
        if !h.in_patch(recv, p) || !src_ok || !f.is_finite() {
            return Err(format!("link {src} -> {recv} (F = {f}) outside patch {p}"));
        }
        out.push(Link { recv, src, f });
    }
    Ok(out)
}
