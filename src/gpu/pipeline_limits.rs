//! Adapter limits a pipeline must fit, checked before wgpu creates it, so that a pipeline that
//! cannot fit is refused with the limit, the need and the knob to change instead of a wgpu
//! validation error: the storage buffers it binds (the scene's group 0 declares 13, among them
//! the primitives and BVH nodes split over up to four bindings each, `scene_split.rs`) against
//! `max_storage_buffers_per_shader_stage`, and the workgroup memory of `--stack workgroup`'s
//! short stacks (`shaders/shared/bvh_stack.wgsl`) against `max_compute_workgroup_storage_size`.

use super::context::AdapterSummary;
use anyhow::{bail, Result};

/// Entries of one thread's short stack in workgroup memory: `SHORT_STACK` in
/// `shaders/shared/bvh_stack.wgsl` (a test holds the two equal).
pub const SHORT_STACK: u64 = 8;
/// The short stack's arrays (node or group base, and hit mask), 4 bytes an entry each.
const SHORT_STACK_ARRAYS: u64 = 2;

/// Bytes of workgroup memory the short stacks take in a pipeline with these constants: none
/// unless `BVH_STACK_WORKGROUP` is 1, then entries × arrays × 4 bytes × `WORKGROUP_SIZE`.
pub fn short_stack_bytes(constants: &[(&str, f64)]) -> u64 {
    let get = |name: &str| constants.iter().find(|c| c.0 == name).map(|c| c.1 as u64);
    if get("BVH_STACK_WORKGROUP") != Some(1) {
        return 0;
    }
    SHORT_STACK * SHORT_STACK_ARRAYS * 4 * get("WORKGROUP_SIZE").unwrap_or(1)
}

/// Errors, naming the limit, the need and the knob, when the pipeline `label` binding
/// `storage` storage buffers with `constants` does not fit `adapter`.
pub fn check(adapter: &AdapterSummary, label: &str, storage: u32, constants: &[(&str, f64)]) -> Result<()> {
    let max = adapter.max_storage_buffers_per_shader_stage;
    if storage > max {
        bail!(
            "the {label} pipeline binds {storage} storage buffers but {} allows {max} per shader \
             stage (max_storage_buffers_per_shader_stage): the scene's bind group alone takes 13 \
             (its primitives and BVH nodes over up to four bindings each, so that large scenes fit \
             lavapipe's 128 MiB bindings); for a wavefront pass use --method megakernel, whose \
             pipelines bind the fewest; otherwise an adapter with more storage buffers per stage \
             (a Vulkan driver)",
            adapter.name
        );
    }
    let need = short_stack_bytes(constants);
    let max = adapter.max_compute_workgroup_storage_size as u64;
    if need > max {
        let size = constants.iter().find(|c| c.0 == "WORKGROUP_SIZE").map_or(1, |c| c.1 as u64);
        bail!(
            "--stack workgroup needs {need} bytes of workgroup memory in the {label} pipeline \
             ({SHORT_STACK} entries × {SHORT_STACK_ARRAYS} arrays × 4 bytes × workgroup size {size}) \
             but {} allows {max} (max_compute_workgroup_storage_size); use --stack function or \
             a --workgroup-size of at most {}",
            adapter.name,
            max / (SHORT_STACK * SHORT_STACK_ARRAYS * 4)
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_stack_matches_the_shader() {
        let wgsl = include_str!("../../shaders/shared/bvh_stack.wgsl");
        assert!(wgsl.contains(&format!("const SHORT_STACK: u32 = {SHORT_STACK}u;")));
        let c = [("BVH_STACK_WORKGROUP", 1.0), ("WORKGROUP_SIZE", 64.0)];
        assert_eq!(short_stack_bytes(&c), 4096);
        assert_eq!(short_stack_bytes(&[("BVH_STACK_WORKGROUP", 0.0), ("WORKGROUP_SIZE", 64.0)]), 0);
    }
}
