// The regenerating megakernel's thread loop (Novák et al. 2010, on Aila & Laine's persistent
// threads): a fixed number of threads loop one bounce per iteration, and a lane whose path has
// ended takes the next (pixel, sample) of the dispatch at once, so lanes stop idling while their
// subgroup's longest path finishes. How a lane takes its next sample is a hook
// (megakernel/take_sample.wgsl, included at the end): `take_sample(wants: bool) -> u32`, per
// thread, and `leave_together(done: bool) -> bool`, whether the loop ends: for this lane alone;
// on adapters with subgroups the variant swaps in megakernel/take_sample_subgroup.wgsl, which
// takes them per subgroup and ends the loop once every lane of its subgroup is done.
// Rust side: src/gpu/megakernel.rs.
//
// Each sample keeps its counter-based random stream and lands in `samples` at its index in the
// dispatch, so the accumulate pass adds the same values in the same order as after the naive
// megakernel: the film is the same.

#include "shared/rng.wgsl"
#include "shared/scene.wgsl"
#include "shared/dispatch.wgsl"
#include "shared/instrument.wgsl"
#include "shared/integrator.wgsl"

@group(1) @binding(0) var<storage, read_write> samples: array<vec4<f32>>;
@group(1) @binding(1) var<uniform> dispatch: Dispatch;
// [WORK_NEXT]: the dispatch's next sample index, zeroed before each dispatch; [WORK_FINISHED]:
// samples written, which the host checks against the samples asked for; [WORK_CUT]: threads
// whose loop ended without running out of work, which only a driver's loop cap does (llvmpipe
// ends an invocation's loops after 65535 trips and says nothing); [WORK_PATHS_PER_THREAD]: most
// paths one thread starts per launch, set by the host (no limit but where loops are capped).
@group(1) @binding(2) var<storage, read_write> work: array<atomic<u32>, 4>;

const WORK_NEXT: u32 = 0u;
const WORK_FINISHED: u32 = 1u;
const WORK_CUT: u32 = 2u;
const WORK_PATHS_PER_THREAD: u32 = 3u;
const NO_SAMPLE: u32 = 0xffffffffu;

override WORKGROUP_SIZE: u32 = 64u;

@compute @workgroup_size(WORKGROUP_SIZE)
fn megakernel_regenerate(@builtin(local_invocation_index) lane: u32, /*@subgroup_size_param*/) {
    instrument_begin(/*@subgroup_size_arg*/);
    bvh_stack_lane(lane);
    let n = dispatch.pixel_count * dispatch.sample_count;
    let paths_per_thread = atomicLoad(&work[WORK_PATHS_PER_THREAD]);
    var path = TracedPath(Ray(vec3<f32>(0.0), vec3<f32>(0.0)), vec3<f32>(0.0), vec3<f32>(0.0), 0u, 0.0, NO_ORIGIN);
    var index = NO_SAMPLE;
    var pixel = 0u;
    var sample = 0u;
    var bounce = 0u;
    var live = false;
    var taken = 0u;
    var finished = 0u;
    var out_of_work = false;
    // Lanes leave the loop together (`leave_together`): with subgroups, `take_sample` runs
    // subgroup operations, which Vulkan defines only in uniform control flow unless the driver
    // guarantees maximal reconvergence. So no lane breaks out alone, `take_sample` is called by
    // every lane of the subgroup at the top of every iteration, and the branches below all
    // reconverge before the next one. A lane with nothing left to do idles there, as it would
    // masked off after an early break.
    loop {
        // A lane out of work never starts another path, so it is no longer live either.
        if leave_together(out_of_work) {
            break;
        }
        let wants = !live && !out_of_work;
        let next = take_sample(wants && taken < paths_per_thread);
        if wants {
            // NO_SAMPLE (this thread's share taken) or past the dispatch: nothing more to start.
            if next >= n {
                out_of_work = true;
            } else {
                index = next;
                taken += 1u;
                // As the naive megakernel: neighbouring indices are neighbouring pixels of a sample.
                pixel = dispatch.pixel_offset + index % dispatch.pixel_count;
                sample = dispatch.sample_start + index / dispatch.pixel_count;
                let x = pixel % frame.width;
                let y = pixel / frame.width;
                let ray = camera_ray(x, y, uniform4(pixel, sample, 0u, PURPOSE_CAMERA, frame.seed));
                path = TracedPath(ray, vec3<f32>(1.0), vec3<f32>(0.0), 0u, 0.0, NO_ORIGIN);
                bounce = 0u;
                live = true;
            }
        }
        if live {
            live = trace_bounce(&path, pixel, sample, bounce);
            bounce += 1u;
            if bounce >= frame.max_depth {
                live = false;
            }
            if !live {
                samples[index] = vec4<f32>(path.radiance, f32(path.rays));
                finished += 1u;
            }
        }
    }
    if finished > 0u {
        atomicAdd(&work[WORK_FINISHED], finished);
    }
    if !out_of_work {
        atomicAdd(&work[WORK_CUT], 1u);
    }
}

#include "megakernel/take_sample.wgsl"
