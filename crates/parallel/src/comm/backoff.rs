//! How a rank waits for a message it polls for ([`super::MpiComm`]'s receives and
//! request tests): spin a little, then yield, and (if asked) sleep.
//!
//! Spinning answers fastest when the partner is running on another core. But with as
//! many ranks as cores (or more) and other processes on the machine, a rank that only
//! spins and yields (`sched_yield`) keeps its core busy: the core never goes idle, so
//! the scheduler does not pull the descheduled partner onto it (Linux's fair scheduler balances a
//! newly idle core at once, a busy one only at its periodic balance, every few
//! milliseconds), and the wait lasts until the partner's core frees up. Sleeping
//! leaves the core idle for the partner; the price is the wake-up latency (the sleep
//! plus the kernel's timer slack, 50 µs by default), paid only by waits already longer
//! than the spin window. This is the "spin then block" policy of Ousterhout's
//! two-phase waiting (Ousterhout 1982, "Scheduling techniques for concurrent systems";
//! Karlin et al. 1991, "Empirical studies of competitive spinning for a shared-memory
//! multiprocessor": spinning for about the cost of a block and wake-up, then blocking,
//! is within a factor of two of the best policy).
//!
//! `IRRADIA_MPI_WAIT` chooses: `spin` (the default: a few quick polls, then a yield
//! between polls, never a sleep), `busy:MICROSECONDS` (poll without yielding that
//! long, then yield) or `sleep` (spin and yield for [`SPIN`], then sleep
//! [`FIRST_SLEEP`], doubling to [`MAX_SLEEP`]). Measured on the 2-core machine at load
//! 10-14 (docs/benchmarks.md, issue 15, 2026-12-03 evening), sleeping did not shorten
//! the 2-rank composite and the spread of its calls came from the scheduler, not from
//! the wait, so spinning stays the default and the others are there to compare.

use std::sync::OnceLock;
use std::time::Duration;

/// How long a wait spins and yields before it starts sleeping.
pub const SPIN: Duration = Duration::from_micros(50);
/// The first sleep after the spin window.
pub const FIRST_SLEEP: Duration = Duration::from_micros(20);
/// The longest sleep (a message that arrives during a sleep waits at most this, plus
/// the timer slack).
pub const MAX_SLEEP: Duration = Duration::from_micros(200);

/// What a waiting rank does between two polls.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    /// Poll again at once.
    Spin,
    /// Give the core to another runnable thread, if any (`sched_yield`).
    Yield,
    /// Sleep this long (the core goes idle unless something else runs).
    Sleep(Duration),
}

/// The waiting policy (see the module's documentation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Policy {
    /// Spin, then yield, never sleep (the default).
    SpinYield,
    /// Poll without yielding for this long, then yield, never sleep: holds the core
    /// while the partner, running on the other core, is about to answer, instead of
    /// handing it to another process for a whole time slice.
    BusyThenYield(Duration),
    /// Spin and yield for [`SPIN`], then sleep with a doubling, capped length.
    SpinThenSleep,
}

impl Policy {
    /// The policy when `IRRADIA_MPI_WAIT` is unset.
    pub const DEFAULT: Policy = Policy::SpinYield;

    /// The process's policy: `IRRADIA_MPI_WAIT` (`spin`, `busy:MICROSECONDS` or
    /// `sleep`), read once; [`Policy::DEFAULT`] when unset or unknown.
    pub fn from_env() -> Policy {
        static P: OnceLock<Policy> = OnceLock::new();
        *P.get_or_init(|| Policy::parse(std::env::var("IRRADIA_MPI_WAIT").ok().as_deref()))
    }

    /// The policy named `name` (`spin`, `busy:MICROSECONDS` or `sleep`; anything else
    /// the default).
    pub fn parse(name: Option<&str>) -> Policy {
        match name.map(str::trim) {
            Some("spin") => Policy::SpinYield,
            Some("sleep") => Policy::SpinThenSleep,
            Some(s) => match s.strip_prefix("busy:").and_then(|us| us.parse().ok()) {
                Some(us) => Policy::BusyThenYield(Duration::from_micros(us)),
                None => Policy::DEFAULT,
            },
            None => Policy::DEFAULT,
        }
    }
}

/// One wait's state: how many polls failed and how long it has slept so far.
#[derive(Clone, Debug)]
pub struct Backoff {
    policy: Policy,
    polls: u32,
    sleep: Duration,
}

/// Polls answered by spinning alone (no clock read) before yielding starts.
const QUICK_POLLS: u32 = 64;

impl Backoff {
    /// A new wait under `policy`.
    pub fn new(policy: Policy) -> Self {
        Backoff {
            policy,
            polls: 0,
            sleep: FIRST_SLEEP,
        }
    }

    /// The step after a failed poll, `waited` after the wait began (read only once
    /// the quick polls are spent, so the caller may pass anything before that).
    pub fn step(&mut self, waited: Duration) -> Step {
        self.polls = self.polls.saturating_add(1);
        if self.polls <= QUICK_POLLS {
            return Step::Spin;
        }
        match self.policy {
            Policy::SpinYield => Step::Yield,
            Policy::BusyThenYield(d) if waited < d => Step::Spin,
            Policy::BusyThenYield(_) => Step::Yield,
            Policy::SpinThenSleep if waited < SPIN => Step::Yield,
            Policy::SpinThenSleep => {
                let s = self.sleep;
                self.sleep = (self.sleep * 2).min(MAX_SLEEP);
                Step::Sleep(s)
            }
        }
    }

    /// Whether the next [`Backoff::step`] needs the time waited (the caller reads the
    /// clock only then, and checks its deadline with the same reading).
    pub fn needs_clock(&self) -> bool {
        self.polls >= QUICK_POLLS
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn steps(policy: Policy, waited: Duration, n: usize) -> Vec<Step> {
        let mut b = Backoff::new(policy);
        (0..n).map(|_| b.step(waited)).collect()
    }

    #[test]
    fn quick_polls_spin_under_both_policies() {
        for p in [Policy::SpinYield, Policy::SpinThenSleep] {
            let s = steps(p, Duration::from_secs(1), QUICK_POLLS as usize);
            assert!(s.iter().all(|&x| x == Step::Spin), "{p:?}: {s:?}");
        }
    }

    #[test]
    fn spin_yield_never_sleeps() {
        let s = steps(Policy::SpinYield, Duration::from_secs(10), 1000);
        assert_eq!(s[QUICK_POLLS as usize..].len(), 1000 - QUICK_POLLS as usize);
        assert!(s[QUICK_POLLS as usize..].iter().all(|&x| x == Step::Yield));
    }

    #[test]
    fn sleeps_only_after_the_spin_window_doubling_to_the_cap() {
        let mut b = Backoff::new(Policy::SpinThenSleep);
        for _ in 0..QUICK_POLLS {
            assert!(!b.needs_clock());
            assert_eq!(b.step(Duration::ZERO), Step::Spin);
        }
        assert!(b.needs_clock());
        // Inside the spin window: yield, however many polls.
        for _ in 0..500 {
            assert_eq!(b.step(SPIN / 2), Step::Yield);
        }
        // Past it: 20, 40, 80, 160, then 200 µs for ever.
        let after: Vec<Step> = (0..7).map(|_| b.step(SPIN)).collect();
        let us = |u| Step::Sleep(Duration::from_micros(u));
        assert_eq!(
            after,
            vec![us(20), us(40), us(80), us(160), us(200), us(200), us(200)]
        );
    }

    #[test]
    fn busy_then_yield_spins_for_its_window_then_yields() {
        let p = Policy::BusyThenYield(Duration::from_micros(300));
        let mut b = Backoff::new(p);
        for _ in 0..QUICK_POLLS + 500 {
            assert_eq!(b.step(Duration::from_micros(299)), Step::Spin);
        }
        assert_eq!(b.step(Duration::from_micros(300)), Step::Yield);
        assert_eq!(b.step(Duration::from_secs(5)), Step::Yield);
    }

    #[test]
    fn policy_names() {
        assert_eq!(Policy::parse(Some("spin")), Policy::SpinYield);
        assert_eq!(Policy::parse(Some(" spin ")), Policy::SpinYield);
        assert_eq!(Policy::parse(Some("sleep")), Policy::SpinThenSleep);
        assert_eq!(Policy::parse(None), Policy::DEFAULT);
        assert_eq!(Policy::parse(Some("bogus")), Policy::DEFAULT);
        assert_eq!(
            Policy::parse(Some("busy:300")),
            Policy::BusyThenYield(Duration::from_micros(300))
        );
        assert_eq!(Policy::parse(Some("busy:x")), Policy::DEFAULT);
    }
}
