//! How a render is cut into dispatches, and the uniform buffer that hands each dispatch its share
//! (one 256-byte-aligned slot per dispatch, bound with a dynamic offset).

use super::context::GpuContext;
use super::memory::{MemoryCategory, MemoryLedger};
use crate::layout::DispatchParams;
use wgpu::util::DeviceExt;

/// Most samples one pixel takes in one dispatch: bounds the accumulate pass's loop (llvmpipe
/// ends a shader's loops after 65535 iterations in total).
pub const MAX_SAMPLES_PER_PIXEL_PER_DISPATCH: u32 = 4096;

/// Splits `pixels` × `spp` path samples into dispatches of at most `budget` samples and
/// `max_threads` threads (one thread per sample). Sample chunks are outermost, so each pixel
/// receives its samples in increasing order across dispatches.
pub fn plan(pixels: u32, spp: u32, budget: u64, max_threads: u32) -> Vec<DispatchParams> {
    let cap = budget.min(max_threads as u64).max(1);
    let pixels_per = (pixels as u64).min(cap) as u32;
    let samples_per =
        (cap / pixels_per as u64).clamp(1, spp.min(MAX_SAMPLES_PER_PIXEL_PER_DISPATCH) as u64) as u32;
    let mut plan = Vec::new();
    let mut s = 0;
    while s < spp {
        let sample_count = samples_per.min(spp - s);
        let mut p = 0;
        while p < pixels {
            let pixel_count = pixels_per.min(pixels - p);
            plan.push(DispatchParams { pixel_offset: p, pixel_count, sample_start: s, sample_count });
            p += pixel_count;
        }
        s += sample_count;
    }
    plan
}

/// The plan's parameters in one uniform buffer; dispatch `i` is at [`DispatchUniforms::offset`].
pub struct DispatchUniforms {
    pub buffer: wgpu::Buffer,
    stride: u32,
}

impl DispatchUniforms {
    pub fn new(ctx: &GpuContext, plan: &[DispatchParams], memory: &mut MemoryLedger) -> Self {
        let stride = ctx.device.limits().min_uniform_buffer_offset_alignment.max(16);
        let mut bytes = vec![0u8; plan.len().max(1) * stride as usize];
        for (i, d) in plan.iter().enumerate() {
            let at = i * stride as usize;
            bytes[at..at + 16].copy_from_slice(bytemuck::bytes_of(d));
        }
        let buffer = ctx.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("dispatch params"),
            contents: &bytes,
            usage: wgpu::BufferUsages::UNIFORM,
        });
        memory.add(MemoryCategory::Parameters, buffer.size());
        Self { buffer, stride }
    }

    pub fn offset(&self, dispatch: usize) -> u32 {
        dispatch as u32 * self.stride
    }

    /// A binding of one slot, for bind-group entries declared with a dynamic offset.
    pub fn binding(&self) -> wgpu::BindingResource<'_> {
        wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &self.buffer,
            offset: 0,
            size: wgpu::BufferSize::new(std::mem::size_of::<DispatchParams>() as u64),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plan_covers_every_pixel_sample_once_in_sample_order() {
        for (pixels, spp, budget, max_threads) in [
            (100, 7, 64, 1000),
            (10, 100, 1 << 20, 1000),
            (5000, 3, 1 << 20, 1024),
            (1, 10_000, 1 << 21, 1 << 22),
        ] {
            let plan = plan(pixels, spp, budget, max_threads);
            let mut next = vec![0u32; pixels as usize];
            for d in &plan {
                let threads = d.pixel_count as u64 * d.sample_count as u64;
                assert!(threads <= budget.min(max_threads as u64).max(1));
                assert!(d.sample_count <= MAX_SAMPLES_PER_PIXEL_PER_DISPATCH);
                for p in d.pixel_offset..d.pixel_offset + d.pixel_count {
                    assert_eq!(next[p as usize], d.sample_start, "pixel {p} sees samples in order");
                    next[p as usize] += d.sample_count;
                }
            }
            assert!(next.iter().all(|&n| n == spp));
        }
    }
}
