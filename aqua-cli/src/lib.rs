//! aqua-cli: the `aqua` binary — argument parsing, printing and progress bars around aqua-sim.
//!
//! Every subcommand lives in [`commands`]; `main.rs` only parses the command line, dispatches
//! and maps errors to exit codes (2 for bad input, see [`InputError`] and
//! `aqua_sim::SimError::is_input`; 1 for a failed run).

pub mod commands;

use std::sync::atomic::{AtomicBool, Ordering};

/// Set by the Ctrl-C handler; long runs poll it between steps and stop cleanly.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Ask running solves to stop after the current step (called from the Ctrl-C handler).
pub fn request_stop() {
    INTERRUPTED.store(true, Ordering::SeqCst);
}

/// True once a stop was requested.
pub fn interrupted() -> bool {
    INTERRUPTED.load(Ordering::SeqCst)
}

use std::fmt;

/// An error caused by the user's input (a flag, a scene key, a file): the binary exits with 2.
///
/// The message names the file/key/value and says what would be valid.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InputError(pub String);

impl InputError {
    /// Wrap a message that names the offending input and the valid range.
    pub fn new(msg: impl Into<String>) -> Self {
        Self(msg.into())
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for InputError {}

/// True when the error (or anything in its chain) is an [`InputError`] or an input
/// [`aqua_sim::SimError`].
pub fn is_input_error(err: &anyhow::Error) -> bool {
    err.chain().any(|e| {
        e.downcast_ref::<InputError>().is_some()
            || e.downcast_ref::<aqua_sim::SimError>()
                .is_some_and(aqua_sim::SimError::is_input)
    })
}
