//! Ctrl-C (SIGINT) and SIGTERM during `rodlab run` and the main job: the run stops at the next
//! frame boundary, prints its summary, finishes its recording (footer included), and the
//! process exits with 130 or 143, as a shell expects.
//!
//! A second signal while stopping exits at once with its own code, unless it comes within
//! [`ONE_SIGNAL_WINDOW`] of the first: signals that close together are one request. GNU
//! `timeout` sends SIGTERM to its child and then to its own process group, which holds the
//! child too, so the child gets two SIGTERMs microseconds apart; and a terminal's Ctrl-C
//! reaches every process of the foreground group at once.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use signal_hook::consts::{SIGINT, SIGTERM};

/// Stop signals that arrive within this time of the first count as that one request.
pub const ONE_SIGNAL_WINDOW: Duration = Duration::from_millis(500);

struct Flags {
    interrupt: AtomicBool,
    terminate: AtomicBool,
    /// Nanoseconds from `started` to the first signal, plus one (0: no signal yet).
    first_signal: AtomicU64,
    started: Instant,
}

static FLAGS: OnceLock<Flags> = OnceLock::new();

/// Installs the handlers (once; later calls do nothing).
pub fn install() -> anyhow::Result<()> {
    if FLAGS.get().is_some() {
        return Ok(());
    }
    let _ = FLAGS.set(Flags {
        interrupt: AtomicBool::new(false),
        terminate: AtomicBool::new(false),
        first_signal: AtomicU64::new(0),
        started: Instant::now(),
    });
    for (signal, code) in [(SIGINT, 130), (SIGTERM, 143)] {
        // SAFETY: the handler only reads the initialised `FLAGS`, reads the monotonic clock
        // (clock_gettime, async-signal-safe), does atomic stores and compare-exchanges, and
        // may call `_exit`: all async-signal-safe, no allocation, no lock.
        unsafe {
            signal_hook::low_level::register(signal, move || on_signal(code))?;
        }
    }
    Ok(())
}

/// The handler of a stop signal whose exit code is `code`.
fn on_signal(code: i32) {
    let Some(flags) = FLAGS.get() else {
        return;
    };
    let now = flags.started.elapsed().as_nanos() as u64 + 1;
    let flag = match code {
        130 => &flags.interrupt,
        _ => &flags.terminate,
    };
    let first = flags
        .first_signal
        .compare_exchange(0, now, Ordering::SeqCst, Ordering::SeqCst);
    if let Err(first) = first {
        if now.saturating_sub(first) > ONE_SIGNAL_WINDOW.as_nanos() as u64 {
            signal_hook::low_level::exit(code);
        }
        if flags.interrupt.load(Ordering::SeqCst) || flags.terminate.load(Ordering::SeqCst) {
            return; // the same request: its exit code stays the first signal's
        }
    }
    flag.store(true, Ordering::SeqCst);
}

/// Whether a stop was asked for.
pub fn requested() -> bool {
    exit_code().is_some()
}

/// The exit code the signal asks for: 130 (SIGINT) or 143 (SIGTERM), if one came.
pub fn exit_code() -> Option<i32> {
    let flags = FLAGS.get()?;
    if flags.interrupt.load(Ordering::Relaxed) {
        Some(130)
    } else if flags.terminate.load(Ordering::Relaxed) {
        Some(143)
    } else {
        None
    }
}

/// The signal's name, for messages.
pub fn signal_name() -> &'static str {
    match exit_code() {
        Some(130) => "SIGINT",
        Some(_) => "SIGTERM",
        None => "no signal",
    }
}
