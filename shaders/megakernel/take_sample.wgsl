// The regenerating megakernel's sample fetch without subgroups (adapters without them): each lane
// that needs a sample takes it with its own atomic. A hook (src/gpu/shader_variants.rs): on
// adapters with subgroups the variant swaps in take_sample_subgroup.wgsl.

fn take_sample(wants: bool) -> u32 {
    if !wants {
        return NO_SAMPLE;
    }
    return atomicAdd(&work[WORK_NEXT], 1u);
}

// Without subgroup operations in the loop, each lane leaves as soon as it is done.
fn leave_together(done: bool) -> bool {
    return done;
}
