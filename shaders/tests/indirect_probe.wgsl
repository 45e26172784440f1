// Test kernels: the indirect arguments of wavefront/shared/indirect_args.wgsl for thread counts the host
// chooses (hostile ones included), and a kernel that counts the workgroups an indirect dispatch
// of them really runs, so tests/suite/indirect_args.rs can check that no argument exceeds the
// adapter's limit with wgpu's indirect validation off.

#include "wavefront/shared/indirect_args.wgsl"

@group(0) @binding(0) var<storage, read> threads: array<u32>;
@group(0) @binding(1) var<storage, read_write> args: array<u32>;
@group(0) @binding(2) var<storage, read_write> ran: array<atomic<u32>>;

const GROUP: u32 = 64u;

@compute @workgroup_size(64)
fn indirect_probe(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= arrayLength(&threads) {
        return;
    }
    args[3u * i] = workgroups_clamped(threads[i], GROUP);
    args[3u * i + 1u] = 1u;
    args[3u * i + 2u] = 1u;
}

@compute @workgroup_size(1)
fn count_workgroups() {
    atomicAdd(&ran[0], 1u);
}
