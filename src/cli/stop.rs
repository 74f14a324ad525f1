//! Ctrl-C (SIGINT) and SIGTERM during `rodlab run` and the main job: the run stops at the next
//! frame boundary, prints its summary, finishes its recording (footer included), and the
//! process exits with 130 or 143, as a shell expects. A second signal while stopping exits at
//! once with the same code.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};

use signal_hook::consts::{SIGINT, SIGTERM};

struct Flags {
    interrupt: Arc<AtomicBool>,
    terminate: Arc<AtomicBool>,
}

static FLAGS: OnceLock<Flags> = OnceLock::new();

/// Installs the handlers (once; later calls do nothing).
pub fn install() -> anyhow::Result<()> {
    if FLAGS.get().is_some() {
        return Ok(());
    }
    let flags = Flags {
        interrupt: Arc::new(AtomicBool::new(false)),
        terminate: Arc::new(AtomicBool::new(false)),
    };
    for (signal, flag, code) in [
        (SIGINT, &flags.interrupt, 130),
        (SIGTERM, &flags.terminate, 143),
    ] {
        // first the shutdown on a second signal (it looks at the flag before the first sets it)
        signal_hook::flag::register_conditional_shutdown(signal, code, Arc::clone(flag))?;
        signal_hook::flag::register(signal, Arc::clone(flag))?;
    }
    let _ = FLAGS.set(flags);
    Ok(())
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
