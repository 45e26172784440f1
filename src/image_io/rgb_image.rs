//! A linear HDR RGB image in memory.
use std::path::Path;

use super::ImageIoError;

/// A linear-light RGB image: interleaved `f32` triples, row-major, top row first.
///
/// The fields are public for cheap access (e.g. uploading `data` to the GPU); keep
/// `data.len() == 3 * width * height`. The writers check it and return an error otherwise.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RgbImage {
    pub width: u32,
    pub height: u32,
    /// R, G, B of pixel (0, 0), then (1, 0), ... then (0, 1), ...
    pub data: Vec<f32>,
}

impl RgbImage {
    /// A black image.
    ///
    /// # Panics
    /// If `3 * width * height` overflows `usize`.
    pub fn new(width: u32, height: u32) -> Self {
        let len = value_count(width, height).expect("image size overflows usize");
        Self { width, height, data: vec![0.0; len] }
    }

    /// Wraps existing interleaved RGB data; `None` unless `data.len() == 3 * width * height`.
    pub fn from_data(width: u32, height: u32, data: Vec<f32>) -> Option<Self> {
        (value_count(width, height) == Some(data.len())).then_some(Self { width, height, data })
    }

    /// # Panics
    /// If `(x, y)` lies outside the image.
    pub fn get(&self, x: u32, y: u32) -> [f32; 3] {
        let i = self.index(x, y);
        [self.data[i], self.data[i + 1], self.data[i + 2]]
    }

    /// # Panics
    /// If `(x, y)` lies outside the image.
    pub fn set(&mut self, x: u32, y: u32, rgb: [f32; 3]) {
        let i = self.index(x, y);
        self.data[i..i + 3].copy_from_slice(&rgb);
    }

    /// Per-channel mean, accumulated in `f64`. NaN if any sample is NaN or the image is empty,
    /// so that a broken render cannot pass for a converged one.
    pub fn mean(&self) -> [f64; 3] {
        let mut sum = [0.0f64; 3];
        for pixel in self.data.chunks_exact(3) {
            for (s, &v) in sum.iter_mut().zip(pixel) {
                *s += f64::from(v);
            }
        }
        let n = (self.data.len() / 3) as f64;
        sum.map(|s| s / n)
    }

    fn index(&self, x: u32, y: u32) -> usize {
        // Without this check an x past the row end would silently alias the next row.
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside {}x{} image",
            self.width,
            self.height
        );
        3 * (y as usize * self.width as usize + x as usize)
    }

    /// Checks what every file format needs: a non-empty image whose data matches its size.
    pub(crate) fn check_writable(&self, path: &Path) -> Result<(), ImageIoError> {
        if self.width == 0 || self.height == 0 {
            return Err(ImageIoError::unsupported(
                path,
                format!("cannot write an empty {}x{} image", self.width, self.height),
            ));
        }
        if value_count(self.width, self.height) != Some(self.data.len()) {
            return Err(ImageIoError::unsupported(
                path,
                format!(
                    "image data has {} values, a {}x{} RGB image needs 3 * {} * {}",
                    self.data.len(),
                    self.width,
                    self.height,
                    self.width,
                    self.height
                ),
            ));
        }
        Ok(())
    }
}

fn value_count(width: u32, height: u32) -> Option<usize> {
    (width as usize).checked_mul(height as usize)?.checked_mul(3)
}
