//! The error metrics reports carry (`wavetrace::metrics::compare`: MSE, RMSE, relMSE, SMAPE,
//! MAPE, FLIP) and the FLIP error map, on two numpy images.

use numpy::PyReadonlyArray3;
use pyo3::prelude::*;
use wavetrace::metrics::{self, CompareOptions};

use crate::errors::{guarded, input};
use crate::image::from_numpy;
use numpy::PyArrayMethods;

/// The metrics of `test` against `reference` (float32 H×W×3 each) as JSON text, the
/// `ErrorMetrics` a run's `error` holds.
#[pyfunction]
#[pyo3(signature = (test, reference, trim = 0.0, flip = true))]
pub fn compare(
    py: Python<'_>,
    test: PyReadonlyArray3<'_, f32>,
    reference: PyReadonlyArray3<'_, f32>,
    trim: f64,
    flip: bool,
) -> PyResult<String> {
    let (t, r) = guarded(py, || Ok((from_numpy(&test, "test")?, from_numpy(&reference, "reference")?)))?;
    guarded(py, || {
        let m = metrics::compare(&t, &r, &CompareOptions { trim, flip }).map_err(|e| input(e.to_string()))?;
        serde_json::to_string(&m).map_err(|e| input(e.to_string()))
    })
}

/// The per-pixel LDR-FLIP error of `test` against `reference`, float32 H×W.
#[pyfunction]
pub fn flip_map<'py>(
    py: Python<'py>,
    test: PyReadonlyArray3<'_, f32>,
    reference: PyReadonlyArray3<'_, f32>,
) -> PyResult<Bound<'py, PyAny>> {
    let (t, r) = guarded(py, || Ok((from_numpy(&test, "test")?, from_numpy(&reference, "reference")?)))?;
    let map = guarded(py, || metrics::flip_map(&t, &r).map_err(|e| input(e.to_string())))?;
    let (h, w) = (t.height as usize, t.width as usize);
    Ok(numpy::PyArray1::from_vec(py, map).reshape([h, w])?.into_any())
}
