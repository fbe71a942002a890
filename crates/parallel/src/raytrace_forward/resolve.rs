//! One generation's exchange: every rank's unanswered queries go to every rank, each
//! rank answers all of them against the objects it owns, and the answers go back to
//! the rank that asked, which merges them (nearest hit, ties to the lower rank; blocked
//! if any rank blocks).
//!
//! This is the "data-parallel" ray forwarding of Reinhard and Jansen (1997) and of
//! Navrátil et al. (2014, "Exploring the spectrum of dynamic scheduling algorithms for
//! scalable distributed-memory ray tracing") reduced to its simplest schedule: a ray is
//! not routed to the owners of the cells it crosses in turn but offered at once to
//! every owner whose domain (the bounding box of its objects, [`super::domain`]) the
//! ray's segment crosses, in two personalised all-to-all exchanges. That needs no
//! spatial decomposition of the objects (ranks own any blocks of objects, as in
//! sort-last rendering) and keeps the answer exactly the serial one: each owner's
//! nearest hit among its objects is the serial tracer's hit test on those objects, and
//! the nearest of them is the scene's.
//!
//! Messages: queries are `[u64 count of all the sender's queries][30-byte queries]`
//! (the count, seen by every rank, tells all of them together when nobody asks
//! anything); answers are the receiver's answers in the order of the queries it got.

use super::domain::Domain;
use super::wire::{Answer, Kind, Query};
use crate::comm::{Comm, CommError};
use irradia_render::whitted::{RayQuery, SceneGeometry};
use rayon::prelude::*;

/// The objects this rank owns: their geometry (`None` when it owns none) and the
/// scene index of the first.
pub struct Owned<'s> {
    pub geometry: Option<SceneGeometry<'s>>,
    pub first: u32,
}

impl Owned<'_> {
    /// This rank's answer to `q` over its own objects, with scene object indices.
    pub fn answer(&self, q: &Query) -> Answer {
        let (ray, t_max, set) = (q.ray(), q.t_max(), q.set());
        let Some(g) = &self.geometry else {
            return match q.kind() {
                Kind::Nearest => Answer::Nearest(None),
                Kind::Any => Answer::Any(false),
            };
        };
        match q.kind() {
            Kind::Nearest => Answer::Nearest(g.closest_hit(set, &ray, t_max).map(|mut h| {
                h.instance += self.first;
                h
            })),
            Kind::Any => Answer::Any(g.any_hit(set, &ray, t_max)),
        }
    }
}

/// What one exchange moved, seen from this rank.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Traffic {
    /// Queries asked by all ranks together in this generation.
    pub queries_total: u64,
    /// Queries this rank asked.
    pub queries_mine: u64,
    /// Bytes this rank sent and received (queries and answers, to and from others).
    pub bytes_sent: u64,
    pub bytes_received: u64,
}

/// Resolves `mine` (this rank's unanswered queries, without duplicates) with every
/// rank, into `answered` (one answer per query, in the same order). Collective: every rank calls it in every generation, with an
/// empty list when it has nothing to ask. Returns the traffic; `queries_total == 0`
/// means no rank asked anything (every rank sees the same), and then nothing more is
/// sent.
/// `domains` holds every rank's [`Domain`]: a query goes only to the ranks whose
/// domain its segment may cross.
pub fn resolve<C: Comm>(
    comm: &C,
    owned: &Owned<'_>,
    domains: &[Domain],
    mine: &[Query],
    answered: &mut Vec<Answer>,
) -> Result<Traffic, CommError> {
    answered.clear();
    let (me, p) = (comm.rank(), comm.size());
    // Which ranks each query goes to, one bit per rank (at most 64 ranks get a bit;
    // beyond that every query goes everywhere).
    let targets: Vec<u64> = mine
        .par_iter()
        .map(|q| {
            let (ray, t_max) = (q.ray(), q.t_max());
            domains
                .iter()
                .take(64)
                .enumerate()
                .filter(|(_, d)| d.may_hit(&ray, t_max))
                .fold(0u64, |m, (r, _)| m | 1 << r)
        })
        .collect();
    let sent_to = |i: usize, rank: usize| rank >= 64 || targets[i] >> rank & 1 == 1;
    let asks: Vec<Vec<u8>> = (0..p)
        .map(|rank| {
            let mut out = (mine.len() as u64).to_le_bytes().to_vec();
            for (i, q) in mine.iter().enumerate() {
                if sent_to(i, rank) {
                    q.encode(&mut out);
                }
            }
            out
        })
        .collect();
    let asked = comm.all_to_all(&asks)?;
    let mut traffic = Traffic {
        queries_mine: mine.len() as u64,
        ..Traffic::default()
    };
    for (rank, a) in asks.iter().enumerate() {
        if rank != me {
            traffic.bytes_sent += a.len() as u64;
        }
    }
    drop(asks);
    let mut lists = Vec::with_capacity(p);
    for (rank, bytes) in asked.iter().enumerate() {
        let malformed = || CommError::Malformed {
            rank,
            message: format!("{} bytes are not a list of ray queries", bytes.len()),
        };
        let count = bytes
            .get(..8)
            .map(|b| u64::from_le_bytes(b.try_into().expect("8 bytes")))
            .ok_or_else(malformed)?;
        let list = Query::decode_all(&bytes[8..]).ok_or_else(malformed)?;
        traffic.queries_total += count;
        if rank != me {
            traffic.bytes_received += bytes.len() as u64;
        }
        lists.push(list);
    }
    drop(asked);
    if traffic.queries_total == 0 {
        return Ok(traffic);
    }

    // Answer every rank's queries against the objects owned here.
    let replies: Vec<Vec<u8>> = lists
        .iter()
        .map(|list| {
            let parts: Vec<Vec<u8>> = list
                .par_chunks(256)
                .map(|chunk| {
                    let mut out = Vec::with_capacity(chunk.len() * 8);
                    chunk.iter().for_each(|q| owned.answer(q).encode(&mut out));
                    out
                })
                .collect();
            parts.concat()
        })
        .collect();
    drop(lists);
    for (rank, r) in replies.iter().enumerate() {
        if rank != me {
            traffic.bytes_sent += r.len() as u64;
        }
    }
    let answers = comm.all_to_all(&replies)?;
    drop(replies);

    // Merge the ranks' answers to this rank's queries, in rank order.
    let mut at = vec![0usize; p];
    for (i, q) in mine.iter().enumerate() {
        let mut merged = None::<Answer>;
        for (rank, bytes) in answers.iter().enumerate() {
            if !sent_to(i, rank) {
                continue;
            }
            let a = Answer::decode(q.kind(), bytes, &mut at[rank]).ok_or_else(|| {
                CommError::Malformed {
                    rank,
                    message: format!(
                        "the answers end or go wrong at byte {} of {}",
                        at[rank],
                        bytes.len()
                    ),
                }
            })?;
            match &mut merged {
                None => merged = Some(a),
                Some(m) => m.merge(a),
            }
        }
        let nobody = match q.kind() {
            Kind::Nearest => Answer::Nearest(None),
            Kind::Any => Answer::Any(false),
        };
        answered.push(merged.unwrap_or(nobody));
    }
    for (rank, bytes) in answers.iter().enumerate() {
        if rank != me {
            traffic.bytes_received += bytes.len() as u64;
        }
        if at[rank] != bytes.len() {
            return Err(CommError::Malformed {
                rank,
                message: format!("{} bytes of answers left over", bytes.len() - at[rank]),
            });
        }
    }
    Ok(traffic)
}
