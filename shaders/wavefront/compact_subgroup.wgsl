// compact, with a subgroup scan (adapters with subgroups): each subgroup scans its lanes with
// subgroupInclusiveAdd, one lane scans the subgroup totals, and every lane adds its subgroup's
// offset: 3 barriers per workgroup scan instead of the Hillis–Steele scan's 16. The passes are in
// shared/compact.wgsl, as for compact.wgsl. Rust side: src/gpu/wavefront/compact.rs.

#include "shared/path_state.wgsl"

// Per subgroup: its total, then the sum of the subgroups before it.
var<workgroup> subgroup_sums: array<vec4<u32>, SCAN_WG>;

// Inclusive scan of `scratch` across the workgroup. SCAN_WG is a multiple of every subgroup
// size, so every subgroup is full and its last lane holds its total.
fn scan_workgroup(lid: u32, lanes: Lanes) {
    let inclusive = subgroupInclusiveAdd(scratch[lid]);
    if lanes.lane == lanes.size - 1u {
        subgroup_sums[lanes.id] = inclusive;
    }
    workgroupBarrier();
    if lid == 0u {
        var running = vec4<u32>(0u);
        for (var i = 0u; i < SCAN_WG / lanes.size; i++) {
            let total = subgroup_sums[i];
            subgroup_sums[i] = running;
            running += total;
        }
    }
    workgroupBarrier();
    scratch[lid] = inclusive + subgroup_sums[lanes.id];
    workgroupBarrier();
}

#include "shared/compact.wgsl"

@compute @workgroup_size(SCAN_WG)
fn compact_scan(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32,
                @builtin(workgroup_id) wid: vec3<u32>, @builtin(subgroup_invocation_id) lane: u32,
                @builtin(subgroup_size) size: u32, @builtin(subgroup_id) id: u32) {
    compact_scan_main(gid, lid, wid, Lanes(lane, size, id));
}

@compute @workgroup_size(SCAN_WG)
fn compact_blocks(@builtin(local_invocation_index) lid: u32, @builtin(workgroup_id) wid: vec3<u32>,
                  @builtin(subgroup_invocation_id) lane: u32, @builtin(subgroup_size) size: u32,
                  @builtin(subgroup_id) id: u32) {
    compact_blocks_main(lid, wid, Lanes(lane, size, id));
}

@compute @workgroup_size(SCAN_WG)
fn compact_scatter(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>) {
    compact_scatter_main(gid, wid);
}
