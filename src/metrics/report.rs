//! The comparison of two EXR files: what `wavetrace compare` prints as a table or JSON.
use std::fmt::Write;
use std::path::Path;

use super::{compare, CompareOptions, ErrorMetrics, MetricsError, DEFAULT_PPD};
use crate::image_io::read_exr;

/// Identifies the JSON layout of [`CompareReport`].
pub const SCHEMA: &str = "wavetrace-compare/1";

/// [`ErrorMetrics`] of a test EXR against a reference EXR, with what produced them.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CompareReport {
    /// `wavetrace-compare/1`.
    pub schema: &'static str,
    pub test: String,
    pub reference: String,
    pub width: u32,
    pub height: u32,
    /// The requested trim fraction (what was actually dropped is in `metrics`).
    pub trim: f64,
    /// Pixels per degree FLIP assumed; `None` when FLIP was not computed.
    pub flip_ppd: Option<f32>,
    pub metrics: ErrorMetrics,
}

impl CompareReport {
    /// Reads both EXRs (linear RGB) and compares them.
    ///
    /// # Errors
    /// `opts.trim` is outside [0, 1), a file cannot be read (the error says which role and names
    /// the file), the sizes differ (both files and sizes named), or [`compare`] fails.
    pub fn from_files(test: &Path, reference: &Path, opts: &CompareOptions) -> Result<Self, MetricsError> {
        // Before the (possibly slow) reads.
        if !(0.0..1.0).contains(&opts.trim) {
            return Err(MetricsError::InvalidTrim(opts.trim));
        }
        let (test_image, _) = read_exr(test).map_err(|error| MetricsError::Read { role: "test", error })?;
        let (reference_image, _) =
            read_exr(reference).map_err(|error| MetricsError::Read { role: "reference", error })?;
        let (test_size, reference_size) =
            ((test_image.width, test_image.height), (reference_image.width, reference_image.height));
        if test_size != reference_size {
            return Err(MetricsError::FileSizeMismatch {
                test: test.to_owned(),
                test_size,
                reference: reference.to_owned(),
                reference_size,
            });
        }
        let metrics = compare(&test_image, &reference_image, opts)?;
        Ok(Self {
            schema: SCHEMA,
            test: test.display().to_string(),
            reference: reference.display().to_string(),
            width: test_image.width,
            height: test_image.height,
            trim: opts.trim,
            flip_ppd: opts.flip.then_some(DEFAULT_PPD),
            metrics,
        })
    }

    /// A small human-readable table, one metric per line, ending in a newline.
    pub fn table(&self) -> String {
        let m = &self.metrics;
        let mut s = String::new();
        let _ = writeln!(s, "test       {}", self.test);
        let _ = writeln!(s, "reference  {}", self.reference);
        let _ = writeln!(
            s,
            "pixels     {}x{} = {}, {} non-finite (excluded)",
            self.width, self.height, m.pixels, m.non_finite_pixels
        );
        let trim = if m.trimmed_pixels > 0 {
            format!(
                "top {:.4}% ({} pixels) dropped per metric, FLIP untrimmed",
                100.0 * m.trimmed_fraction,
                m.trimmed_pixels
            )
        } else if self.trim > 0.0 {
            format!("none (--trim {} drops no pixel of {})", self.trim, m.pixels - m.non_finite_pixels)
        } else {
            "none".to_string()
        };
        let _ = writeln!(s, "trimming   {trim}");
        let _ = writeln!(s, "{:<8} {:>14}", "metric", "value");
        for (name, value) in
            [("MSE", m.mse), ("RMSE", m.rmse), ("relMSE", m.relmse), ("SMAPE", m.smape), ("MAPE", m.mape)]
        {
            let _ = writeln!(s, "{name:<8} {value:>14.6e}");
        }
        match (m.flip, self.flip_ppd) {
            (Some(flip), Some(ppd)) => {
                let _ =
                    writeln!(s, "{:<8} {flip:>14.6}  (LDR-FLIP, clamped to [0, 1], {ppd:.2} PPD)", "FLIP");
            }
            _ => {
                let _ = writeln!(s, "{:<8} {:>14}", "FLIP", "-");
            }
        }
        s
    }
}
