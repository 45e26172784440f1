//! Why two images could not be compared.
use std::path::PathBuf;

use crate::image_io::ImageIoError;

/// Why a comparison failed. `Display` is self-contained (sizes, counts and files included).
#[derive(Debug, thiserror::Error)]
pub enum MetricsError {
    /// The images have different sizes.
    #[error("image sizes differ: test is {}x{}, reference is {}x{}", test.0, test.1, reference.0, reference.1)]
    SizeMismatch { test: (u32, u32), reference: (u32, u32) },
    /// The same, for two files.
    #[error(
        "image sizes differ: test {} is {}x{}, reference {} is {}x{}",
        test.display(), test_size.0, test_size.1, reference.display(), reference_size.0, reference_size.1
    )]
    FileSizeMismatch { test: PathBuf, test_size: (u32, u32), reference: PathBuf, reference_size: (u32, u32) },
    /// An image file could not be read; `role` is `test` or `reference`. (`error` is part of the
    /// message, not a `source()`, so that error chains do not print it twice.)
    #[error("cannot read the {role} image: {error}")]
    Read { role: &'static str, error: ImageIoError },
    /// `RgbImage::data` does not hold `3 * width * height` values.
    #[error("{role} image data has {len} values, a {width}x{height} RGB image needs {}", 3 * *width as u64 * *height as u64)]
    BadData { role: &'static str, len: usize, width: u32, height: u32 },
    /// Zero pixels: every mean would be 0/0.
    #[error("images are empty ({width}x{height})")]
    Empty { width: u32, height: u32 },
    /// Every pixel is NaN or infinite in the test or the reference image.
    #[error("all {pixels} pixels are non-finite (NaN or Inf) in the test or the reference image")]
    NoFinitePixels { pixels: u64 },
    /// `CompareOptions::trim` outside [0, 1).
    #[error("trim must be a fraction in [0, 1), got {0}")]
    InvalidTrim(f64),
}
