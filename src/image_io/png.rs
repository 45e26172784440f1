//! 8-bit sRGB PNG previews of linear images.
use std::{
    io::{BufReader, Write},
    path::Path,
};

use super::{atomic_file::write_atomically, ImageIoError, RgbImage};

/// Writes an 8-bit sRGB preview of the linear `image`, atomically; see [`linear_to_srgb8`].
pub fn write_png(path: impl AsRef<Path>, image: &RgbImage) -> Result<(), ImageIoError> {
    let path = path.as_ref();
    image.check_writable(path)?;
    let bytes: Vec<u8> = image.data.iter().map(|&v| linear_to_srgb8(v)).collect();
    write_atomically(path, |file| {
        encode_rgb8(file, image.width, image.height, &bytes)
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
        encode_rgb8(file, width, height, rgb)
            .map_err(|error| ImageIoError::Png { path: path.to_owned(), error })
    })
}

/// 8-bit RGB bytes as PNG in memory (for `data:` URIs in HTML reports).
pub fn encode_png_rgb8(width: u32, height: u32, rgb: &[u8]) -> Result<Vec<u8>, ::png::EncodingError> {
    let mut out = Vec::new();
    encode_rgb8(&mut out, width, height, rgb)?;
    Ok(out)
}

fn encode_rgb8(out: impl Write, width: u32, height: u32, rgb: &[u8]) -> Result<(), ::png::EncodingError> {
    let mut encoder = ::png::Encoder::new(out, width, height);
    encoder.set_color(::png::ColorType::Rgb);
    encoder.set_depth(::png::BitDepth::Eight);
    let mut writer = encoder.write_header()?;
    writer.write_image_data(rgb)?;
    writer.finish()
}

/// Reads a PNG of any colour type as 8-bit RGB: width, height and the bytes, row by row (alpha
/// dropped, grey repeated, 16-bit samples cut to their high byte, palettes expanded).
pub fn read_png_rgb8(path: impl AsRef<Path>) -> Result<(u32, u32, Vec<u8>), ImageIoError> {
    let path = path.as_ref();
    let fail = |reason: String| ImageIoError::PngRead { path: path.to_owned(), reason };
    let file = std::fs::File::open(path).map_err(|e| fail(e.to_string()))?;
    decode_rgb8(BufReader::new(file)).map_err(fail)
}

/// [`read_png_rgb8`] for a PNG already in memory (an image embedded in a glTF file).
pub fn decode_png_rgb8(bytes: &[u8]) -> Result<(u32, u32, Vec<u8>), String> {
    decode_rgb8(std::io::Cursor::new(bytes))
}

fn decode_rgb8(input: impl std::io::BufRead + std::io::Seek) -> Result<(u32, u32, Vec<u8>), String> {
    let mut decoder = ::png::Decoder::new(input);
    decoder.set_transformations(::png::Transformations::EXPAND | ::png::Transformations::STRIP_16);
    let mut reader = decoder.read_info().map_err(|e| e.to_string())?;
    let size = reader.output_buffer_size().ok_or("image too large")?;
    let mut buf = vec![0; size];
    let info = reader.next_frame(&mut buf).map_err(|e| e.to_string())?;
    let channels = match info.color_type {
        ::png::ColorType::Grayscale => 1,
        ::png::ColorType::GrayscaleAlpha => 2,
        ::png::ColorType::Rgb => 3,
        ::png::ColorType::Rgba => 4,
        ::png::ColorType::Indexed => return Err("palette not expanded".into()),
    };
    let (w, h) = (info.width as usize, info.height as usize);
    let mut rgb = Vec::with_capacity(w * h * 3);
    for row in buf.chunks(info.line_size).take(h) {
        for px in row[..w * channels].chunks(channels) {
            match channels {
                1 | 2 => rgb.extend_from_slice(&[px[0]; 3]),
                _ => rgb.extend_from_slice(&px[..3]),
            }
        }
    }
    Ok((info.width, info.height, rgb))
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
