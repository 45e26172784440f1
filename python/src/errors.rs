//! Errors as Python exceptions: the classes live in `wavetrace.errors` (Python can give a class
//! two bases, `InputError(WavetraceError, ValueError)`); the text is the command line's
//! (`error: {e:#}` less the prefix).

use pyo3::prelude::*;
use wavetrace::input_error::InputError;
use wavetrace::metrics::MetricsError;
use wavetrace::options::OptionError;

/// Why a call failed, before it becomes a Python exception.
#[derive(Debug)]
pub enum Failure {
    /// Bad input (a value, a file, a config): `wavetrace.InputError`, a `ValueError`.
    Input(String),
    /// An option name `render` does not take: `wavetrace.UnknownOptionError`, a `TypeError` too.
    UnknownOption(String),
    /// Anything else that stopped the work (no adapter, a GPU error, a file not written):
    /// `wavetrace.RenderError`, a `RuntimeError`.
    Failed(String),
    /// A panic inside the library (a bug): `wavetrace.WavetraceError`, never the panic itself.
    Panic(String),
}

impl Failure {
    /// Input or not, by what the error chain holds.
    pub fn of(e: anyhow::Error) -> Self {
        let input =
            e.chain().any(|c| c.is::<InputError>() || c.is::<OptionError>() || c.is::<MetricsError>());
        let text = format!("{e:#}");
        if input {
            Failure::Input(text)
        } else {
            Failure::Failed(text)
        }
    }

    /// The text a panic carried.
    pub fn panic(payload: &(dyn std::any::Any + Send)) -> Self {
        let msg = payload
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_default();
        Failure::Panic(format!("internal error (panic): {msg}"))
    }

    pub fn into_pyerr(self, py: Python<'_>) -> PyErr {
        let (class, text) = match self {
            Failure::Input(t) => ("InputError", t),
            Failure::UnknownOption(t) => ("UnknownOptionError", t),
            Failure::Failed(t) => ("RenderError", t),
            Failure::Panic(t) => ("WavetraceError", t),
        };
        match py.import("wavetrace.errors").and_then(|m| m.getattr(class)) {
            Ok(cls) => PyErr::from_type(cls.cast_into().expect("an exception class"), text),
            Err(e) => e,
        }
    }
}

pub fn input(text: impl Into<String>) -> Failure {
    Failure::Input(text.into())
}

/// Runs `f` on this thread (quick work: loading a scene, reading a file), a panic made a
/// [`Failure::Panic`].
pub fn guarded<T>(py: Python<'_>, f: impl FnOnce() -> Result<T, Failure>) -> PyResult<T> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(Ok(v)) => Ok(v),
        Ok(Err(failure)) => Err(failure.into_pyerr(py)),
        Err(payload) => Err(Failure::panic(payload.as_ref()).into_pyerr(py)),
    }
}
