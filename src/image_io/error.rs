//! Errors from reading and writing image files; each names the file.
use std::path::{Path, PathBuf};

/// Why an image file could not be read or written. `Display` is self-contained: it names the
/// file and includes the underlying cause.
#[derive(Debug, thiserror::Error)]
pub enum ImageIoError {
    /// The file (or its temporary sibling) could not be opened, created, written or renamed.
    #[error("{}: {action}: {error}", path.display())]
    Io {
        path: PathBuf,
        /// What was being done, e.g. `cannot open`.
        action: &'static str,
        error: std::io::Error,
    },
    /// The file is not a readable OpenEXR file, or the `exr` crate refused to write it.
    #[error("{}: {action}: {error}", path.display())]
    Exr {
        path: PathBuf,
        /// `cannot read as OpenEXR` or `cannot write OpenEXR`.
        action: &'static str,
        error: ::exr::error::Error,
    },
    /// The PNG encoder failed.
    #[error("{}: cannot write PNG: {error}", path.display())]
    Png { path: PathBuf, error: ::png::EncodingError },
    /// The file is not a readable PNG.
    #[error("{}: cannot read as PNG: {reason}", path.display())]
    PngRead { path: PathBuf, reason: String },
    /// The file or the arguments are well-formed but unusable here, e.g. an EXR without RGB
    /// channels, an empty image or a duplicate attribute name.
    #[error("{}: {reason}", path.display())]
    Unsupported { path: PathBuf, reason: String },
}

impl ImageIoError {
    /// The file this error is about.
    pub fn path(&self) -> &Path {
        match self {
            Self::Io { path, .. }
            | Self::Exr { path, .. }
            | Self::Png { path, .. }
            | Self::PngRead { path, .. }
            | Self::Unsupported { path, .. } => path,
        }
    }

    pub(crate) fn io(path: &Path, action: &'static str, error: std::io::Error) -> Self {
        Self::Io { path: path.to_owned(), action, error }
    }

    pub(crate) fn unsupported(path: &Path, reason: impl Into<String>) -> Self {
        Self::Unsupported { path: path.to_owned(), reason: reason.into() }
    }
}
