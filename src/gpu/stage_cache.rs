//! Shader modules, bind-group layouts and compute pipelines built once per device and reused by
//! every later render on it: a repetition of an experiment run, or the next run of the same
//! method, pays no shader translation or driver compilation again (on a GPU driver, creating a
//! pipeline compiles it to machine code: tens to hundreds of milliseconds per pass).
//!
//! Reuse is safe because wgpu deduplicates bind-group layouts by their entries (wgpu-core's
//! layout pool): a pipeline built against an earlier layout accepts bind groups made from an
//! equal one. Layouts are cached here as well, so equal layouts are the same object.
//!
//! A pipeline is keyed by the constants its entry point reaches, not by every constant it is
//! given: the wavefront gives each pass every knob's constant, and most passes read few of them,
//! so two renders that differ in one knob share the passes that never read it (on the software
//! driver, where each pipeline costs about half a second to compile, this is most of the test
//! suite's GPU time).

use std::collections::hash_map::DefaultHasher;
use std::collections::{BTreeSet, HashMap};
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
    /// Each module's WGSL as naga reads it, to tell which constants an entry point reaches.
    parsed: HashMap<wgpu::ShaderModule, naga::Module>,
    /// By module and entry point: the pipeline constants it reaches.
    reached: HashMap<(wgpu::ShaderModule, &'static str), BTreeSet<String>>,
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
        let mut e = self.entries.lock().unwrap();
        e.modules.insert(key, m.clone());
        if let Ok(parsed) = naga::front::wgsl::parse_str(source) {
            e.parsed.insert(m.clone(), parsed);
        }
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
        let reached = self.reached(module, label);
        let key = PipelineKey {
            label,
            module: module.clone(),
            layouts: layouts.iter().map(|&l| l.clone()).collect(),
            constants: constants
                .iter()
                .filter(|(n, _)| reached.as_ref().is_none_or(|r| r.contains(*n)))
                .map(|&(n, v)| (n.to_string(), v.to_bits()))
                .collect(),
        };
        if let Some(p) = self.entries.lock().unwrap().pipelines.get(&key) {
            *self.hits.lock().unwrap() += 1;
            return Ok(p.clone());
        }
        let p = make()?;
        self.entries.lock().unwrap().pipelines.insert(key, p.clone());
        Ok(p)
    }

    /// The constants entry point `label` of `module` reaches (`None` for a module built
    /// elsewhere: then every constant keys its pipelines).
    fn reached(&self, module: &wgpu::ShaderModule, label: &'static str) -> Option<BTreeSet<String>> {
        let mut e = self.entries.lock().unwrap();
        let key = (module.clone(), label);
        if let Some(r) = e.reached.get(&key) {
            return Some(r.clone());
        }
        let r = reached_constants(e.parsed.get(module)?, label)?;
        e.reached.insert(key, r.clone());
        Some(r)
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

/// `module` cut to its entry point `entry` and compacted by naga: what that entry point reaches,
/// directly or through the functions it calls (global variables, functions, constants, and the
/// overrides its code, array sizes, workgroup size and other overrides' initializers name).
/// `None` when the module has no such entry point.
pub fn reached(module: &naga::Module, entry: &str) -> Option<naga::Module> {
    let mut m = module.clone();
    m.entry_points.retain(|e| e.name == entry);
    if m.entry_points.is_empty() {
        return None;
    }
    naga::compact::compact(&mut m, naga::compact::KeepUnused::No);
    Some(m)
}

/// The named overrides entry point `entry` of `module` reaches ([`reached`]).
pub fn reached_constants(module: &naga::Module, entry: &str) -> Option<BTreeSet<String>> {
    reached(module, entry).map(|m| m.overrides.iter().filter_map(|(_, o)| o.name.clone()).collect())
}

#[cfg(test)]
mod tests {
    use super::reached_constants;

    /// An entry point reaches the overrides its functions read, its workgroup size's, those an
    /// array size or a reached override's initializer names, and no other.
    #[test]
    fn an_entry_point_reaches_only_the_constants_it_reads() {
        let src = "
            override A: u32 = 1u;
            override B: u32 = 2u;
            override C: u32 = 3u;
            override D: u32 = A * 2u;
            override WG: u32 = 64u;
            override LEN: u32 = 4u;
            var<workgroup> scratch: array<u32, LEN>;
            @group(0) @binding(0) var<storage, read_write> out: array<u32>;
            fn helper() -> u32 { return D; }
            @compute @workgroup_size(WG) fn first() { out[0] = helper() + scratch[0]; }
            @compute @workgroup_size(1) fn second() { out[1] = B; }
        ";
        let module = naga::front::wgsl::parse_str(src).unwrap();
        let names = |e| reached_constants(&module, e).unwrap().into_iter().collect::<Vec<_>>();
        assert_eq!(names("first"), ["A", "D", "LEN", "WG"]);
        assert_eq!(names("second"), ["B"]);
        assert!(reached_constants(&module, "third").is_none());
    }
}
