// The traversal stack (`--stack`, bvh::BvhStack): in function memory (`function`: a 64-entry
// array per thread, per-thread local memory on NVIDIA), or (`workgroup`) a short stack of 8
// entries a thread in workgroup memory with the deeper entries spilled to the function array
// (tinybvh's tiny8.comp keeps 8 a thread, in two arrays against bank conflicts). The short
// stack is a ring: entry i sits in slot i % 8, and pushing entry i ≥ 8 first moves entry i − 8
// out to function memory; popping it brings entry i − 8 back. The same entries in the same
// order either way, so the films are the same; only where they live changes. The entry point
// names its lane (bvh_stack_lane) before it traverses.

const SHORT_STACK: u32 = 8u;

// 1: the short stack in workgroup memory; 0: function memory only. A pipeline constant.
override BVH_STACK_WORKGROUP: u32 = 0u;

// Entry k of lane l at k * WORKGROUP_SIZE + l: neighbouring lanes in neighbouring banks.
// One entry (unused) with the function stack, so that a large workgroup does not reserve
// workgroup memory it never touches.
override SHORT_STACK_ENTRIES: u32 = select(1u, SHORT_STACK * WORKGROUP_SIZE, BVH_STACK_WORKGROUP == 1u);
var<workgroup> short_stack_a: array<u32, SHORT_STACK_ENTRIES>;
var<workgroup> short_stack_b: array<u32, SHORT_STACK_ENTRIES>;
var<private> stack_lane: u32;

// The calling thread's lane in its workgroup, from its global id (every traversing entry point
// runs one-dimensional workgroups of WORKGROUP_SIZE).
fn bvh_stack_lane(gid_x: u32) {
    stack_lane = gid_x % WORKGROUP_SIZE;
}

fn short_slot(i: u32) -> u32 {
    return (i % SHORT_STACK) * WORKGROUP_SIZE + stack_lane;
}

// Pushes `a` as entry i of a one-word stack whose function array is `deep`.
fn stack_push1(deep: ptr<function, array<u32, BVH_STACK>>, i: u32, a: u32) {
    if BVH_STACK_WORKGROUP == 0u {
        (*deep)[i] = a;
        return;
    }
    let s = short_slot(i);
    if i >= SHORT_STACK {
        (*deep)[i - SHORT_STACK] = short_stack_a[s];
    }
    short_stack_a[s] = a;
}

// Pops entry i (the top) of a one-word stack.
fn stack_pop1(deep: ptr<function, array<u32, BVH_STACK>>, i: u32) -> u32 {
    if BVH_STACK_WORKGROUP == 0u {
        return (*deep)[i];
    }
    let s = short_slot(i);
    let a = short_stack_a[s];
    if i >= SHORT_STACK {
        short_stack_a[s] = (*deep)[i - SHORT_STACK];
    }
    return a;
}

// Pushes (a, b) as entry i of a two-word stack whose function arrays are `deep_a`, `deep_b`.
fn stack_push2(deep_a: ptr<function, array<u32, BVH_STACK>>, deep_b: ptr<function, array<u32, BVH_STACK>>, i: u32, a: u32, b: u32) {
    if BVH_STACK_WORKGROUP == 0u {
        (*deep_a)[i] = a;
        (*deep_b)[i] = b;
        return;
    }
    let s = short_slot(i);
    if i >= SHORT_STACK {
        (*deep_a)[i - SHORT_STACK] = short_stack_a[s];
        (*deep_b)[i - SHORT_STACK] = short_stack_b[s];
    }
    short_stack_a[s] = a;
    short_stack_b[s] = b;
}

// Pops entry i (the top) of a two-word stack.
fn stack_pop2(deep_a: ptr<function, array<u32, BVH_STACK>>, deep_b: ptr<function, array<u32, BVH_STACK>>, i: u32) -> vec2<u32> {
    if BVH_STACK_WORKGROUP == 0u {
        return vec2<u32>((*deep_a)[i], (*deep_b)[i]);
    }
    let s = short_slot(i);
    let v = vec2<u32>(short_stack_a[s], short_stack_b[s]);
    if i >= SHORT_STACK {
        short_stack_a[s] = (*deep_a)[i - SHORT_STACK];
        short_stack_b[s] = (*deep_b)[i - SHORT_STACK];
    }
    return v;
}
