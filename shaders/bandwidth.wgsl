// The bandwidth microbenchmark's kernels (src/gpu/bandwidth.rs): a streaming copy and a streaming
// read of 16-byte elements, consecutive threads on consecutive elements, the access pattern of the
// wavefront's path state. What the path-state traffic of a pass (src/gpu/wavefront/traffic.rs)
// is compared with: the bytes per second this device reaches on it.

@group(0) @binding(0) var<storage, read> src: array<vec4<u32>>;
@group(0) @binding(1) var<storage, read_write> dst: array<vec4<u32>>;

// Threads in one row of the dispatch: a large buffer needs more workgroups than one dimension
// holds, so the dispatch is two-dimensional.
override ROW: u32 = 16776960u;

fn element(gid: vec3<u32>) -> u32 {
    return gid.y * ROW + gid.x;
}

@compute @workgroup_size(256)
fn stream_copy(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = element(gid);
    if i < arrayLength(&src) {
        dst[i] = src[i];
    }
}

@compute @workgroup_size(256)
fn stream_read(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = element(gid);
    if i < arrayLength(&src) {
        let v = src[i];
        // Never true for the benchmark's data (every element's w is 1): it keeps the load.
        if v.w == 0xffffffffu {
            dst[0] = v;
        }
    }
}
