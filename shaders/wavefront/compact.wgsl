// compact, with a workgroup scan that needs no subgroups (adapters without them). The passes are
// in shared/compact.wgsl; compact_subgroup.wgsl is the same with a subgroup scan.
// Rust side: src/gpu/wavefront/compact.rs.

#include "shared/path_state.wgsl"

// Inclusive Hillis–Steele scan of `scratch` across the workgroup.
// `lanes` is unused here.
fn scan_workgroup(lid: u32, lanes: Lanes) {
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

#include "shared/compact.wgsl"

@compute @workgroup_size(SCAN_WG)
fn compact_scan(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32,
                @builtin(workgroup_id) wid: vec3<u32>) {
    compact_scan_main(gid, lid, wid, Lanes(0u, 0u, 0u));
}

@compute @workgroup_size(SCAN_WG)
fn compact_blocks(@builtin(local_invocation_index) lid: u32, @builtin(workgroup_id) wid: vec3<u32>) {
    compact_blocks_main(lid, wid, Lanes(0u, 0u, 0u));
}

@compute @workgroup_size(SCAN_WG)
fn compact_scatter(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>) {
    compact_scatter_main(gid, wid);
}
