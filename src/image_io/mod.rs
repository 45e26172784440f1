//! Image files: linear HDR RGB images in memory, OpenEXR for the data, 8-bit sRGB PNG for
//! previews. Every write is atomic (temporary file + rename), so a crash mid-write never leaves
//! a truncated image where a finished one is expected.
mod atomic_file;
mod error;
mod exr;
mod png;
mod rgb_image;

pub use self::atomic_file::write_file_atomically;
pub use self::error::ImageIoError;
pub use self::exr::{read_exr, write_exr};
pub use self::png::{
    decode_png_rgb8, encode_png_rgb8, linear_to_srgb8, read_png_rgb8, write_png, write_png_rgb8,
};
pub use self::rgb_image::RgbImage;
