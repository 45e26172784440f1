//! Images between the library (`RgbImage`: interleaved f32 RGB, top row first) and numpy
//! (float32, height × width × 3): the same layout, so the library's vector becomes the array's
//! buffer without a copy.

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::prelude::*;
use wavetrace::image_io::{read_exr as read_exr_file, RgbImage};

use crate::errors::{guarded, input, Failure};

/// The image as an H×W×3 float32 array owning its data.
pub fn to_numpy(py: Python<'_>, image: RgbImage) -> PyResult<Bound<'_, PyAny>> {
    let shape = [image.height as usize, image.width as usize, 3];
    Ok(PyArray1::from_vec(py, image.data).reshape(shape)?.into_any())
}

/// An H×W×3 float32 array as an image (copied: the library keeps its own vector).
pub fn from_numpy(a: &PyReadonlyArray3<'_, f32>, what: &str) -> Result<RgbImage, Failure> {
    let shape = a.shape();
    if shape[2] != 3 {
        return Err(input(format!("{what}: expected an array of shape (height, width, 3), got {shape:?}")));
    }
    let data: Vec<f32> = a.as_array().iter().copied().collect();
    RgbImage::from_data(shape[1] as u32, shape[0] as u32, data)
        .ok_or_else(|| input(format!("{what}: an array of shape {shape:?} is not an image")))
}

/// read_exr(path) -> numpy.ndarray: an EXR the library wrote (or any RGB EXR), as float32 H×W×3.
#[pyfunction]
pub fn read_exr<'py>(py: Python<'py>, path: std::path::PathBuf) -> PyResult<Bound<'py, PyAny>> {
    let image =
        guarded(py, || read_exr_file(&path).map(|(image, _)| image).map_err(|e| input(e.to_string())))?;
    to_numpy(py, image)
}
