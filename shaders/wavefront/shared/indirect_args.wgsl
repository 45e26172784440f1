// Indirect-dispatch arguments that are safe without wgpu's indirect validation (off by default:
// it adds a dispatch and two barriers to every indirect pass, src/gpu/context.rs). A workgroup
// count above the adapter's limit is undefined behaviour on a GPU, so every count our shaders
// write is clamped here, and a clamp is counted so the host can refuse the render: a count that
// needs clamping means a queue grew past the pool, a bug, never a normal case.
// Included by wavefront/queue_setup.wgsl; checked with hostile counts by tests/indirect_probe.wgsl.

// The adapter's max_compute_workgroups_per_dimension, set by the host.
override MAX_WORKGROUPS: u32 = 65535u;

// Workgroups of `group` threads that cover `threads`, rounded up without overflowing near 2^32.
fn workgroups_needed(threads: u32, group: u32) -> u32 {
    return threads / group + select(0u, 1u, threads % group != 0u);
}

// `workgroups_needed`, at most MAX_WORKGROUPS.
fn workgroups_clamped(threads: u32, group: u32) -> u32 {
    return min(workgroups_needed(threads, group), MAX_WORKGROUPS);
}
