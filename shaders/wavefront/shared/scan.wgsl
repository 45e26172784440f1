// The compaction's workgroup scan without subgroups (`--scan workgroup`, and adapters without
// them): Hillis–Steele. A hook (src/gpu/shader_variants.rs): the `--scan subgroup` variant of
// wavefront/compact.wgsl swaps in scan_subgroup.wgsl.

// What a scan pass's entry point takes to place its lane: here its index in the workgroup alone.
struct ScanLane {
    @builtin(local_invocation_index) lid: u32,
}

// Inclusive Hillis–Steele scan of `scratch` across the workgroup.
fn scan_workgroup(at: ScanLane) {
    let lid = at.lid;
    for (var step = 1u; step < SCAN_WG; step <<= 1u) {
        workgroupBarrier();
        var v = scratch[lid];
        if lid >= step {
            v += scratch[lid - step];
        }
        workgroupBarrier();
        scratch[lid] = v;
    }
    workgroupBarrier();
}
