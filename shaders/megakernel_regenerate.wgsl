// The regenerating megakernel on adapters without subgroups: each lane that needs a sample
// takes it with its own atomic. The loop is in shared/regenerate.wgsl.

#include "shared/regenerate.wgsl"

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
