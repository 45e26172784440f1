//! Adapter choice and device set-up, shared by the CLI, tests and benches.
//!
//! A real GPU is preferred; `--adapter SUBSTRING` and `WGPU_BACKEND` narrow the choice; a
//! software adapter (lavapipe) is used with a one-line notice. Device errors and device loss
//! are captured here and surfaced as `Err` by [`GpuContext::check`], never as panics.

use super::stage_cache::StageCache;
use anyhow::{anyhow, bail, Result};
use std::sync::{Arc, Mutex};

/// Shown when no adapter exists at all.
pub const NO_ADAPTER_HELP: &str = "no GPU adapter found. On Debian/Ubuntu install the software \
Vulkan driver with `sudo apt-get install -y mesa-vulkan-drivers` (or run ./scripts/setup.sh), \
or install your GPU's Vulkan driver";

/// What the tool needs to know about an adapter (also printed by `wavetrace info` and written
/// into reports).
#[derive(Clone, Debug, serde::Serialize)]
pub struct AdapterSummary {
    pub name: String,
    /// PCI vendor id (0x10de NVIDIA, 0x1002 AMD, 0x8086 Intel; 0x10005 Mesa's software driver).
    pub vendor: u32,
    /// `domain:bus:device.function` where the driver reports it (empty otherwise): how the GPU's
    /// state is read from the right device (`gpu/state.rs`).
    pub pci_bus_id: String,
    pub backend: String,
    pub device_type: String,
    pub driver: String,
    pub driver_info: String,
    pub timestamps: bool,
    pub subgroups: bool,
    pub subgroup_min_size: u32,
    pub subgroup_max_size: u32,
    pub max_storage_buffer_binding_size: u64,
    pub max_buffer_size: u64,
    pub max_compute_workgroups_per_dimension: u32,
    pub max_compute_invocations_per_workgroup: u32,
    /// Bytes of workgroup memory one workgroup may use (`--stack workgroup` takes the most).
    pub max_compute_workgroup_storage_size: u32,
    /// Storage buffers one pipeline may bind for the compute stage, over all its bind groups.
    pub max_storage_buffers_per_shader_stage: u32,
    /// wgpu validates every indirect dispatch with an extra dispatch (on by default in wgpu 30;
    /// `WGPU_VALIDATION_INDIRECT_CALL=0` turns it off).
    pub indirect_validation: bool,
}

impl AdapterSummary {
    pub fn of(adapter: &wgpu::Adapter) -> Self {
        let info = adapter.get_info();
        let f = adapter.features();
        let l = adapter.limits();
        Self {
            name: info.name,
            vendor: info.vendor,
            pci_bus_id: info.device_pci_bus_id,
            backend: format!("{:?}", info.backend),
            device_type: format!("{:?}", info.device_type),
            driver: info.driver,
            driver_info: info.driver_info,
            timestamps: f.contains(wgpu::Features::TIMESTAMP_QUERY),
            subgroups: f.contains(wgpu::Features::SUBGROUP),
            subgroup_min_size: info.subgroup_min_size,
            subgroup_max_size: info.subgroup_max_size,
            max_storage_buffer_binding_size: l.max_storage_buffer_binding_size,
            max_buffer_size: l.max_buffer_size,
            max_compute_workgroups_per_dimension: l.max_compute_workgroups_per_dimension,
            max_compute_invocations_per_workgroup: l.max_compute_invocations_per_workgroup,
            max_compute_workgroup_storage_size: l.max_compute_workgroup_storage_size,
            max_storage_buffers_per_shader_stage: l.max_storage_buffers_per_shader_stage,
            indirect_validation: instance_flags().contains(wgpu::InstanceFlags::VALIDATION_INDIRECT_CALL),
        }
    }

    pub fn is_software(&self) -> bool {
        self.device_type == "Cpu"
    }
}

/// wgpu's defaults adjusted by its `WGPU_*` variables, except that indirect-call validation is
/// off unless `WGPU_VALIDATION_INDIRECT_CALL=1` asks for it: it adds a dispatch and two barriers
/// to every indirect pass, which nearly all wavefront passes are and no megakernel pass is, so
/// it biased every comparison against the wavefront (15-25% of a small job on the software
/// driver). It guards against indirect arguments past the device's limit; ours are clamped where
/// our shaders write them (shaders/wavefront/shared/indirect_args.wgsl, tests/suite/indirect_args.rs).
/// Reports record the setting (`indirect_validation`).
fn instance_descriptor() -> wgpu::InstanceDescriptor {
    let mut d = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    if std::env::var_os("WGPU_VALIDATION_INDIRECT_CALL").is_none() {
        d.flags.remove(wgpu::InstanceFlags::VALIDATION_INDIRECT_CALL);
    }
    d
}

/// The instance flags in force (build defaults adjusted by `WGPU_*` variables).
pub fn instance_flags() -> wgpu::InstanceFlags {
    instance_descriptor().flags
}

/// All adapters found (honouring `WGPU_BACKEND`).
pub fn enumerate() -> (wgpu::Instance, Vec<wgpu::Adapter>) {
    let instance = wgpu::Instance::new(instance_descriptor());
    let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
    (instance, adapters)
}

/// Higher is better: discrete > integrated > virtual > software > other; Vulkan breaks ties
/// because the software driver and NVIDIA both speak it and it has every feature we use.
fn rank(a: &wgpu::Adapter) -> (u32, u32) {
    let info = a.get_info();
    let t = match info.device_type {
        wgpu::DeviceType::DiscreteGpu => 4,
        wgpu::DeviceType::IntegratedGpu => 3,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 1,
        wgpu::DeviceType::Other => 0,
    };
    (t, (info.backend == wgpu::Backend::Vulkan) as u32)
}

/// Picks the adapter: the best-ranked one whose name contains `filter` (case-insensitive).
/// Returns it and a sentence saying why.
pub fn choose(adapters: &[wgpu::Adapter], filter: Option<&str>) -> Result<(usize, String)> {
    if adapters.is_empty() {
        bail!("{NO_ADAPTER_HELP}");
    }
    let wanted = |a: &wgpu::Adapter| match filter {
        Some(f) => a.get_info().name.to_lowercase().contains(&f.to_lowercase()),
        None => true,
    };
    let best = (0..adapters.len())
        .filter(|&i| wanted(&adapters[i]))
        .max_by_key(|&i| rank(&adapters[i]))
        .ok_or_else(|| {
            let names: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
            anyhow!("no adapter name contains {:?}; found: {}", filter.unwrap_or(""), names.join(", "))
        })?;
    let info = adapters[best].get_info();
    let why = match filter {
        Some(f) => format!("the best-ranked adapter matching --adapter {f:?}"),
        None => format!("the best-ranked adapter ({:?} on {:?})", info.device_type, info.backend),
    };
    Ok((best, why))
}

/// A device and queue with error capture, and what was chosen.
pub struct GpuContext {
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub summary: AdapterSummary,
    /// Modules, layouts and pipelines built on this device, reused by later renders.
    pub stages: StageCache,
    errors: Arc<Mutex<Vec<String>>>,
}

impl GpuContext {
    /// Chooses an adapter (see [`choose`]) and opens a device on it with the adapter's own limits
    /// (wgpu's defaults are far lower, e.g. for storage bindings) and the optional features we use.
    pub fn new(filter: Option<&str>) -> Result<Self> {
        let (_instance, mut adapters) = enumerate();
        let (i, why) = choose(&adapters, filter)?;
        let adapter = adapters.swap_remove(i);
        let summary = AdapterSummary::of(&adapter);
        log::info!("adapter: {} ({}), {why}", summary.name, summary.backend);
        if summary.is_software() {
            eprintln!(
                "notice: using the software adapter {:?}: GPU timings reflect the CPU it runs on",
                summary.name
            );
        }
        Self::open(adapter, summary)
    }

    fn open(adapter: wgpu::Adapter, summary: AdapterSummary) -> Result<Self> {
        let wanted = wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::SUBGROUP;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("wavetrace"),
            required_features: adapter.features() & wanted,
            required_limits: adapter.limits(),
            ..Default::default()
        }))
        .map_err(|e| anyhow!("cannot open a device on {}: {e}", summary.name))?;
        let errors = Arc::new(Mutex::new(Vec::new()));
        let sink = errors.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            sink.lock().unwrap().push(describe(&e));
        }));
        let sink = errors.clone();
        device.set_device_lost_callback(move |reason, msg| {
            sink.lock().unwrap().push(format!("device lost ({reason:?}): {msg}"));
        });
        Ok(Self { adapter, device, queue, summary, stages: StageCache::default(), errors })
    }

    /// Returns the first device error or loss reported since the last check.
    pub fn check(&self) -> Result<()> {
        let mut errors = self.errors.lock().unwrap();
        if errors.is_empty() {
            return Ok(());
        }
        let all = std::mem::take(&mut *errors);
        bail!("GPU error: {}", all.join("; "))
    }

    /// Refuses a workgroup size the adapter cannot run (shared by every GPU method).
    pub fn check_workgroup_size(&self, size: u32) -> Result<()> {
        let max = self.summary.max_compute_invocations_per_workgroup;
        if size == 0 || size > max {
            bail!("workgroup size {size} is outside 1..={max} on {}", self.summary.name);
        }
        Ok(())
    }

    /// Waits for all submitted work, then reports any error or device loss.
    pub fn wait(&self) -> Result<()> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| anyhow!("waiting for the GPU failed: {e}"))?;
        self.check()
    }

    /// Creates a compute pipeline and its layout, turning validation errors, out-of-memory and
    /// internal errors (e.g. a shader needing too much scratch memory, wgpu #10027) into `Err`.
    /// The layout is made inside the same scopes: an adapter with too few bindings (OpenGL)
    /// fails there with the reason, where the pipeline alone would only call its layout invalid.
    pub fn compute_pipeline(
        &self,
        label: &'static str,
        module: &wgpu::ShaderModule,
        layouts: &[&wgpu::BindGroupLayout],
        constants: &[(&str, f64)],
    ) -> Result<wgpu::ComputePipeline> {
        let storage = layouts.iter().map(|l| self.stages.storage_buffers(l)).sum();
        super::pipeline_limits::check(&self.summary, label, storage, constants)?;
        let scopes =
            [wgpu::ErrorFilter::Validation, wgpu::ErrorFilter::OutOfMemory, wgpu::ErrorFilter::Internal]
                .map(|f| self.device.push_error_scope(f));
        let layouts: Vec<Option<&wgpu::BindGroupLayout>> = layouts.iter().map(|l| Some(*l)).collect();
        let layout = self.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts: &layouts,
            immediate_size: 0,
        });
        let started = std::time::Instant::now();
        let pipeline = self.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(label),
            layout: Some(&layout),
            module,
            entry_point: Some(label),
            compilation_options: wgpu::PipelineCompilationOptions { constants, ..Default::default() },
            cache: None,
        });
        // What the driver's compiler costs (RUST_LOG=wavetrace=debug): on the software driver,
        // most of the test suite's time.
        log::debug!("pipeline {label}: created in {:.3} s", started.elapsed().as_secs_f64());
        for scope in scopes.into_iter().rev() {
            if let Some(e) = pollster::block_on(scope.pop()) {
                if self.adapter.get_info().backend == wgpu::Backend::Gl {
                    bail!(
                        "the {label} pipeline does not fit {} (an OpenGL adapter offers too few storage \
                         buffers for the wavefront: install a Vulkan driver, e.g. `apt-get install \
                         mesa-vulkan-drivers`, or use the megakernel): {}",
                        self.summary.name,
                        describe(&e)
                    );
                }
                bail!("creating the {label} pipeline failed: {}", describe(&e));
            }
        }
        self.check()?;
        Ok(pipeline)
    }

    /// A bind-group layout with `entries`: the one made before on this device if any, so that
    /// cached pipelines accept the bind groups of later renders.
    pub fn bind_group_layout(
        &self,
        label: &'static str,
        entries: &[wgpu::BindGroupLayoutEntry],
    ) -> wgpu::BindGroupLayout {
        self.stages.layout(entries, || {
            self.device
                .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(label), entries })
        })
    }

    /// A shader module from composed WGSL (compilation errors as `Err`), built once per device
    /// and set of runtime checks.
    pub fn shader(
        &self,
        label: &'static str,
        source: &str,
        checks: super::shader_checks::ShaderChecks,
    ) -> Result<wgpu::ShaderModule> {
        self.stages.module(label, source, checks, || self.build_shader(label, source, checks))
    }

    fn build_shader(
        &self,
        label: &'static str,
        source: &str,
        checks: super::shader_checks::ShaderChecks,
    ) -> Result<wgpu::ShaderModule> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let desc = wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        };
        let module = match checks {
            super::shader_checks::ShaderChecks::Checked => self.device.create_shader_module(desc),
            // SAFETY: every method's films with these modules match the checked ones' (the
            // shader-checks tests), so no access leaves its array; `--shader-checks unchecked`
            // is a measured knob, never the default.
            super::shader_checks::ShaderChecks::Unchecked => unsafe {
                self.device.create_shader_module_trusted(desc, wgpu::ShaderRuntimeChecks::unchecked())
            },
        };
        if let Some(e) = pollster::block_on(scope.pop()) {
            bail!("compiling shader {label} failed: {}", describe(&e));
        }
        Ok(module)
    }
}

/// A wgpu error with its causes: wgpu's own text is often just "Validation Error", and what
/// was wrong (which buffer, which binding) is in the source chain.
fn describe(e: &wgpu::Error) -> String {
    let mut text = e.to_string();
    let mut cause = std::error::Error::source(e);
    while let Some(c) = cause {
        let line = c.to_string();
        if !text.contains(&line) {
            text.push_str(": ");
            text.push_str(&line);
        }
        cause = c.source();
    }
    text
}
