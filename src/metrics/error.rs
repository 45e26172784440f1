//! Why two images could not be compared.
use std::path::PathBuf;

use crate::image_io::{ImageIoError, RgbImage};

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

/// Checks what every metric needs: consistent data, equal sizes, at least one pixel.
pub(super) fn check_pair(test: &RgbImage, reference: &RgbImage) -> Result<(), MetricsError> {
    for (role, image) in [("test", test), ("reference", reference)] {
        let expected = (image.width as u64).checked_mul(image.height as u64).and_then(|n| n.checked_mul(3));
        if expected != Some(image.data.len() as u64) {
            return Err(MetricsError::BadData {
                role,
                len: image.data.len(),
                width: image.width,
                height: image.height,
            });
        }
    }
    if (test.width, test.height) != (reference.width, reference.height) {
        return Err(MetricsError::SizeMismatch {
            test: (test.width, test.height),
            reference: (reference.width, reference.height),
        });
    }
    if test.data.is_empty() {
        return Err(MetricsError::Empty { width: test.width, height: test.height });
    }
    Ok(())
}
