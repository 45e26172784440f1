//! Errors in what a user wrote — a scene file, an OBJ mesh, an experiment config, a `--scene`
//! argument: each names the file, the JSON path (or line) and the reason.
use std::fmt;

#[derive(Debug, Clone, PartialEq)]
pub struct InputError {
    /// The file, or `<built-in NAME>` / `<string>` / the command-line argument.
    pub file: String,
    /// JSON path of the offending value, e.g. `objects[3].radius` or `runs.spp`; empty for
    /// whole-file errors.
    pub path: String,
    pub reason: String,
}

impl InputError {
    pub fn new(file: impl Into<String>, path: impl Into<String>, reason: impl Into<String>) -> Self {
        Self { file: file.into(), path: path.into(), reason: reason.into() }
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.path.is_empty() {
            write!(f, "{}: {}", self.file, self.reason)
        } else {
            write!(f, "{}: {}: {}", self.file, self.path, self.reason)
        }
    }
}

impl std::error::Error for InputError {}
