//! What happens on SIGINT, SIGTERM and SIGHUP: every registered clean-up runs (NuSMV processes
//! killed, temporary files and staging folders removed), then the program exits with 130.
//!
//! The handler is installed by the command line before any work ([`install`]), so a signal
//! ends every phase the same way (reading included), and otherwise on the first registration.
//! Registrations are plain functions, so that this module depends on nothing and every other
//! module may use it.
//!
//! While a live run records ([`stop_first`]) the first signal only asks it to stop: it
//! finishes its file and ends with 130 itself ([`end_stopped`]); a second signal ends it at once.
//!
//! While a result is being published ([`hold`]) a signal waits: the moves finish, so the
//! folder holds one whole result. Once it is published the signal is dropped and the run ends
//! with its own outcome; a publish that fails honours it.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, Once};

static HOOKS: Mutex<Vec<fn()>> = Mutex::new(Vec::new());
static INSTALL: Once = Once::new();

/// Set once the clean-up began: what registers a clean-up later (another thread still at
/// work) does it at once ([`terminating`]).
static TERMINATING: AtomicBool = AtomicBool::new(false);

/// Whether the first signal only asks the run to stop ([`stop_first`]), and whether it came.
static STOP_FIRST: AtomicBool = AtomicBool::new(false);
static STOP_ASKED: AtomicBool = AtomicBool::new(false);

/// Whether a publish holds signals, and whether one came meanwhile. The handler keeps the lock
/// from its check to the exit, so a publish never starts once the clean-up began.
static STATE: Mutex<State> = Mutex::new(State {
    held: false,
    pending: false,
});

struct State {
    held: bool,
    pending: bool,
}

/// Runs `hook` when a termination signal arrives (once per distinct function).
pub(crate) fn on_termination(hook: fn()) {
    {
        let mut hooks = HOOKS.lock().unwrap_or_else(|e| e.into_inner());
        if !hooks.iter().any(|&h| h as usize == hook as usize) {
            hooks.push(hook);
        }
    }
    install();
}

/// Installs the handler (once): from now on SIGINT, SIGTERM and SIGHUP run the clean-ups
/// and end the program with 130, also where the shell started it with SIGINT ignored.
pub(crate) fn install() {
    INSTALL.call_once(|| {
        // Fails only when the program installed a handler of its own first; that program
        // must then call `run_hooks` from it.
        let _ = ctrlc::set_handler(|| {
            let mut state = STATE.lock().unwrap_or_else(|e| e.into_inner());
            if state.held {
                state.pending = true;
                return;
            }
            if STOP_FIRST.load(Ordering::SeqCst) && !STOP_ASKED.swap(true, Ordering::SeqCst) {
                return;
            }
            run_hooks();
            std::process::exit(130);
        });
    });
}

/// From now on the first termination signal only sets [`stop_asked`]: a live run polls it,
/// finishes its file and calls [`end_stopped`]. A second signal ends the program as usual.
pub(crate) fn stop_first() {
    STOP_FIRST.store(true, Ordering::SeqCst);
    install();
}

/// Whether a signal asked the run to stop ([`stop_first`]).
pub(crate) fn stop_asked() -> bool {
    STOP_ASKED.load(Ordering::SeqCst)
}

/// Ends a run that a signal stopped, once its file is written: the clean-ups run and the
/// program exits with 130, as for any signal.
pub(crate) fn end_stopped() -> ! {
    run_hooks();
    std::process::exit(130);
}

/// Whether the clean-up of a termination signal began.
pub(crate) fn terminating() -> bool {
    TERMINATING.load(Ordering::SeqCst)
}

/// Runs every registered clean-up.
pub(crate) fn run_hooks() {
    TERMINATING.store(true, Ordering::SeqCst);
    let hooks: Vec<fn()> = HOOKS.lock().unwrap_or_else(|e| e.into_inner()).clone();
    for hook in hooks {
        hook();
    }
}

/// Signals wait while this lives; see [`Hold::published`] and its `drop`.
pub(crate) struct Hold {
    published: bool,
}

/// Holds signals until the returned [`Hold`] is dropped (a publish that failed: a signal
/// that came meanwhile is honoured then) or [`Hold::published`].
pub(crate) fn hold() -> Hold {
    STATE.lock().unwrap_or_else(|e| e.into_inner()).held = true;
    Hold { published: false }
}

/// Whether signals are held now (for tests that signal in the middle of a publish).
#[cfg(test)]
pub(crate) fn held() -> bool {
    STATE.lock().unwrap_or_else(|e| e.into_inner()).held
}

impl Hold {
    /// The result is published: a signal that came meanwhile is dropped, so the run ends
    /// with the outcome of the result it published.
    pub(crate) fn published(mut self) {
        self.published = true;
    }
}

impl Drop for Hold {
    fn drop(&mut self) {
        let mut state = STATE.lock().unwrap_or_else(|e| e.into_inner());
        state.held = false;
        let pending = std::mem::take(&mut state.pending);
        if pending && !self.published {
            run_hooks();
            std::process::exit(130);
        }
    }
}
