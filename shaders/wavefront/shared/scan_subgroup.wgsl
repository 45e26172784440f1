// The compaction's workgroup scan with subgroups (`--scan subgroup`): each subgroup scans its
// lanes with subgroupInclusiveAdd, one lane scans the subgroup totals, and every lane adds its
// subgroup's offset: 3 barriers per workgroup scan instead of the Hillis–Steele scan's 16.
// Swapped in for scan.wgsl (src/gpu/shader_variants.rs).

// What a scan pass's entry point takes to place its lane: its index in the workgroup, and where
// it sits in its subgroup.
struct ScanLane {
    @builtin(local_invocation_index) lid: u32,
    @builtin(subgroup_invocation_id) lane: u32,
    @builtin(subgroup_size) size: u32,
    @builtin(subgroup_id) id: u32,
}

// Per subgroup: its total, then the sum of the subgroups before it.
var<workgroup> subgroup_sums: array<vec4<u32>, SCAN_WG>;

// Inclusive scan of `scratch` across the workgroup. SCAN_WG is a multiple of every subgroup
// size, so every subgroup is full and its last lane holds its total.
fn scan_workgroup(at: ScanLane) {
    let lid = at.lid;
    let inclusive = subgroupInclusiveAdd(scratch[lid]);
    if at.lane == at.size - 1u {
        subgroup_sums[at.id] = inclusive;
    }
    workgroupBarrier();
    if lid == 0u {
        var running = vec4<u32>(0u);
        for (var i = 0u; i < SCAN_WG / at.size; i++) {
            let total = subgroup_sums[i];
            subgroup_sums[i] = running;
            running += total;
        }
    }
    workgroupBarrier();
    scratch[lid] = inclusive + subgroup_sums[at.id];
    workgroupBarrier();
}
