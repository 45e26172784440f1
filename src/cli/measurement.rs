//! The arguments the measuring commands share (`bandwidth`, `dispatch-cost`, `intersect-cost`):
//! the adapter they measure and where their JSON goes.

use crate::gpu::GpuContext;
use anyhow::Result;
use std::path::PathBuf;

#[derive(clap::Args, Debug, Clone)]
pub struct Measurement {
    /// Also write the measurements as JSON (its schema named in its `schema` field).
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Use the adapter whose name contains this (case-insensitive); see `wavetrace info`.
    #[arg(long)]
    pub adapter: Option<String>,
}

impl Measurement {
    /// The adapter to measure.
    pub fn context(&self) -> Result<GpuContext> {
        GpuContext::new(self.adapter.as_deref())
    }

    /// Prints the measurement's `table` and writes `report` where `--json` says.
    pub fn publish(&self, table: &str, report: &impl serde::Serialize) -> Result<()> {
        print!("{table}");
        match &self.json {
            Some(path) => super::write_json(path, report),
            None => Ok(()),
        }
    }
}
