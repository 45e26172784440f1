//! `wavetrace dispatch-cost`: what one dispatch costs on this GPU, by itself (issue 42).

use anyhow::{bail, Result};

use super::measurement::Measurement;
use crate::measure::dispatch_cost;

const EXAMPLES: &str = "\
Examples:
  wavetrace dispatch-cost                                 # 1000 dispatches, 9 repetitions
  wavetrace dispatch-cost --dispatches 3232 --json cost.json   # a regenerate + tail frame's count
  wavetrace dispatch-cost --adapter nvidia --repetitions 21";

/// Times a chain of tiny dispatches recorded six ways (one compute pass each or all in one,
/// direct or indirect, the chain's buffer read-write or read-only): GPU time per dispatch from
/// timestamps around the chain, and the host's recording and submission time.
#[derive(clap::Args, Debug)]
#[command(after_help = EXAMPLES)]
pub struct DispatchCostArgs {
    /// Dispatches in each chain.
    #[arg(long, default_value_t = 1000)]
    pub dispatches: u32,
    /// Timed chains per variant (after one untimed round; the variants take turns).
    #[arg(long, default_value_t = 9)]
    pub repetitions: u32,
    #[command(flatten)]
    pub measurement: Measurement,
}

pub fn run(a: DispatchCostArgs) -> Result<()> {
    let ctx = a.measurement.context()?;
    let report = dispatch_cost::measure(&ctx, a.dispatches, a.repetitions)?;
    a.measurement.publish(&report.table(), &report)?;
    if report.variants.iter().any(|v| !v.counter_ok) {
        bail!("the read-write chain's counter is wrong: dispatches were lost or reordered on this adapter");
    }
    Ok(())
}
