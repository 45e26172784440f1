//! The passes of a render, built once from its [`Graph`]: a pipeline per pass spec (its
//! shader, constants and bind groups as the spec declares them), and the one way every pass is
//! recorded.

use super::super::accumulate::Accumulate;
use super::super::buffers::storage_entry;
use super::super::context::GpuContext;
use super::super::label;
use super::super::memory::MemoryLedger;
use super::super::shaders::{self, Hook};
use super::super::stage::{Stage, Workgroups};
use super::graph::{Binds, Graph, Launch, Pass, Phase, Shader};
use super::plan::Plan;
use super::recorder::{Bindings, WaveRecorder};
use super::{ray_sort, WavefrontOptions};
use anyhow::Result;
use std::collections::HashMap;

/// The passes of a render, recorded per share and per iteration.
pub(super) struct Stages<'a> {
    pub(super) graph: Graph,
    /// `graph.passes[i]`'s pipeline (None for the film's passes: `accumulate` has them).
    stages: Vec<Option<Stage>>,
    accumulate: &'a Accumulate,
    /// The ray sort's buckets (`--ray-sort`).
    ray_sort: Option<(wgpu::BindGroupLayout, wgpu::BindGroup)>,
    /// (regenerate) The range of the film the decision pass writes (group 3 of its passes).
    film_range: Option<(wgpu::BindGroupLayout, wgpu::BindGroup)>,
}

impl<'a> Stages<'a> {
    /// The passes of `plan`'s graph, their pipelines built (or taken from the device's cache).
    pub(super) fn new(
        ctx: &GpuContext,
        plan: &Plan,
        b: &Bindings,
        accumulate: &'a Accumulate,
        opts: &WavefrontOptions,
        instrument: bool,
        memory: &mut MemoryLedger,
    ) -> Result<Stages<'a>> {
        let max_workgroups = ctx.device.limits().max_compute_workgroups_per_dimension;
        let graph = Graph::new(plan, opts, max_workgroups);
        let ray_sort =
            plan.ray_sort_cell_bits.is_some().then(|| ray_sort::buckets(ctx, memory)).transpose()?;
        let film_range = plan.regenerate.then(|| {
            let layout = ctx.bind_group_layout("film range", &[storage_entry(0, false)]);
            let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("film range"),
                layout: &layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: accumulate.range_buffer().as_entire_binding(),
                }],
            });
            (layout, group)
        });
        let mut s = Stages { graph, stages: vec![], accumulate, ray_sort, film_range };
        let mut modules = HashMap::new();
        for pass in &s.graph.passes {
            if pass.binds == Binds::Film {
                s.stages.push(None);
                continue;
            }
            let module = match modules.get(&pass.shader) {
                Some(m) => m,
                None => {
                    let (l, source) = source(pass.shader, plan, b, instrument);
                    let m = ctx.shader(l, source, b.shader_checks)?;
                    modules.entry(pass.shader).or_insert(m)
                }
            };
            let constants = pass_constants(pass, b, &s.graph);
            let layouts = s.layouts(pass, b);
            s.stages.push(Some(Stage::new(ctx, pass.label, module, &layouts, &constants)?));
        }
        Ok(s)
    }

    /// The bind-group layouts of a pass's `binds`.
    fn layouts<'b>(&'b self, pass: &Pass, b: &'b Bindings) -> Vec<&'b wgpu::BindGroupLayout> {
        let all = b.layouts();
        match pass.binds {
            Binds::Instrumented => all,
            Binds::State => all[..2].to_vec(),
            Binds::Indirect => vec![all[0], all[1], &b.state.indirect_layout],
            Binds::Decide => {
                let range = &self.film_range.as_ref().expect("regenerating").0;
                vec![all[0], all[1], &b.state.indirect_layout, range]
            }
            Binds::RaySort => vec![all[0], all[1], &self.ray_sort.as_ref().expect("--ray-sort").0],
            Binds::Film => vec![],
        }
    }

    /// Records the passes of `phase` (an iteration's: `i`, refilling or not, checking or not).
    pub(super) fn record(
        &self,
        wave: &mut WaveRecorder<'_>,
        phase: Phase,
        i: u32,
        refill: bool,
        check: bool,
    ) {
        for (pass, stage) in self.graph.passes.iter().zip(&self.stages) {
            if pass.phase == phase && (phase != Phase::Iteration || pass.runs(refill, check)) {
                self.record_pass(wave, pass, stage.as_ref(), i);
            }
        }
    }

    fn record_pass(&self, wave: &mut WaveRecorder<'_>, pass: &Pass, stage: Option<&Stage>, i: u32) {
        let b = wave.b;
        let indirect = |slot: u64| Workgroups::Indirect(&b.state.indirect, slot * 12);
        let wg = pass.constants.iter().find(|c| c.0 == "WORKGROUP_SIZE").map_or(1, |c| c.1 as u32);
        let workgroups = match pass.launch {
            Launch::Single => Workgroups::Direct(1),
            Launch::Queue(slot) => wave.consumer(slot),
            Launch::Indirect(slot) => indirect(slot),
            Launch::Direct(n) => Workgroups::Direct(n),
            Launch::Paths => {
                Workgroups::Direct(if b.regenerate { b.state.pool } else { wave.paths }.div_ceil(wg))
            }
            // (Accumulate records its own launch.)
            Launch::Pixels => Workgroups::Direct(0),
        };
        let bounce = pass.per_bounce.then_some(i);
        let mut g = b.groups(wave.offset);
        match pass.binds {
            Binds::Instrumented => {}
            Binds::State => g.truncate(2),
            Binds::Indirect => {
                g.truncate(2);
                g.push((&b.state.indirect_group, vec![]));
            }
            Binds::Decide => {
                g.truncate(2);
                g.push((&b.state.indirect_group, vec![]));
                g.push((&self.film_range.as_ref().expect("regenerating").1, vec![]));
            }
            Binds::RaySort => {
                g.truncate(2);
                g.push((&self.ray_sort.as_ref().expect("--ray-sort").1, vec![]));
            }
            Binds::Film => {
                if pass.label == label::ACCUMULATE {
                    let (offset, pixels) = (wave.offset, wave.pixels);
                    let (enc, timer) = wave.encoder();
                    self.accumulate.record(enc, timer, offset, pixels);
                    wave.dispatches += 1;
                    wave.compute_passes += 1;
                } else {
                    let (stage, groups) = self.accumulate.range_pass(wave.offset);
                    wave.record_groups(stage, None, &groups, workgroups);
                }
                return;
            }
        }
        wave.record_groups(stage.expect("a pipeline per pass"), bounce, &g, workgroups);
    }
}

/// A pass's pipeline constants: its own, the scene's where it takes them (a pattern's shade
/// pass replaces the scene's texture kinds with its own), then the graph's knobs.
fn pass_constants(pass: &Pass, b: &Bindings, graph: &Graph) -> Vec<(&'static str, f64)> {
    let own = |n: &str| pass.constants.iter().find(|c| c.0 == n).map(|c| c.1);
    let mut c: Vec<(&'static str, f64)> = if pass.scene_constants {
        b.scene.constants(&[]).into_iter().map(|(n, v)| (n, own(n).unwrap_or(v))).collect()
    } else {
        vec![]
    };
    let scene: Vec<&str> = c.iter().map(|x| x.0).collect();
    let mine: Vec<_> = pass.constants.iter().filter(|x| !scene.contains(&x.0)).copied().collect();
    c.splice(0..0, mine);
    c.extend(graph.constants.iter().copied());
    c
}

/// The label a shader's module is cached under and its source, in the variant of its hooks.
fn source(shader: Shader, plan: &Plan, b: &Bindings, instrument: bool) -> (&'static str, &'static str) {
    let hooked = b.hooks(instrument);
    match shader {
        Shader::Generate => (label::GENERATE, shaders::GENERATE.select(&hooked)),
        Shader::Intersect => (label::INTERSECT, shaders::INTERSECT.select(&hooked)),
        Shader::Shade => (label::SHADE, shaders::SHADE.select(&hooked)),
        Shader::Shadow => (label::SHADOW, shaders::SHADOW.select(&hooked)),
        Shader::Tail => (label::TAIL, shaders::TAIL.select(&hooked)),
        Shader::QueueSetup => (label::QUEUE_SETUP_INTERSECT, shaders::QUEUE_SETUP),
        Shader::CompactStates => (label::COMPACT_STATES_FIND, shaders::COMPACT_STATES),
        Shader::RaySort => (label::RAY_SORT_COUNT, shaders::RAY_SORT),
        Shader::Compact => {
            (label::COMPACT_SCAN, shaders::COMPACT.select(&[(Hook::ScanSubgroup, plan.subgroup_scan)]))
        }
        Shader::SlotSweep => {
            (label::SLOT_SWEEP, shaders::SLOT_SWEEP.select(&[(Hook::AppendSubgroup, b.subgroup_append)]))
        }
        Shader::Accumulate => unreachable!("the film's passes are built by Accumulate"),
    }
}
