//! `wavetrace compare`: error metrics of a test EXR against a reference EXR.

use crate::metrics::{CompareOptions, CompareReport};
use anyhow::Result;
use std::path::PathBuf;

const EXAMPLES: &str = "\
Examples:
  wavetrace compare gpu.exr truth.exr
  wavetrace compare gpu.exr truth.exr --json > errors.json
  wavetrace compare gpu.exr truth.exr --trim 0.001     # drop the top 0.1% per-pixel errors
  wavetrace compare gpu.exr truth.exr --no-flip        # skip FLIP (faster on large images)

Metrics (per channel, averaged; pixels with NaN/Inf in either image are counted and excluded):
  MSE     mean((v-r)^2)                   RMSE  sqrt(MSE)
  relMSE  mean((v-r)^2 / (r+0.01)^2)      (pbrt-v4 imgtool diff's MRSE)
  SMAPE   mean(|v-r| / (|v|+|r|))         MAPE  mean(|v-r| / (|r|+0.01))
  FLIP    mean LDR-FLIP (NVIDIA) of the images clamped to [0, 1], 67.02 pixels per degree";

#[derive(clap::Args, Debug)]
#[command(after_help = EXAMPLES)]
pub struct CompareArgs {
    /// The image to judge (linear RGB EXR).
    pub test: PathBuf,
    /// The ground truth, e.g. a high-spp `--method cpu-f64` render (same size).
    pub reference: PathBuf,
    /// Print a JSON object (`"schema": "wavetrace-compare/1"`) instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Drop this fraction of the largest per-pixel errors from each metric (FLIP excepted),
    /// e.g. 0.001 for the top 0.1%.
    #[arg(long, default_value_t = 0.0, value_name = "F")]
    pub trim: f64,
    /// Skip FLIP.
    #[arg(long)]
    pub no_flip: bool,
}

pub fn run(a: CompareArgs) -> Result<()> {
    let opts = CompareOptions { trim: a.trim, flip: !a.no_flip };
    let report = CompareReport::from_files(&a.test, &a.reference, &opts)?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", report.table());
    }
    Ok(())
}
