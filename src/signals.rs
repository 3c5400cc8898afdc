//! What happens on SIGINT, SIGTERM and SIGHUP: every registered clean-up runs (NuSMV processes
//! killed, temporary files and staging folders removed), then the program exits with 130.
//!
//! The handler is installed on the first registration. Registrations are plain functions, so
//! that this module depends on nothing and every other module may use it.

use std::sync::{Mutex, Once};

static HOOKS: Mutex<Vec<fn()>> = Mutex::new(Vec::new());
static INSTALL: Once = Once::new();

/// Runs `hook` when a termination signal arrives (once per distinct function).
pub(crate) fn on_termination(hook: fn()) {
    {
        let mut hooks = HOOKS.lock().unwrap_or_else(|e| e.into_inner());
        if !hooks.iter().any(|&h| h as usize == hook as usize) {
            hooks.push(hook);
        }
    }
    INSTALL.call_once(|| {
        // Fails only when the program installed a handler of its own first; that program
        // must then call `run_hooks` from it.
        let _ = ctrlc::set_handler(|| {
            run_hooks();
            std::process::exit(130);
        });
    });
}

/// Runs every registered clean-up.
pub(crate) fn run_hooks() {
    let hooks: Vec<fn()> = HOOKS.lock().unwrap_or_else(|e| e.into_inner()).clone();
    for hook in hooks {
        hook();
    }
}
