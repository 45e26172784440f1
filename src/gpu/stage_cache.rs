//! Shader modules, bind-group layouts and compute pipelines built once per device and reused by
//! every later render on it: a repetition of an experiment run, or the next run of the same
//! method, pays no shader translation or driver compilation again (on a GPU driver, creating a
//! pipeline compiles it to machine code: tens to hundreds of milliseconds per pass).
//!
//! Reuse is safe because wgpu deduplicates bind-group layouts by their entries (wgpu-core's
//! layout pool): a pipeline built against an earlier layout accepts bind groups made from an
//! equal one. Layouts are cached here as well, so equal layouts are the same object.

use std::collections::hash_map::DefaultHasher;
use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::sync::Mutex;

/// A pipeline's identity: entry point, module, bind-group layouts and pipeline constants (by
/// their bits, as f64 is not `Eq`).
#[derive(Clone, PartialEq, Eq, Hash)]
struct PipelineKey {
    label: &'static str,
    module: wgpu::ShaderModule,
    layouts: Vec<wgpu::BindGroupLayout>,
    constants: Vec<(String, u64)>,
}

#[derive(Default)]
struct Entries {
    layouts: HashMap<Vec<wgpu::BindGroupLayoutEntry>, wgpu::BindGroupLayout>,
    /// Per layout made here: its storage-buffer bindings (`pipeline_limits`).
    storage: HashMap<wgpu::BindGroupLayout, u32>,
    /// By label, a hash of the composed source, and the runtime checks it was compiled with.
    modules: HashMap<(&'static str, u64, super::shader_checks::ShaderChecks), wgpu::ShaderModule>,
    pipelines: HashMap<PipelineKey, wgpu::ComputePipeline>,
}

/// What one device has built, with counts of what was reused (for logs and tests).
#[derive(Default)]
pub struct StageCache {
    entries: Mutex<Entries>,
    hits: Mutex<u64>,
}

impl StageCache {
    /// The cached layout with these entries, or the one `make` builds (then cached).
    pub fn layout(
        &self,
        entries: &[wgpu::BindGroupLayoutEntry],
        make: impl FnOnce() -> wgpu::BindGroupLayout,
    ) -> wgpu::BindGroupLayout {
        let mut e = self.entries.lock().unwrap();
        let layout = e.layouts.entry(entries.to_vec()).or_insert_with(make).clone();
        let storage = entries
            .iter()
            .filter(|b| {
                matches!(b.ty, wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Storage { .. }, .. })
            })
            .count() as u32;
        e.storage.insert(layout.clone(), storage);
        layout
    }

    /// Storage-buffer bindings of `layout` (0 for a layout not made by [`Self::layout`]).
    pub fn storage_buffers(&self, layout: &wgpu::BindGroupLayout) -> u32 {
        self.entries.lock().unwrap().storage.get(layout).copied().unwrap_or(0)
    }

    /// The cached module for `label`, `source` and `checks`, or the one `make` builds (cached
    /// if it succeeds).
    pub fn module<E>(
        &self,
        label: &'static str,
        source: &str,
        checks: super::shader_checks::ShaderChecks,
        make: impl FnOnce() -> Result<wgpu::ShaderModule, E>,
    ) -> Result<wgpu::ShaderModule, E> {
        let mut h = DefaultHasher::new();
        source.hash(&mut h);
        let key = (label, h.finish(), checks);
        if let Some(m) = self.entries.lock().unwrap().modules.get(&key) {
            *self.hits.lock().unwrap() += 1;
            return Ok(m.clone());
        }
        let m = make()?;
        self.entries.lock().unwrap().modules.insert(key, m.clone());
        Ok(m)
    }

    /// The cached pipeline for entry point `label` of `module` with these layouts and
    /// constants, or the one `make` builds (cached if it succeeds).
    pub fn pipeline<E>(
        &self,
        label: &'static str,
        module: &wgpu::ShaderModule,
        layouts: &[&wgpu::BindGroupLayout],
        constants: &[(&str, f64)],
        make: impl FnOnce() -> Result<wgpu::ComputePipeline, E>,
    ) -> Result<wgpu::ComputePipeline, E> {
        let key = PipelineKey {
            label,
            module: module.clone(),
            layouts: layouts.iter().map(|&l| l.clone()).collect(),
            constants: constants.iter().map(|&(n, v)| (n.to_string(), v.to_bits())).collect(),
        };
        if let Some(p) = self.entries.lock().unwrap().pipelines.get(&key) {
            *self.hits.lock().unwrap() += 1;
            return Ok(p.clone());
        }
        let p = make()?;
        self.entries.lock().unwrap().pipelines.insert(key, p.clone());
        Ok(p)
    }

    /// Modules and pipelines served from the cache so far.
    pub fn hits(&self) -> u64 {
        *self.hits.lock().unwrap()
    }

    /// Pipelines built so far.
    pub fn pipelines(&self) -> usize {
        self.entries.lock().unwrap().pipelines.len()
    }
}
