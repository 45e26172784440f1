//! Buffer creation checked against the adapter's limits, bind-group-layout entries, and
//! read-back: the wgpu plumbing every stage shares.

pub use super::binding::{storage_entry, uniform_entry};
use super::context::GpuContext;
use anyhow::{anyhow, bail, Result};
use wgpu::util::DeviceExt;

/// A storage buffer holding `data`. An empty slice gets one zeroed `T`: wgpu rejects empty
/// bindings, and a binding shorter than one element of the shader's array fails validation
/// ("bound with size 16 where the shader expects 48"), so padding must be a whole element.
/// Refused with a message naming `label` when it exceeds the adapter's storage-binding or
/// buffer limit.
pub fn storage_init<T: bytemuck::Pod>(
    ctx: &GpuContext,
    label: &'static str,
    data: &[T],
    extra: wgpu::BufferUsages,
) -> Result<wgpu::Buffer> {
    let padding = [T::zeroed()];
    let contents: &[u8] = bytemuck::cast_slice(if data.is_empty() { &padding[..] } else { data });
    check_size(ctx, label, contents.len() as u64)?;
    Ok(ctx.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents,
        usage: wgpu::BufferUsages::STORAGE | extra,
    }))
}

/// A zeroed storage buffer of `size` bytes, checked like [`storage_init`].
pub fn storage_zeroed(
    ctx: &GpuContext,
    label: &'static str,
    size: u64,
    extra: wgpu::BufferUsages,
) -> Result<wgpu::Buffer> {
    let size = size.max(16);
    check_size(ctx, label, size)?;
    Ok(ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::STORAGE | extra,
        mapped_at_creation: false,
    }))
}

/// Errors out, naming the buffer and both sizes, if one binding of `size` bytes cannot exist here.
pub fn check_size(ctx: &GpuContext, label: &str, size: u64) -> Result<()> {
    let limit = ctx.summary.max_storage_buffer_binding_size.min(ctx.summary.max_buffer_size);
    if size > limit {
        bail!(
            "the {label} buffer needs {} but {} allows at most {} per storage binding; \
             use a smaller image or scene",
            human_bytes(size),
            ctx.summary.name,
            human_bytes(limit)
        );
    }
    Ok(())
}

pub fn human_bytes(b: u64) -> String {
    match b {
        b if b >= 1 << 30 => format!("{:.2} GiB", b as f64 / (1u64 << 30) as f64),
        b if b >= 1 << 20 => format!("{:.1} MiB", b as f64 / (1u64 << 20) as f64),
        b if b >= 1 << 10 => format!("{:.1} KiB", b as f64 / 1024.0),
        b => format!("{b} B"),
    }
}

/// Copies `size` bytes of `src` to the host (in its own submission) and returns them as `T`s.
/// For one-off reads (the film, end-of-render counters); reads repeated within a render go
/// through a [`Staging`] buffer.
pub fn read_back<T: bytemuck::Pod>(ctx: &GpuContext, src: &wgpu::Buffer, size: u64) -> Result<Vec<T>> {
    let staging = Staging::new(ctx, "read-back", size);
    let mut enc =
        ctx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("read-back") });
    staging.copy(&mut enc, src, size);
    ctx.queue.submit([enc.finish()]);
    staging.read(ctx, size)
}

/// A host-readable buffer reused by every read-back of one kind during a render (the
/// regenerating schedule's counters at each check, the timestamps of each batch), so that a
/// check costs a copy recorded into the submission it follows, not a buffer and a submission of
/// its own.
pub struct Staging {
    buffer: wgpu::Buffer,
}

impl Staging {
    pub fn new(ctx: &GpuContext, label: &'static str, size: u64) -> Self {
        let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: size.max(4),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self { buffer }
    }

    /// Records a copy of `src`'s first `size` bytes into the staging buffer.
    pub fn copy(&self, enc: &mut wgpu::CommandEncoder, src: &wgpu::Buffer, size: u64) {
        enc.copy_buffer_to_buffer(src, 0, &self.buffer, 0, size);
    }

    /// Asks for the first `size` bytes to be mapped once the submissions before have run,
    /// without waiting: the device's polls complete it ([`MapRequest::is_ready`]), and
    /// [`Self::take`] reads it then.
    pub fn request(&self, size: u64) -> MapRequest {
        let state = std::sync::Arc::new(std::sync::atomic::AtomicU8::new(MAP_PENDING));
        let done = state.clone();
        self.buffer.slice(..size).map_async(wgpu::MapMode::Read, move |r| {
            done.store(if r.is_ok() { MAP_OK } else { MAP_FAILED }, std::sync::atomic::Ordering::Release);
        });
        MapRequest { state, size }
    }

    /// The bytes of a [`Self::request`] that is ready, as `T`s; unmaps for the next copy.
    pub fn take<T: bytemuck::Pod>(&self, req: &MapRequest) -> Result<Vec<T>> {
        match req.state.load(std::sync::atomic::Ordering::Acquire) {
            MAP_OK => {}
            MAP_FAILED => bail!("mapping the read-back buffer failed"),
            _ => bail!("read-back taken before it was mapped"),
        }
        let slice = self.buffer.slice(..req.size);
        let view = slice.get_mapped_range().map_err(|e| anyhow!("read-back: {e}"))?;
        let out = bytemuck::cast_slice::<u8, T>(&view).to_vec();
        drop(view);
        self.buffer.unmap();
        Ok(out)
    }

    /// Unmaps after a request whose bytes are not needed (once it is ready).
    pub fn discard(&self, req: &MapRequest) {
        if req.state.load(std::sync::atomic::Ordering::Acquire) == MAP_OK {
            self.buffer.unmap();
        }
    }

    /// The first `size` bytes as `T`s, once the submission holding the copy has run (waits
    /// for it).
    pub fn read<T: bytemuck::Pod>(&self, ctx: &GpuContext, size: u64) -> Result<Vec<T>> {
        let slice = self.buffer.slice(..size);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        ctx.wait()?;
        rx.recv()
            .map_err(|_| anyhow!("read-back was never completed"))?
            .map_err(|e| anyhow!("mapping the read-back buffer failed: {e}"))?;
        let view = slice.get_mapped_range().map_err(|e| anyhow!("read-back: {e}"))?;
        let out = bytemuck::cast_slice::<u8, T>(&view).to_vec();
        drop(view);
        self.buffer.unmap();
        Ok(out)
    }
}

const MAP_PENDING: u8 = 0;
const MAP_OK: u8 = 1;
const MAP_FAILED: u8 = 2;

/// A read-back asked for with [`Staging::request`], completed by the device's polls.
pub struct MapRequest {
    state: std::sync::Arc<std::sync::atomic::AtomicU8>,
    size: u64,
}

impl MapRequest {
    /// Whether the mapping has completed (or failed: [`Staging::take`] says so).
    pub fn is_ready(&self) -> bool {
        self.state.load(std::sync::atomic::Ordering::Acquire) != MAP_PENDING
    }

    /// Waits until the mapping has completed: for the submission `index` that holds its copy,
    /// then for its callback, which another thread polling the same device may be the one to
    /// run (the tests share a device), so a wait for the submission alone can return first.
    pub fn wait(&self, ctx: &GpuContext, index: Option<wgpu::SubmissionIndex>) -> Result<()> {
        ctx.device
            .poll(wgpu::PollType::Wait { submission_index: index, timeout: None })
            .map_err(|e| anyhow!("waiting for the GPU failed: {e}"))?;
        let start = std::time::Instant::now();
        while !self.is_ready() {
            if start.elapsed() > std::time::Duration::from_secs(60) {
                bail!("a read-back's mapping never completed");
            }
            ctx.device.poll(wgpu::PollType::Poll).map_err(|e| anyhow!("polling the GPU failed: {e}"))?;
            std::thread::yield_now();
        }
        Ok(())
    }
}
