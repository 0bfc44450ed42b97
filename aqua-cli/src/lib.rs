//! aqua-cli: the `aqua` binary — argument parsing, printing and progress bars around aqua-sim.
//!
//! Every subcommand lives in [`commands`]; `main.rs` only parses the command line, dispatches
//! and maps errors to exit codes (2 for bad input, see [`InputError`] and
//! `aqua_sim::SimError::is_input`; 1 for a failed run).

pub mod commands;

use std::sync::atomic::{AtomicI32, Ordering};

/// The first stop signal received (SIGINT, SIGTERM or SIGHUP), 0 while none; long runs poll
/// it between steps and stop cleanly.
static STOP_SIGNAL: AtomicI32 = AtomicI32::new(0);

/// Ask running solves to stop after the current step (called from the signal thread with the
/// signal's number; the first signal is the one the exit code reports).
pub fn request_stop(signal: i32) {
    let _ = STOP_SIGNAL.compare_exchange(0, signal.max(1), Ordering::SeqCst, Ordering::SeqCst);
}

/// True once a stop was requested.
pub fn interrupted() -> bool {
    STOP_SIGNAL.load(Ordering::SeqCst) != 0
}

/// The exit status of a run stopped by a signal: 128 + the signal's number, as a shell
/// reports a process killed by it (130 for Ctrl-C's SIGINT, 143 for the SIGTERM that Slurm
/// and `kill` send); 130 when no signal is recorded.
pub fn interrupted_exit_code() -> i32 {
    match STOP_SIGNAL.load(Ordering::SeqCst) {
        0 => 130,
        s => 128 + s,
    }
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
