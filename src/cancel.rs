//! Stopping long work from outside the thread that does it: the Python package's Ctrl-C (issue
//! 60). Renders report progress at safe points (after each CPU row, after each GPU submission);
//! callers that can be interrupted call [`checkpoint`] there, which unwinds the render with a
//! [`Cancelled`] payload once [`request`] has been called. Unwinding, not an error value, because
//! the progress callbacks return nothing: threading a `Result` through every renderer's loop would
//! touch each of them for a hook only one caller uses. The command line never requests it.

use std::any::Any;
use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// The payload a cancelled render unwinds with (raised by [`std::panic::resume_unwind`], so no
/// panic hook runs and nothing is printed).
#[derive(Debug)]
pub struct Cancelled;

/// Asks the work in progress to stop at its next [`checkpoint`].
pub fn request() {
    REQUESTED.store(true, Ordering::SeqCst);
}

/// Withdraws a request: the next work runs to its end unless asked again.
pub fn clear() {
    REQUESTED.store(false, Ordering::SeqCst);
}

/// Whether a stop has been requested.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::SeqCst)
}

/// Unwinds with [`Cancelled`] when a stop has been requested; call only where unwinding leaves
/// nothing half-written (between submissions, between runs).
pub fn checkpoint() {
    if requested() {
        std::panic::resume_unwind(Box::new(Cancelled));
    }
}

/// Whether an unwind's payload is a [`Cancelled`] (catchers of panics pass it on).
pub fn is_cancelled(payload: &(dyn Any + Send)) -> bool {
    payload.is::<Cancelled>()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The flag is process-wide: one test drives it through a whole cycle.
    #[test]
    fn a_request_unwinds_the_next_checkpoint_with_cancelled() {
        clear();
        checkpoint();
        request();
        let unwound = std::panic::catch_unwind(checkpoint).unwrap_err();
        assert!(is_cancelled(unwound.as_ref()));
        clear();
        assert!(std::panic::catch_unwind(checkpoint).is_ok());
        let other = std::panic::catch_unwind(|| std::panic::resume_unwind(Box::new(3u8))).unwrap_err();
        assert!(!is_cancelled(other.as_ref()));
    }
}
