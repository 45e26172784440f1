//! The pool: how many paths the wavefront keeps in flight (`--pool-size`). A count as given
//! (reduced to what the adapter holds), about a million by default (pbrt-v4's and Laine et al.'s
//! choice), or `device`: Cycles' rule for CUDA, max(SMs × threads per SM, 65536) × 16 path
//! states (its `PathTraceWorkGPU`), about 4.3 million on an H100 or H200, so that each SM has
//! many times the threads it can run at once queued, whatever the pass.

use super::super::buffers::human_bytes;
use super::super::context::GpuContext;
use super::path_state::{self, LARGEST_BINDING_PER_PATH};
use crate::gpu::state::{GpuMonitor, Multiprocessors};
use crate::options::{PoolSize, WavefrontOptions};
use anyhow::{bail, Result};

/// Default pool: about a million paths in flight (pbrt-v4's choice), less where limits say so.
pub const DEFAULT_POOL: u32 = 1 << 20;

/// Cycles' floor on the threads one wave of a pass should have, whatever the device.
const CYCLES_MIN_THREADS: u64 = 65_536;
/// Cycles' path states per thread the device can hold at once.
const CYCLES_STATES_PER_THREAD: u64 = 16;

/// The largest pool the adapter can hold: every per-path buffer within one storage binding,
/// and one thread per path within one dispatch.
pub fn max_pool(ctx: &GpuContext, workgroup_size: u32) -> u32 {
    let s = &ctx.summary;
    let by_binding =
        s.max_storage_buffer_binding_size.min(s.max_buffer_size) / LARGEST_BINDING_PER_PATH.max(16);
    let by_threads =
        s.max_compute_workgroups_per_dimension as u64 * workgroup_size.min(path_state::SCAN_WG as u32) as u64;
    by_binding.min(by_threads).min(u32::MAX as u64) as u32
}

/// Cycles' pool for a device with these multiprocessors.
pub fn cycles_pool(m: Multiprocessors) -> u64 {
    (m.count as u64 * m.threads_each as u64).max(CYCLES_MIN_THREADS) * CYCLES_STATES_PER_THREAD
}

/// The pool a render asks for, before the job's size caps it: see the module's text.
pub fn choose(ctx: &GpuContext, opts: &WavefrontOptions) -> Result<u32> {
    let max = max_pool(ctx, opts.workgroup_size);
    if max == 0 {
        bail!("{} cannot hold even one path's state in its storage bindings", ctx.summary.name);
    }
    let asked = match opts.pool_size {
        None => return Ok(DEFAULT_POOL.min(max)),
        Some(PoolSize::Paths(0)) => bail!("--pool-size must be at least 1"),
        Some(PoolSize::Paths(p)) => p as u64,
        Some(PoolSize::Device) => match GpuMonitor::open(&ctx.summary).and_then(|m| m.multiprocessors()) {
            Some(m) => {
                let pool = cycles_pool(m);
                log::info!(
                    "pool sized to the device: {} SMs × {} threads × {CYCLES_STATES_PER_THREAD} = {pool} paths",
                    m.count,
                    m.threads_each
                );
                pool
            }
            None => {
                eprintln!(
                    "notice: --pool-size device needs the SM count, which only NVIDIA's NVML gives; \
                     {} has none, so the default pool ({DEFAULT_POOL} paths) is used",
                    ctx.summary.name
                );
                DEFAULT_POOL as u64
            }
        },
    };
    if asked > max as u64 {
        eprintln!(
            "notice: pool of {asked} paths does not fit {} ({LARGEST_BINDING_PER_PATH} bytes per path in \
             its largest buffer, {} per binding); using {max}",
            ctx.summary.name,
            human_bytes(ctx.summary.max_storage_buffer_binding_size)
        );
        return Ok(max);
    }
    Ok(asked as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cycles_rule_gives_about_4_3_million_paths_on_hopper() {
        let h200 = Multiprocessors { count: 132, threads_each: 2048 };
        assert_eq!(cycles_pool(h200), 4_325_376);
        // A small device is held at the floor: 65536 threads' worth.
        assert_eq!(cycles_pool(Multiprocessors { count: 2, threads_each: 1024 }), 1_048_576);
    }
}
