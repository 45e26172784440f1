//! The GPU methods on wgpu, and the plumbing they share.

pub mod accumulate;
pub mod buffers;
pub mod context;
pub mod dispatch_plan;
pub mod megakernel;
pub mod scene_buffers;
pub mod shaders;
pub mod timing;

/// One static label per GPU pass: the same string names the pipeline, the WGSL entry point,
/// the timestamp slot, the row of the timing table and the key in JSON reports.
pub mod label {
    pub const MEGAKERNEL: &str = "megakernel";
    pub const ACCUMULATE: &str = "accumulate";
}

pub use context::GpuContext;
