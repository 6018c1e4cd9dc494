//! How a run fails: its exit status and what it prints.
//!
//! | kind | exit status | examples |
//! |---|---|---|
//! | usage | 2 | an unknown option (clap), conflicting or out-of-range options (`--spp 0`) |
//! | runtime | 1 | a missing or malformed scene, no device, an unwritable output |
//! | interrupted | 128 + the signal: 130 (SIGINT, Ctrl-C), 143 (SIGTERM) | a render stopped after writing its partial image |
//! | interrupted in set-up | the signal itself ends the process (a shell shows 130, 143) | Ctrl-C while the BVH is built or the kernels compile ([`SetupWatch`]) |
//!
//! The message goes to stderr as `error: ...`; with `--json` one object
//! `{"error": "...", "kind": "usage|runtime|interrupted"}` goes to stdout as well (an
//! interrupted render has printed its report, which says `"interrupted": true`, instead).

use std::fmt;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

/// A mistake in the command line that parsing cannot catch (conflicting or out-of-range
/// options): exit status 2, like clap's own usage errors.
#[derive(Debug)]
pub struct UsageError(pub String);

impl fmt::Display for UsageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UsageError {}

/// Returns a [`UsageError`] with the formatted message from the enclosing function.
macro_rules! usage {
    ($($arg:tt)*) => {
        return Err(anyhow::Error::new($crate::failure::UsageError(format!($($arg)*))))
    };
}
pub(crate) use usage;

/// A render stopped by a signal after writing what it had.
#[derive(Debug)]
pub struct Interrupted {
    /// The signal's number (2 SIGINT, 15 SIGTERM).
    pub signal: i32,
    /// What was stopped and written.
    pub message: String,
    /// Whether the command printed its report (with `--json`, the report's `interrupted` says
    /// so); if not, `main` prints the JSON error object instead.
    pub reported: bool,
}

impl fmt::Display for Interrupted {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Interrupted {}

/// The interrupted error for the signal received, naming it: `what` says what was written,
/// `reported` whether the command printed its report.
pub fn interrupted(what: &str, reported: bool) -> anyhow::Error {
    let signal = received_signal();
    let name = match signal {
        2 => "Ctrl-C (SIGINT)".to_string(),
        15 => "SIGTERM".to_string(),
        1 => "SIGHUP".to_string(),
        other => format!("signal {other}"),
    };
    anyhow::Error::new(Interrupted { signal, message: format!("interrupted by {name} {what}"), reported })
}

/// What kind of failure `error` is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A command-line mistake.
    Usage,
    /// Anything else that went wrong.
    Runtime,
    /// Stopped by this signal; `true` when the command printed its report.
    Interrupted(i32, bool),
}

impl Kind {
    /// The kind of `error`, looking through its context chain.
    pub fn of(error: &anyhow::Error) -> Kind {
        for cause in error.chain() {
            if cause.is::<UsageError>() {
                return Kind::Usage;
            }
            if let Some(interrupted) = cause.downcast_ref::<Interrupted>() {
                return Kind::Interrupted(interrupted.signal, interrupted.reported);
            }
        }
        Kind::Runtime
    }

    /// The exit status: 2, 1, or 128 + the signal.
    pub fn exit_status(self) -> u8 {
        match self {
            Kind::Usage => 2,
            Kind::Runtime => 1,
            Kind::Interrupted(signal, _) => u8::try_from(128 + signal).unwrap_or(1),
        }
    }

    /// The name in the JSON error object.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Usage => "usage",
            Kind::Runtime => "runtime",
            Kind::Interrupted(..) => "interrupted",
        }
    }
}

/// The one JSON error object a `--json` run prints on failure.
pub fn json_error(message: &str, kind: Kind) -> String {
    serde_json::json!({ "error": message, "kind": kind.name() }).to_string()
}

/// The flag the interrupt handler sets, shared by every render of the process.
static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
/// The number of the signal that interrupted the run (0: none recorded).
static SIGNAL: OnceLock<Arc<AtomicUsize>> = OnceLock::new();

/// The signal that interrupted the run (SIGINT when none was recorded).
fn received_signal() -> i32 {
    match SIGNAL.get().map_or(0, |s| s.load(Ordering::SeqCst)) {
        0 => signal_hook::consts::SIGINT,
        signal => signal as i32,
    }
}

/// Watches the interrupt flag on a thread while a render sets up (builds the BVH, compiles
/// the kernels: calls into the driver that take 7-25 s on a cold shader cache and cannot stop
/// at a tile). A signal there ends the process within a few hundredths of a second: nothing
/// has been written yet, so it prints the error (and with `--json` the error object) and lets
/// the signal's default action end the process, which skips exit handlers that could run
/// while the driver is still compiling on the main thread. Dropping the watch ends it; a
/// signal after that stops the render at its next tile as usual.
pub struct SetupWatch {
    done: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl SetupWatch {
    /// Starts watching `flag` (from [`interrupt_flag`]); `json` as the command's `--json`.
    pub fn start(flag: Arc<AtomicBool>, json: bool) -> SetupWatch {
        let done = Arc::new(AtomicBool::new(false));
        let watching = done.clone();
        let thread = std::thread::spawn(move || {
            while !watching.load(Ordering::SeqCst) {
                if flag.load(Ordering::SeqCst) {
                    end_in_setup(json);
                }
                std::thread::sleep(std::time::Duration::from_millis(20));
            }
        });
        SetupWatch { done, thread: Some(thread) }
    }
}

impl Drop for SetupWatch {
    fn drop(&mut self) {
        self.done.store(true, Ordering::SeqCst);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// Says that the render was interrupted while setting up and ends the process by the signal.
fn end_in_setup(json: bool) -> ! {
    let error = interrupted("while the render was setting up (building the BVH, compiling the kernels); nothing was written", false);
    eprintln!("error: {error:#}");
    if json {
        println!("{}", json_error(&format!("{error:#}"), Kind::of(&error)));
    }
    let signal = received_signal();
    let _ = signal_hook::low_level::emulate_default_handler(signal);
    // The default action of SIGINT, SIGTERM and SIGHUP ends the process; this is not reached.
    std::process::exit(i32::from(Kind::of(&error).exit_status()))
}

/// A flag that Ctrl-C (SIGINT), SIGTERM or (on Unix) SIGHUP sets, so the render stops at the
/// next tile and writes what it has; the signal is kept for the exit status ([`interrupted`]).
/// signal-hook's handlers only store to atomics, which is async-signal-safe.
pub fn interrupt_flag() -> anyhow::Result<Arc<AtomicBool>> {
    use anyhow::Context;
    use signal_hook::consts::{SIGINT, SIGTERM};
    let flag = FLAG.get_or_init(|| Arc::new(AtomicBool::new(false))).clone();
    let signal = SIGNAL.get_or_init(|| Arc::new(AtomicUsize::new(0))).clone();
    #[cfg(unix)]
    let signals = [SIGINT, SIGTERM, signal_hook::consts::SIGHUP];
    #[cfg(not(unix))]
    let signals = [SIGINT, SIGTERM];
    for number in signals {
        signal_hook::flag::register_usize(number, signal.clone(), number as usize).context("cannot install the interrupt handler")?;
        signal_hook::flag::register(number, flag.clone()).context("cannot install the interrupt handler")?;
    }
    Ok(flag)
}
