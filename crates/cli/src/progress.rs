//! The one progress reporter of every long job (`radiosity`, `parallel`, `render`): on a
//! terminal an indicatif bar (or a spinner when the amount of work is unknown); when
//! standard error is a file or a pipe, one line every few seconds (a script's log is not
//! silent for minutes): what is running, the pass, samples per pixel and error estimate
//! of a progressive render, or the phase and its count, the elapsed time and an
//! estimate of the time left. `--quiet` silences both.
//!
//! The interval of the log lines is 5 s; `IRRADIA_PROGRESS_INTERVAL` (seconds) changes it.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Seconds between two log lines unless `IRRADIA_PROGRESS_INTERVAL` says otherwise.
pub const LOG_INTERVAL_SECONDS: f64 = 5.0;

/// Where a progressive render stands after a pass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PassStatus {
    /// Passes finished.
    pub pass: u32,
    /// Samples per pixel so far.
    pub spp: u64,
    /// The image's relative error estimate, when known.
    pub error: Option<f64>,
    /// The fraction of the budget (samples, time or error) used, for the time left.
    pub done: Option<f64>,
}

/// What is shown: the job, its phase and count, or the pass of a progressive render.
#[derive(Clone, Debug, Default)]
struct State {
    what: String,
    message: String,
    position: u64,
    length: Option<u64>,
    /// When the count was last reset (the time left is estimated from here).
    phase_start: Option<Instant>,
    pass: Option<PassStatus>,
}

/// The progress of one job; cheap to share by reference between threads.
pub struct Progress {
    bar: Option<ProgressBar>,
    state: Arc<Mutex<State>>,
    ticker: Mutex<Option<(Arc<AtomicBool>, JoinHandle<()>)>>,
}

impl Progress {
    /// Starts reporting `what` (e.g. "radiosity"): nothing when `quiet`, a bar on a
    /// terminal, log lines otherwise.
    pub fn new(what: &str, quiet: bool) -> Progress {
        let terminal = std::io::stderr().is_terminal();
        Self::with_target(what, quiet, terminal, log_interval())
    }

    fn with_target(what: &str, quiet: bool, terminal: bool, interval: Duration) -> Progress {
        let start = Instant::now();
        let state = Arc::new(Mutex::new(State {
            what: what.to_string(),
            phase_start: Some(start),
            ..State::default()
        }));
        let bar = (!quiet && terminal).then(|| {
            let b = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
            b.set_style(spinner_style());
            b.enable_steady_tick(Duration::from_millis(120));
            b.set_message(what.to_string());
            b
        });
        let ticker = (!quiet && !terminal).then(|| {
            let stop = Arc::new(AtomicBool::new(false));
            let (s, st) = (stop.clone(), state.clone());
            let handle = std::thread::spawn(move || tick(&s, &st, start, interval));
            (stop, handle)
        });
        Progress {
            bar,
            state,
            ticker: Mutex::new(ticker),
        }
    }

    /// A new phase of `length` steps (`None`: unknown), counted from zero.
    pub fn phase(&self, name: &str, length: Option<u64>) {
        {
            let mut s = self.state.lock().unwrap_or_else(|e| e.into_inner());
            s.message = name.to_string();
            s.position = 0;
            s.length = length;
            s.phase_start = Some(Instant::now());
            s.pass = None;
        }
        if let Some(b) = &self.bar {
            match length {
                Some(n) => {
                    b.set_style(bar_style());
                    b.set_length(n.max(1));
                }
                None => b.set_style(spinner_style()),
            }
            b.set_position(0);
            b.set_message(name.to_string());
        }
    }

    /// Replaces the message, keeping the count (a stage of a job of unknown length).
    pub fn message(&self, msg: &str) {
        self.state.lock().unwrap_or_else(|e| e.into_inner()).message = msg.to_string();
        if let Some(b) = &self.bar {
            b.set_message(msg.to_string());
        }
    }

    /// Steps of the current phase done so far.
    pub fn set_position(&self, done: u64) {
        self.state
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .position = done;
        if let Some(b) = &self.bar {
            b.set_position(done);
        }
    }

    /// Sets the length of the current phase when it changes (learnt after the phase
    /// began), keeping the count.
    pub fn set_length(&self, length: u64) {
        {
            let mut s = self.state.lock().unwrap_or_else(|e| e.into_inner());
            if s.length == Some(length) {
                return;
            }
            s.length = Some(length);
        }
        if let Some(b) = &self.bar {
            b.set_style(bar_style());
            b.set_length(length.max(1));
        }
    }

    /// A progressive render finished a pass.
    pub fn pass(&self, p: PassStatus) {
        self.state.lock().unwrap_or_else(|e| e.into_inner()).pass = Some(p);
        if let Some(b) = &self.bar {
            b.set_message(pass_text(&p));
            if let Some(f) = p.done {
                b.set_style(bar_style());
                b.set_length(1000);
                b.set_position((f.clamp(0.0, 1.0) * 1000.0) as u64);
            }
        }
    }

    /// Clears the bar and stops the log lines (also on drop).
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
        if let Some((stop, handle)) = self.ticker.lock().unwrap_or_else(|e| e.into_inner()).take() {
            stop.store(true, Ordering::Relaxed);
            let _ = handle.join();
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}

/// `IRRADIA_PROGRESS_INTERVAL` seconds, or [`LOG_INTERVAL_SECONDS`].
fn log_interval() -> Duration {
    let s = std::env::var("IRRADIA_PROGRESS_INTERVAL")
        .ok()
        .and_then(|v| v.trim().parse::<f64>().ok())
        .filter(|s| s.is_finite() && *s > 0.0)
        .unwrap_or(LOG_INTERVAL_SECONDS);
    Duration::from_secs_f64(s.clamp(0.01, 3600.0))
}

/// The log-line thread: a line each `interval` until told to stop.
fn tick(stop: &AtomicBool, state: &Mutex<State>, start: Instant, interval: Duration) {
    let mut next = start + interval;
    while !stop.load(Ordering::Relaxed) {
        std::thread::sleep(Duration::from_millis(20).min(interval));
        let now = Instant::now();
        if now >= next {
            let s = state.lock().unwrap_or_else(|e| e.into_inner()).clone();
            eprintln!("{}", log_line(&s, now - start, now));
            next = now + interval;
        }
    }
}

fn spinner_style() -> ProgressStyle {
    ProgressStyle::with_template("{spinner} {elapsed:>4} {msg}").expect("a valid template")
}

fn bar_style() -> ProgressStyle {
    ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} ({eta})")
        .expect("a valid template")
        .progress_chars("=> ")
}

/// "pass 3, 48 spp, error 0.0123".
fn pass_text(p: &PassStatus) -> String {
    let mut t = format!("pass {}, {} spp", p.pass, p.spp);
    if let Some(e) = p.error {
        t.push_str(&format!(", error {e:.4}"));
    }
    t
}

/// Seconds as "42 s" or "3 min 05 s".
fn clock(d: Duration) -> String {
    let s = d.as_secs_f64();
    if s < 60.0 {
        format!("{s:.1} s")
    } else {
        let whole = s.round() as u64;
        format!("{} min {:02} s", whole / 60, whole % 60)
    }
}

/// One log line: "irradia: radiosity: form factors 120/400, elapsed 5.0 s, eta 11.7 s".
fn log_line(s: &State, elapsed: Duration, now: Instant) -> String {
    let mut line = format!("irradia: {}", s.what);
    if let Some(p) = &s.pass {
        line.push_str(&format!(": {}, elapsed {}", pass_text(p), clock(elapsed)));
        if let Some(f) = p.done.filter(|f| *f > 0.0 && *f < 1.0) {
            let left = elapsed.as_secs_f64() * (1.0 - f) / f;
            line.push_str(&format!(", eta {}", clock(Duration::from_secs_f64(left))));
        }
        return line;
    }
    if !s.message.is_empty() && s.message != s.what {
        line.push_str(&format!(": {}", s.message));
    }
    if let Some(n) = s.length {
        line.push_str(&format!(" {}/{n}", s.position.min(n)));
    }
    line.push_str(&format!(", elapsed {}", clock(elapsed)));
    if let (Some(n), Some(t0)) = (s.length, s.phase_start) {
        if s.position > 0 && s.position < n {
            let spent = now.duration_since(t0).as_secs_f64();
            let left = spent * (n - s.position) as f64 / s.position as f64;
            line.push_str(&format!(", eta {}", clock(Duration::from_secs_f64(left))));
        }
    }
    line
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_counted_phase_shows_count_elapsed_and_time_left() {
        let now = Instant::now();
        let s = State {
            what: "radiosity".into(),
            message: "form factors".into(),
            position: 100,
            length: Some(400),
            phase_start: now.checked_sub(Duration::from_secs(4)),
            pass: None,
        };
        assert_eq!(
            log_line(&s, Duration::from_secs(5), now),
            "irradia: radiosity: form factors 100/400, elapsed 5.0 s, eta 12.0 s"
        );
    }

    #[test]
    fn a_pass_shows_spp_error_and_time_left() {
        let s = State {
            what: "render".into(),
            pass: Some(PassStatus {
                pass: 3,
                spp: 48,
                error: Some(0.01234),
                done: Some(0.25),
            }),
            ..State::default()
        };
        assert_eq!(
            log_line(&s, Duration::from_secs(90), Instant::now()),
            "irradia: render: pass 3, 48 spp, error 0.0123, elapsed 1 min 30 s, eta 4 min 30 s"
        );
    }

    #[test]
    fn log_lines_come_every_interval_and_stop_at_finish() {
        // Not a terminal: the ticker runs; quiet: nothing at all.
        let p = Progress::with_target("job", false, false, Duration::from_millis(30));
        assert!(p.ticker.lock().unwrap().is_some());
        p.phase("phase", Some(10));
        p.set_position(5);
        std::thread::sleep(Duration::from_millis(80));
        p.finish();
        assert!(p.ticker.lock().unwrap().is_none());
        let q = Progress::with_target("job", true, false, Duration::from_millis(30));
        assert!(q.ticker.lock().unwrap().is_none() && q.bar.is_none());
    }
}
