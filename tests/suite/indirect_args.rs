//! Indirect arguments are safe without wgpu's indirect validation (off by default: it charged
//! the wavefront a dispatch and two barriers per indirect pass). Every workgroup count our
//! shaders write goes through `shaders/wavefront/shared/indirect_args.wgsl`; fed hostile thread counts
//! (0, exact multiples, one past, the largest u32) on the GPU, it never exceeds the device's
//! limit, is exact wherever the limit allows, and an indirect dispatch of the clamped largest
//! count runs exactly the limit's workgroups with the validation off.

use crate::common;

use wavetrace::gpu::buffers::{read_back, storage_entry, storage_init, storage_zeroed};
use wavetrace::gpu::context::instance_flags;
use wavetrace::gpu::shaders;

#[test]
fn indirect_arguments_stay_within_the_limit() {
    let Some(ctx) = common::gpu() else { return };
    assert!(
        !instance_flags().contains(wgpu::InstanceFlags::VALIDATION_INDIRECT_CALL)
            || std::env::var_os("WGPU_VALIDATION_INDIRECT_CALL").is_some(),
        "wgpu's indirect validation is on although WGPU_VALIDATION_INDIRECT_CALL is unset"
    );
    let limit = ctx.device.limits().max_compute_workgroups_per_dimension;
    let group = 64u32;
    let at_limit = limit.saturating_mul(group);
    let threads =
        [0, 1, 63, 64, 65, 4096, at_limit - 1, at_limit, at_limit.saturating_add(1), u32::MAX - 63, u32::MAX];
    let n = threads.len() as u64;
    let input = storage_init(ctx, "threads", &threads, wgpu::BufferUsages::empty()).unwrap();
    let args =
        storage_zeroed(ctx, "args", n * 12, wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::INDIRECT)
            .unwrap();
    let ran = storage_zeroed(ctx, "ran", 4, wgpu::BufferUsages::COPY_SRC).unwrap();
    let layout = ctx.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: None,
        entries: &[storage_entry(0, true), storage_entry(1, false), storage_entry(2, false)],
    });
    // The indirect dispatch cannot bind its argument buffer as storage: a stand-in there.
    let stand_in = storage_zeroed(ctx, "stand-in", n * 12, wgpu::BufferUsages::empty()).unwrap();
    let group_of = |binding_1: &wgpu::Buffer| {
        let entries = [
            wgpu::BindGroupEntry { binding: 0, resource: input.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: binding_1.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 2, resource: ran.as_entire_binding() },
        ];
        ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &layout,
            entries: &entries,
        })
    };
    let module = ctx.shader("indirect_probe", shaders::INDIRECT_PROBE, Default::default()).unwrap();
    let constants = [("MAX_WORKGROUPS", limit as f64)];
    let probe = ctx.compute_pipeline("indirect_probe", &module, &[&layout], &constants).unwrap();
    let count = ctx.compute_pipeline("count_workgroups", &module, &[&layout], &constants).unwrap();
    let (write_group, count_group) = (group_of(&args), group_of(&stand_in));
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&probe);
        pass.set_bind_group(0, &write_group, &[]);
        pass.dispatch_workgroups(1, 1, 1);
    }
    {
        // The clamped largest count, dispatched as the wavefront dispatches its passes.
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&count);
        pass.set_bind_group(0, &count_group, &[]);
        pass.dispatch_workgroups_indirect(&args, (n - 1) * 12);
    }
    ctx.queue.submit([enc.finish()]);
    let got: Vec<u32> = read_back(ctx, &args, n * 12).unwrap();
    for (i, &t) in threads.iter().enumerate() {
        let needed = t.div_ceil(group);
        let want = needed.min(limit);
        assert_eq!(got[3 * i..3 * i + 3], [want, 1, 1], "{t} threads in groups of {group}, limit {limit}");
    }
    let ran: Vec<u32> = read_back(ctx, &ran, 4).unwrap();
    assert_eq!(ran[0], limit, "workgroups an indirect dispatch of u32::MAX threads ran");
}
