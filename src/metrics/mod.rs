//! Image error metrics: how far a test render is from a reference.
//!
//! - [`compare`]: MSE, RMSE, relMSE, SMAPE, MAPE (names and definitions as in pbrt-v4's
//!   `imgtool diff` and DESIGN.md §4) and optionally mean LDR-FLIP, in one [`ErrorMetrics`].
//! - [`flip_map`] / [`mean_flip`]: NVIDIA's perceptual metric (Andersson et al. 2020) on our
//!   linear HDR images clamped to [0, 1]; validated against the official `flip-evaluator`.
//! - [`CompareReport`]: the same for two EXR files, with the errors that name them; what
//!   `wavetrace compare` prints.
//!
//! Pixels where either image has a NaN or infinite channel are counted
//! ([`ErrorMetrics::non_finite_pixels`]) and left out of every mean, so a metric is never NaN.

mod error;
mod error_metrics;
mod flip;
mod report;

pub use self::error::MetricsError;
pub use self::error_metrics::{compare, CompareOptions, ErrorMetrics, RELATIVE_EPSILON};
pub use self::flip::{flip_map, flip_map_with_ppd, mean_flip, pixels_per_degree, DEFAULT_PPD};
pub use self::report::{CompareReport, SCHEMA as COMPARE_SCHEMA};
