//! `wavetrace info`: what GPUs wgpu sees and which one a render would use.

use crate::gpu::buffers::human_bytes;
use crate::gpu::context::{choose, enumerate, AdapterSummary, NO_ADAPTER_HELP};

#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  wavetrace info\n  WGPU_BACKEND=vulkan wavetrace info --adapter llvmpipe"
)]
pub struct InfoArgs {
    /// Prefer the adapter whose name contains this (case-insensitive).
    #[arg(long)]
    pub adapter: Option<String>,
}

pub fn run(args: InfoArgs) -> anyhow::Result<()> {
    print!("{}", text(args.adapter.as_deref())?);
    Ok(())
}

/// What `wavetrace info` prints, with `adapter` as its `--adapter` (the Python package's
/// `wavetrace.info()` returns it).
pub fn text(adapter: Option<&str>) -> anyhow::Result<String> {
    use std::fmt::Write as _;
    let mut out = String::new();
    let (_instance, adapters) = enumerate();
    if adapters.is_empty() {
        anyhow::bail!("{NO_ADAPTER_HELP}");
    }
    writeln!(out, "adapters found: {}", adapters.len())?;
    for (i, a) in adapters.iter().enumerate() {
        let s = AdapterSummary::of(a);
        writeln!(
            out,
            "  [{i}] {} ({}, {}), driver {} {}",
            s.name, s.backend, s.device_type, s.driver, s.driver_info
        )?;
    }
    let (chosen, why) = choose(&adapters, adapter)?;
    let s = AdapterSummary::of(&adapters[chosen]);
    writeln!(out, "chosen: [{chosen}] {}: {why}", s.name)?;
    if s.is_software() {
        writeln!(out, "  note: a software adapter; GPU timings measure the CPU it runs on")?;
    }
    let info = adapters[chosen].get_info();
    writeln!(out, "  device type:               {}", s.device_type)?;
    writeln!(out, "  vendor:                    {:#06x} ({})", info.vendor, vendor_name(info.vendor))?;
    writeln!(out, "  backend:                   {}", s.backend)?;
    writeln!(out, "  driver:                    {} {}", s.driver, s.driver_info)?;
    writeln!(
        out,
        "  timestamp queries:         {}",
        if s.timestamps { "yes" } else { "no (wall-clock timing)" }
    )?;
    if s.subgroups {
        writeln!(
            out,
            "  subgroups:                 yes, size {}..={}",
            s.subgroup_min_size, s.subgroup_max_size
        )?;
    } else {
        writeln!(out, "  subgroups:                 no")?;
    }
    writeln!(out, "  max storage binding:       {}", human_bytes(s.max_storage_buffer_binding_size))?;
    writeln!(out, "  max buffer size:           {}", human_bytes(s.max_buffer_size))?;
    writeln!(out, "  max workgroups per dim:    {}", s.max_compute_workgroups_per_dimension)?;
    writeln!(out, "  max invocations per group: {}", s.max_compute_invocations_per_workgroup)?;
    Ok(out)
}

/// The PCI vendor IDs of the GPU vendors a researcher is likely to meet.
fn vendor_name(id: u32) -> &'static str {
    match id {
        0x10de => "NVIDIA",
        0x1002 | 0x1022 => "AMD",
        0x8086 => "Intel",
        0x106b => "Apple",
        0x13b5 => "Arm",
        0x5143 => "Qualcomm",
        0x10005 => "Mesa (software)",
        _ => "unknown",
    }
}
