//! The forwarded geometry queries and their answers, and how they travel.
//!
//! A query is the exact bits of what the Whitted tracer asked: nearest hit or any hit,
//! of which objects (all, opaque, clear: `irradia_render::whitted::ObjectSet`), along
//! which ray (origin and direction) up to which `t_max`. Bits, not values, so that a
//! query replayed in a later generation finds its answer (the replay computes the same
//! ray bit for bit) and `-0.0` and `0.0` stay distinct. On the wire a query is 30 bytes
//! (tag, set, seven little-endian `f32`s); an answer is one byte for any-hit queries,
//! and one byte plus, for a hit, the 64-byte hit record (object index, `t`, point, the
//! two normals, uv, primitive, CSG leaf, error bound) for nearest-hit ones.
//!
//! Each rank answers every query against its own objects; the asker merges the answers
//! in rank order: the nearest hit wins, an equal `t` goes to the lower rank (which
//! owns the objects that come first, as in `crate::raytrace_last`'s depth compositing),
//! and a shadow ray is blocked when any rank blocks it.

use glam::{Vec2, Vec3};
use irradia_core::Ray;
use irradia_geometry::{Hit, SceneHit};
use irradia_render::whitted::ObjectSet;

/// Bytes of one query on the wire.
pub const QUERY_BYTES: usize = 30;
/// Bytes of one hit record on the wire (after its one-byte flag).
pub const HIT_BYTES: usize = 64;

/// What is asked along the ray.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Kind {
    /// The nearest hit.
    Nearest = 0,
    /// Whether anything is hit.
    Any = 1,
}

/// One geometry query, as bits (also the cache key).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Query {
    kind: Kind,
    set: u8,
    /// Origin, direction and `t_max` as `f32` bits.
    bits: [u32; 7],
}

/// The answer to a query, merged over every rank.
#[derive(Clone, Copy, Debug)]
pub enum Answer {
    Nearest(Option<SceneHit>),
    Any(bool),
}

impl PartialEq for Answer {
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (Answer::Any(a), Answer::Any(b)) => a == b,
            (Answer::Nearest(a), Answer::Nearest(b)) => match (a, b) {
                (None, None) => true,
                (Some(a), Some(b)) => a.instance == b.instance && a.hit == b.hit,
                _ => false,
            },
            _ => false,
        }
    }
}

fn set_code(set: ObjectSet) -> u8 {
    match set {
        ObjectSet::All => 0,
        ObjectSet::Opaque => 1,
        ObjectSet::Clear => 2,
    }
}

impl Query {
    pub fn new(kind: Kind, set: ObjectSet, ray: &Ray, t_max: f32) -> Self {
        let (o, d) = (ray.origin, ray.dir);
        Self {
            kind,
            set: set_code(set),
            bits: [o.x, o.y, o.z, d.x, d.y, d.z, t_max].map(f32::to_bits),
        }
    }

    pub fn kind(&self) -> Kind {
        self.kind
    }

    pub fn set(&self) -> ObjectSet {
        match self.set {
            0 => ObjectSet::All,
            1 => ObjectSet::Opaque,
            _ => ObjectSet::Clear,
        }
    }

    pub fn ray(&self) -> Ray {
        let f = self.bits.map(f32::from_bits);
        Ray::new(Vec3::new(f[0], f[1], f[2]), Vec3::new(f[3], f[4], f[5]))
    }

    pub fn t_max(&self) -> f32 {
        f32::from_bits(self.bits[6])
    }

    /// Appends the query's 30 bytes.
    pub fn encode(&self, out: &mut Vec<u8>) {
        out.push(self.kind as u8);
        out.push(self.set);
        for b in self.bits {
            out.extend_from_slice(&b.to_le_bytes());
        }
    }

    /// Reads a list of queries (a whole message); `None` when it is not one.
    pub fn decode_all(bytes: &[u8]) -> Option<Vec<Query>> {
        if !bytes.len().is_multiple_of(QUERY_BYTES) {
            return None;
        }
        bytes
            .chunks_exact(QUERY_BYTES)
            .map(|c| {
                let kind = match c[0] {
                    0 => Kind::Nearest,
                    1 => Kind::Any,
                    _ => return None,
                };
                if c[1] > 2 {
                    return None;
                }
                let mut bits = [0u32; 7];
                for (i, b) in bits.iter_mut().enumerate() {
                    *b = u32::from_le_bytes(c[2 + 4 * i..6 + 4 * i].try_into().unwrap());
                }
                Some(Query {
                    kind,
                    set: c[1],
                    bits,
                })
            })
            .collect()
    }
}

impl Answer {
    /// Appends this rank's answer (before merging).
    pub fn encode(&self, out: &mut Vec<u8>) {
        match self {
            Answer::Any(b) => out.push(*b as u8),
            Answer::Nearest(None) => out.push(0),
            Answer::Nearest(Some(sh)) => {
                out.push(1);
                let h = &sh.hit;
                let words = [
                    sh.instance,
                    h.t.to_bits(),
                    h.point.x.to_bits(),
                    h.point.y.to_bits(),
                    h.point.z.to_bits(),
                    h.normal.x.to_bits(),
                    h.normal.y.to_bits(),
                    h.normal.z.to_bits(),
                    h.shading_normal.x.to_bits(),
                    h.shading_normal.y.to_bits(),
                    h.shading_normal.z.to_bits(),
                    h.uv.x.to_bits(),
                    h.uv.y.to_bits(),
                    h.prim,
                    h.leaf,
                    h.error.to_bits(),
                ];
                for w in words {
                    out.extend_from_slice(&w.to_le_bytes());
                }
            }
        }
    }

    /// Reads the answer to a query of `kind` at `*at` in `bytes`, moving `*at` past it;
    /// `None` when the bytes end early or hold a bad flag.
    pub fn decode(kind: Kind, bytes: &[u8], at: &mut usize) -> Option<Answer> {
        let flag = *bytes.get(*at)?;
        *at += 1;
        match (kind, flag) {
            (Kind::Any, 0 | 1) => Some(Answer::Any(flag == 1)),
            (Kind::Nearest, 0) => Some(Answer::Nearest(None)),
            (Kind::Nearest, 1) => {
                let rec = bytes.get(*at..*at + HIT_BYTES)?;
                *at += HIT_BYTES;
                let w = |i: usize| u32::from_le_bytes(rec[4 * i..4 * i + 4].try_into().unwrap());
                let f = |i: usize| f32::from_bits(w(i));
                let v3 = |i: usize| Vec3::new(f(i), f(i + 1), f(i + 2));
                Some(Answer::Nearest(Some(SceneHit {
                    instance: w(0),
                    hit: Hit {
                        t: f(1),
                        point: v3(2),
                        normal: v3(5),
                        shading_normal: v3(8),
                        uv: Vec2::new(f(11), f(12)),
                        prim: w(13),
                        leaf: w(14),
                        error: f(15),
                    },
                })))
            }
            _ => None,
        }
    }

    /// Folds the answer of a higher rank into `self`: the nearer hit (a tie stays with
    /// the lower rank), or blocked if either blocks.
    pub fn merge(&mut self, later: Answer) {
        match (self, later) {
            (Answer::Any(a), Answer::Any(b)) => *a |= b,
            (Answer::Nearest(Some(best)), Answer::Nearest(Some(h))) if h.hit.t < best.hit.t => {
                *best = h
            }
            (Answer::Nearest(a @ None), Answer::Nearest(h)) => *a = h,
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn queries_and_hits_round_trip_bit_for_bit() {
        let ray = Ray::new(
            Vec3::new(-0.0, 1.5, f32::MIN_POSITIVE),
            Vec3::new(0.3, -2.0, 7.0),
        );
        let qs = [
            Query::new(Kind::Nearest, ObjectSet::All, &ray, f32::INFINITY),
            Query::new(Kind::Any, ObjectSet::Opaque, &ray, 3.25),
            Query::new(Kind::Nearest, ObjectSet::Clear, &ray, 1e-30),
        ];
        let mut buf = Vec::new();
        qs.iter().for_each(|q| q.encode(&mut buf));
        assert_eq!(buf.len(), 3 * QUERY_BYTES);
        assert_eq!(Query::decode_all(&buf).unwrap(), qs);
        assert_eq!(qs[1].set(), ObjectSet::Opaque);
        assert_eq!(qs[0].ray().origin.x.to_bits(), (-0.0f32).to_bits());
        assert!(Query::decode_all(&buf[1..]).is_none());

        let hit = SceneHit {
            instance: 7,
            hit: Hit {
                t: 2.5,
                point: Vec3::new(1.0, -2.0, 3.0),
                normal: Vec3::Y,
                shading_normal: Vec3::new(0.0, 0.6, 0.8),
                uv: Vec2::new(0.25, 0.75),
                prim: 11,
                leaf: 2,
                error: 1e-6,
            },
        };
        let answers = [
            Answer::Nearest(Some(hit)),
            Answer::Any(true),
            Answer::Nearest(None),
        ];
        let mut buf = Vec::new();
        answers.iter().for_each(|a| a.encode(&mut buf));
        assert_eq!(buf.len(), 1 + HIT_BYTES + 1 + 1);
        let mut at = 0;
        for (a, q) in answers.iter().zip(&qs) {
            assert_eq!(Answer::decode(q.kind(), &buf, &mut at).as_ref(), Some(a));
        }
        assert_eq!(at, buf.len());
    }

    #[test]
    fn merge_keeps_the_nearest_and_ties_to_the_lower_rank() {
        let at = |t: f32, instance: u32| {
            let mut h = SceneHit {
                instance,
                hit: Hit::new(t, Vec3::ZERO, Vec3::Z, Vec2::ZERO),
            };
            h.hit.prim = instance;
            Answer::Nearest(Some(h))
        };
        let mut a = Answer::Nearest(None);
        a.merge(at(3.0, 0));
        a.merge(at(2.0, 1));
        a.merge(at(2.0, 2));
        a.merge(Answer::Nearest(None));
        assert_eq!(a, at(2.0, 1));
        let mut b = Answer::Any(false);
        b.merge(Answer::Any(true));
        b.merge(Answer::Any(false));
        assert_eq!(b, Answer::Any(true));
    }
}
