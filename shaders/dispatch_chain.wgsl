// The dispatch-cost microbenchmark's link (src/gpu/dispatch_cost.rs): a dispatch of one
// workgroup that does almost nothing, so a chain of them measures what a dispatch costs by
// itself (launch, the barrier before it, ramp-up and drain), the floor under every wavefront pass.

// `chain_link`: adds one to the counter, so each link depends on the one before it; bound
// read-write, it gets a barrier before every dispatch (wgpu-core: a read_write binding is a
// new usage scope each dispatch).
@group(0) @binding(0) var<storage, read_write> counter: array<u32>;

// `chain_read`: only reads, bound read-only: nothing for wgpu to order between its dispatches,
// so no barrier; the dispatches are independent and may overlap.
@group(0) @binding(1) var<storage, read> input: array<u32>;

var<workgroup> sink: atomic<u32>;

@compute @workgroup_size(64)
fn chain_link(@builtin(local_invocation_index) lane: u32) {
    if lane == 0u {
        counter[0] = counter[0] + 1u;
    }
}

@compute @workgroup_size(64)
fn chain_read(@builtin(local_invocation_index) lane: u32) {
    // Never true (the input holds zero); it keeps the load from being optimised away.
    if input[0] == 0xdeadbeefu {
        atomicAdd(&sink, lane);
    }
}
