// The preheat's busy work (src/gpu/preheat.rs): every invocation spins on integer arithmetic
// whose result is never stored (the test keeps the compiler from dropping the loop), so a
// dispatch keeps every SM busy without touching memory.

@group(0) @binding(0) var<storage, read_write> sink: array<u32>;

const SPINS: u32 = 4096u;

@compute @workgroup_size(64)
fn preheat(@builtin(global_invocation_id) id: vec3<u32>) {
    var x = id.x * 747796405u + 2891336453u;
    for (var i = 0u; i < SPINS; i++) {
        x = x * 1664525u + 1013904223u;
        x ^= x >> 13u;
    }
    if x == 0x9e3779b9u && id.x == 0xffffffffu {
        sink[0] = x;
    }
}
