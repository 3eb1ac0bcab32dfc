//! Stopping a run on SIGINT, SIGTERM or SIGHUP: the handler only notes the signal, and the
//! run's observer stops at the next Newton iteration or increment; the command then removes
//! its unfinished output and exits with 128 plus the signal's number.

use std::sync::atomic::{AtomicI32, Ordering};

/// The signal caught, 0 while none has been.
static CAUGHT: AtomicI32 = AtomicI32::new(0);

/// Note SIGINT, SIGTERM and SIGHUP from now on instead of dying at once.
pub(super) fn catch() {
    #[cfg(unix)]
    for signal in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
        // SAFETY: the action only stores to an atomic, which is async-signal-safe.
        let _ = unsafe {
            signal_hook_registry::register(signal, move || CAUGHT.store(signal, Ordering::SeqCst))
        };
    }
}

/// The signal caught, if one was.
pub(super) fn caught() -> Option<i32> {
    match CAUGHT.load(Ordering::SeqCst) {
        0 => None,
        s => Some(s),
    }
}

/// The name of signal `s`.
pub(super) fn name(s: i32) -> &'static str {
    match s {
        2 => "SIGINT",
        15 => "SIGTERM",
        1 => "SIGHUP",
        _ => "a signal",
    }
}
