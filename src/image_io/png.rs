//! 8-bit sRGB PNG previews of linear images.
use std::path::Path;

use image::{codecs::png::PngEncoder, ExtendedColorType, ImageEncoder};

use super::{atomic_file::write_atomically, ImageIoError, RgbImage};

/// Writes an 8-bit sRGB preview of the linear `image`, atomically; see [`linear_to_srgb8`].
pub fn write_png(path: impl AsRef<Path>, image: &RgbImage) -> Result<(), ImageIoError> {
    let path = path.as_ref();
    image.check_writable(path)?;
    let bytes: Vec<u8> = image.data.iter().map(|&v| linear_to_srgb8(v)).collect();
    write_atomically(path, |file| {
        PngEncoder::new(file)
            .write_image(&bytes, image.width, image.height, ExtendedColorType::Rgb8)
            .map_err(|error| ImageIoError::Png { path: path.to_owned(), error })
    })
}

/// Writes 8-bit RGB bytes as they are (false-colour maps, thumbnails), atomically.
pub fn write_png_rgb8(
    path: impl AsRef<Path>,
    width: u32,
    height: u32,
    rgb: &[u8],
) -> Result<(), ImageIoError> {
    let path = path.as_ref();
    write_atomically(path, |file| {
        PngEncoder::new(file)
            .write_image(rgb, width, height, ExtendedColorType::Rgb8)
            .map_err(|error| ImageIoError::Png { path: path.to_owned(), error })
    })
}

/// 8-bit RGB bytes as PNG in memory (for `data:` URIs in HTML reports).
pub fn encode_png_rgb8(width: u32, height: u32, rgb: &[u8]) -> Result<Vec<u8>, image::ImageError> {
    let mut out = Vec::new();
    PngEncoder::new(&mut out).write_image(rgb, width, height, ExtendedColorType::Rgb8)?;
    Ok(out)
}

/// The sRGB transfer function (the piecewise IEC 61966-2-1 curve, not a pure 2.2 gamma),
/// clamped to [0, 1] and rounded to the nearest 8-bit code. NaN maps to 0.
pub fn linear_to_srgb8(linear: f32) -> u8 {
    // f64 so that values near a code boundary round the same way as a reference would.
    let v = f64::from(linear);
    let encoded = if v <= 0.003_130_8 { 12.92 * v } else { 1.055 * v.powf(1.0 / 2.4) - 0.055 };
    if encoded.is_nan() {
        0
    } else {
        (encoded.clamp(0.0, 1.0) * 255.0).round() as u8
    }
}
