//! The WGSL RNG (`shaders/shared/rng.wgsl`) matches `src/rng.rs` bit for bit on the GPU.

use crate::common;

use wavetrace::gpu::buffers::{read_back, storage_entry, storage_init, storage_zeroed};
use wavetrace::gpu::shaders;
use wavetrace::rng::{pcg4d, to_unit_f32, Purpose, Stream};

#[test]
fn wgsl_rng_is_bit_identical_to_rust() {
    let Some(ctx) = common::gpu() else { return };
    // Edge keys plus random ones covering all purposes and large bounce/pixel/sample values.
    let mut s = Stream::new(7);
    let mut keys: Vec<[u32; 4]> = vec![[0; 4], [u32::MAX; 4], [1, 0, 0, 0], [0, 0, ((1 << 24) - 1) << 8, 0]];
    for i in 0..4096u32 {
        let word = |s: &mut Stream| (s.next_f32() * 16_777_216.0) as u32 ^ (i << 24);
        let purpose =
            [Purpose::Camera, Purpose::Scatter, Purpose::Light, Purpose::Roulette][i as usize % 4] as u32;
        keys.push([word(&mut s), word(&mut s), (word(&mut s) << 8) | purpose, word(&mut s)]);
    }
    let n = keys.len() as u64;
    let none = wgpu::BufferUsages::empty();
    let keys_buf = storage_init(ctx, "keys", &keys, none).unwrap();
    let hashes = storage_zeroed(ctx, "hashes", n * 16, wgpu::BufferUsages::COPY_SRC).unwrap();
    let unit = storage_zeroed(ctx, "unit", n * 16, wgpu::BufferUsages::COPY_SRC).unwrap();
    let layout = ctx.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: None,
        entries: &[storage_entry(0, true), storage_entry(1, false), storage_entry(2, false)],
    });
    let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &layout,
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: keys_buf.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: hashes.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 2, resource: unit.as_entire_binding() },
        ],
    });
    let module = ctx.shader("rng_probe", shaders::RNG_PROBE, Default::default()).unwrap();
    let pipeline = ctx.compute_pipeline("rng_probe", &module, &[&layout], &[]).unwrap();
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups((n as u32).div_ceil(64), 1, 1);
    }
    ctx.queue.submit([enc.finish()]);
    let gpu_hashes: Vec<[u32; 4]> = read_back(ctx, &hashes, n * 16).unwrap();
    let gpu_unit: Vec<[f32; 4]> = read_back(ctx, &unit, n * 16).unwrap();
    for (i, k) in keys.iter().enumerate() {
        let want = pcg4d(*k);
        assert_eq!(gpu_hashes[i], want, "pcg4d({k:?})");
        let want_unit = want.map(to_unit_f32);
        assert_eq!(gpu_unit[i].map(f32::to_bits), want_unit.map(f32::to_bits), "uniform4 for key {k:?}");
    }
}
