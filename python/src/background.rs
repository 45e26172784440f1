//! Long work (a render, an experiment) on a worker thread, the calling thread waiting with the
//! GIL released and looking at Python's signals every 50 ms. Ctrl-C asks the work to stop at its
//! next checkpoint (`wavetrace::cancel`: after a CPU row, a GPU submission), waits for that up to
//! [`SETTLE`], and raises `KeyboardInterrupt`, within a second. An experiment stopped so has the
//! report.json of the groups it finished, which `resume=True` continues.
//!
//! One piece of work runs at a time in a process ([`WORK`]): the device is one, timings of two at
//! once would mean nothing, and work abandoned by an interrupt that has not reached its
//! checkpoint yet must finish unwinding before the next starts (a resumed experiment must not
//! meet its predecessor still writing).

use std::collections::BTreeSet;
use std::sync::atomic::{AtomicU64, Ordering::SeqCst};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::Mutex;
use std::time::Duration;

use pyo3::prelude::*;
use wavetrace::cancel;

use crate::errors::Failure;

static WORK: Mutex<()> = Mutex::new(());
/// Each piece of work's number, from 1.
static NEXT: AtomicU64 = AtomicU64::new(1);
/// The number of the work running now (0: none).
static RUNNING: AtomicU64 = AtomicU64::new(0);
/// The numbers of work whose caller was interrupted.
static INTERRUPTED: Mutex<BTreeSet<u64>> = Mutex::new(BTreeSet::new());

/// How often the waiting thread looks at signals.
const POLL: Duration = Duration::from_millis(50);
/// How long an interrupt waits for the work to reach its checkpoint before raising anyway.
const SETTLE: Duration = Duration::from_millis(500);

enum Outcome<T> {
    Done(T),
    Failed(Failure),
    Cancelled,
}

/// Runs `work` on a worker thread and returns what it returns; see the module's docs.
pub fn run<T: Send + 'static>(
    py: Python<'_>,
    work: impl FnOnce() -> Result<T, Failure> + Send + 'static,
) -> PyResult<T> {
    let id = NEXT.fetch_add(1, SeqCst);
    let (tx, rx) = mpsc::channel();
    std::thread::Builder::new()
        .name("wavetrace".into())
        .spawn(move || {
            let _one = WORK.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
            cancel::clear();
            RUNNING.store(id, SeqCst);
            let outcome = if interrupted().contains(&id) {
                Outcome::Cancelled
            } else {
                match std::panic::catch_unwind(std::panic::AssertUnwindSafe(work)) {
                    Ok(Ok(v)) => Outcome::Done(v),
                    Ok(Err(f)) => Outcome::Failed(f),
                    Err(p) if cancel::is_cancelled(p.as_ref()) => Outcome::Cancelled,
                    Err(p) => Outcome::Failed(Failure::panic(p.as_ref())),
                }
            };
            RUNNING.store(0, SeqCst);
            cancel::clear();
            interrupted().remove(&id);
            // The caller may have stopped waiting (an interrupt): nothing to tell then.
            let _ = tx.send(outcome);
        })
        .map_err(|e| Failure::Failed(format!("starting a worker thread: {e}")).into_pyerr(py))?;
    let mut rx = rx;
    loop {
        let (back, got) = py.detach(move || {
            let got = rx.recv_timeout(POLL);
            (rx, got)
        });
        rx = back;
        match got {
            Ok(Outcome::Done(v)) => return Ok(v),
            Ok(Outcome::Failed(f)) => return Err(f.into_pyerr(py)),
            // (Only after this thread's interrupt, which returns below.)
            Ok(Outcome::Cancelled) => {
                return Err(pyo3::exceptions::PyKeyboardInterrupt::new_err(
                    "wavetrace: the work was interrupted",
                ))
            }
            Err(RecvTimeoutError::Timeout) => {
                if let Err(signal) = py.check_signals() {
                    interrupted().insert(id);
                    if RUNNING.load(SeqCst) == id {
                        cancel::request();
                    }
                    py.detach(move || {
                        let _ = rx.recv_timeout(SETTLE);
                    });
                    return Err(signal);
                }
            }
            Err(RecvTimeoutError::Disconnected) => {
                return Err(Failure::Panic("the worker thread ended without an answer".into()).into_pyerr(py))
            }
        }
    }
}

fn interrupted() -> std::sync::MutexGuard<'static, BTreeSet<u64>> {
    INTERRUPTED.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// `_panic(message)`: panics inside the worker, for the test that no panic reaches Python as one.
#[pyfunction]
#[pyo3(name = "_panic")]
pub fn panic_for_tests(py: Python<'_>, message: String) -> PyResult<()> {
    run(py, move || -> Result<(), Failure> { panic!("{message}") })
}
