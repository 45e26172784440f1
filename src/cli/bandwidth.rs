//! `wavetrace bandwidth`: what this GPU's memory delivers to a streaming pass (issue 44).

use anyhow::{bail, Result};

use super::measurement::Measurement;
use crate::measure::bandwidth;

const EXAMPLES: &str = "\
Examples:
  wavetrace bandwidth                                # 256 MiB buffers (less where bindings are smaller), 9 repetitions
  wavetrace bandwidth --mib 64 --json bandwidth.json
  wavetrace bandwidth --adapter nvidia --repetitions 21";

/// Times a streaming copy and a streaming read of 16-byte elements in compute passes, and a
/// buffer-to-buffer copy: GB/s from timestamps (and over the host's round trip), the bandwidth
/// the wavefront's path-state traffic is compared with.
#[derive(clap::Args, Debug)]
#[command(after_help = EXAMPLES)]
pub struct BandwidthArgs {
    /// MiB in each buffer (source and destination); the default is 256, or the adapter's largest
    /// storage binding where that is smaller.
    #[arg(long)]
    pub mib: Option<u64>,
    /// Timed repetitions per way (after one untimed round; the ways take turns).
    #[arg(long, default_value_t = 9)]
    pub repetitions: u32,
    #[command(flatten)]
    pub measurement: Measurement,
}

pub fn run(a: BandwidthArgs) -> Result<()> {
    let ctx = a.measurement.context()?;
    let largest = ctx.summary.max_storage_buffer_binding_size.min(ctx.summary.max_buffer_size) >> 20;
    let report = bandwidth::measure(&ctx, a.mib.unwrap_or(largest.min(256)), a.repetitions)?;
    a.measurement.publish(&report.table(), &report)?;
    if !report.copy_ok {
        bail!("the copy's destination does not hold its source on this adapter");
    }
    Ok(())
}
