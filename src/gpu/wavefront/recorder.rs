//! What every pass records into: the bindings a render's passes share, and the recorder of a
//! share (its encoder, its open compute pass, its dispatch parameters and its counts).

use super::super::context::GpuContext;
use super::super::instrument::SimdCounters;
use super::super::scene_buffers::SceneBuffers;
use super::super::shaders::Hook;
use super::super::stage::{Stage, Workgroups};
use super::super::timing::GpuTimer;
use super::path_state::PathState;
use anyhow::Result;

/// The GPU objects every stage binds: scene (group 0), path state (group 1), SIMD counters
/// (group 2, with `--instrument`).
pub struct Bindings {
    pub scene: SceneBuffers,
    pub state: PathState,
    pub simd: Option<SimdCounters>,
    /// `--schedule regenerate`.
    pub regenerate: bool,
    /// Whether passes use the shader variants with subgroup-aggregated appends (`--append`).
    pub subgroup_append: bool,
    /// The runtime checks the passes' shaders are compiled with (`--shader-checks`).
    pub shader_checks: crate::options::ShaderChecks,
}

impl Bindings {
    /// The scene's buffers (its `frame` uniform), the pool `plan` sizes, and the SIMD counters
    /// with `--instrument`.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        ctx: &GpuContext,
        scene: &crate::packed_scene::PackedScene,
        frame: &crate::layout::FrameUniform,
        settings: &crate::settings::RenderSettings,
        plan: &super::plan::Plan,
        measure: super::super::timing::Measure,
        params: &super::super::dispatch_plan::DispatchUniforms,
        memory: &mut super::super::memory::MemoryLedger,
    ) -> Result<Self> {
        let (pool, layout) = (plan.pool, plan.layout);
        Ok(Bindings {
            scene: SceneBuffers::new(ctx, scene, frame, settings, measure.specialize, memory)?,
            state: PathState::new(ctx, pool, plan.wave, params, plan.stats_bounces, layout, memory)?,
            simd: measure.instrument.then(|| SimdCounters::new(ctx, memory)).transpose()?,
            regenerate: plan.regenerate,
            subgroup_append: plan.subgroup_append,
            shader_checks: measure.shader_checks,
        })
    }

    /// The shader variant an appending pass takes: instrumented or not, and its appends.
    pub fn hooks(&self, instrument: bool) -> [(Hook, bool); 2] {
        [(Hook::Instrument, instrument), (Hook::AppendSubgroup, self.subgroup_append)]
    }

    pub fn layouts(&self) -> Vec<&wgpu::BindGroupLayout> {
        let mut l = vec![&self.scene.layout, &self.state.layout];
        l.extend(self.simd.as_ref().map(|s| &s.layout));
        l
    }

    /// Bind groups with the dynamic offset of the wave's dispatch parameters.
    pub fn groups(&self, offset: u32) -> Vec<(&wgpu::BindGroup, Vec<u32>)> {
        let mut g = vec![(&self.scene.bind_group, vec![]), (&self.state.bind_group, vec![offset])];
        g.extend(self.simd.as_ref().map(|s| (&s.bind_group, vec![])));
        g
    }
}

/// What every pass of a wave records into: the open encoder (and, with `--compute-passes
/// shared`, the open compute pass), the timer, the bindings and the wave's dispatch parameters.
pub struct WaveRecorder<'a> {
    /// The compute pass consecutive dispatches share (`--compute-passes shared`, without per-pass
    /// timestamps); ended before anything else is recorded into `enc`.
    pass: Option<wgpu::ComputePass<'static>>,
    /// Whether dispatches share passes.
    shared: bool,
    enc: wgpu::CommandEncoder,
    pub timer: &'a mut GpuTimer,
    pub b: &'a Bindings,
    /// Dynamic offset of the wave's `Dispatch` parameters.
    pub offset: u32,
    /// Paths in this wave.
    pub paths: u32,
    /// Pixels of this share (its film accumulation's threads).
    pub pixels: u32,
    /// Whether passes are timed per bounce (waves) or only per label (regenerating: an
    /// iteration holds paths at every bounce).
    pub per_bounce: bool,
    /// Passes recorded (compute dispatches, empty ones included).
    pub dispatches: u64,
    /// Compute passes opened: `dispatches` with a pass per dispatch, fewer when they share.
    pub compute_passes: u64,
    /// `--launch pool`: the workgroups that cover the pool's slots (a wave's paths), which the
    /// passes consuming a queue are launched with instead of their indirect arguments.
    pub pool_launch: Option<u32>,
}

impl<'a> WaveRecorder<'a> {
    /// A share's recorder: `shared` compute passes or a pass per dispatch, the share's
    /// `offset` into the dispatch parameters and the `share` itself (its paths and pixels), and the workgroups of a pool-size
    /// launch (`--launch pool`). Passes are timed per bounce in waves, per label regenerating
    /// (an iteration holds paths at every bounce).
    pub fn new(
        ctx: &GpuContext,
        shared: bool,
        timer: &'a mut GpuTimer,
        b: &'a Bindings,
        offset: u32,
        share: &crate::layout::DispatchParams,
        pool_launch: Option<u32>,
    ) -> Self {
        WaveRecorder {
            pass: None,
            shared,
            enc: ctx.device.create_command_encoder(&Default::default()),
            timer,
            b,
            offset,
            paths: share.pixel_count * share.sample_count,
            pixels: share.pixel_count,
            per_bounce: !b.regenerate,
            dispatches: 0,
            compute_passes: 0,
            pool_launch,
        }
    }

    /// The launch of a pass that consumes a queue: at the pool's size (`--launch pool`), or the
    /// indirect arguments a setup pass wrote at argument slot `slot`.
    pub fn consumer(&self, slot: u64) -> Workgroups<'a> {
        let b: &'a Bindings = self.b;
        match self.pool_launch {
            Some(groups) => Workgroups::Direct(groups),
            None => Workgroups::Indirect(&b.state.indirect, slot * 12),
        }
    }
}

impl WaveRecorder<'_> {
    /// Records `stage` as a timed pass with the wave's first `groups` bind groups.
    pub fn record(&mut self, stage: &Stage, bounce: Option<u32>, groups: usize, workgroups: Workgroups<'_>) {
        self.record_with(stage, bounce, groups, None, workgroups);
    }

    /// [`Self::record`], with `extra` bound after the first `groups` bind groups.
    pub fn record_with(
        &mut self,
        stage: &Stage,
        bounce: Option<u32>,
        groups: usize,
        extra: Option<(&wgpu::BindGroup, Vec<u32>)>,
        workgroups: Workgroups<'_>,
    ) {
        let b = self.b;
        let mut g = b.groups(self.offset);
        g.truncate(groups);
        g.extend(extra);
        self.record_groups(stage, bounce, &g, workgroups);
    }

    /// Records `stage` as a timed pass with the bind groups `g` (group i: `g[i]`).
    pub fn record_groups(
        &mut self,
        stage: &Stage,
        bounce: Option<u32>,
        g: &[(&wgpu::BindGroup, Vec<u32>)],
        workgroups: Workgroups<'_>,
    ) {
        let bounce = bounce.filter(|_| self.per_bounce);
        self.dispatches += 1;
        if !self.shared {
            stage.record(&mut self.enc, self.timer, bounce, g, workgroups);
            self.compute_passes += 1;
            return;
        }
        // Counted under its label (there are no timestamps to write: `shared` is off with them).
        let writes = self.timer.pass_at(stage.label, bounce);
        debug_assert!(writes.is_none(), "shared compute passes without per-pass timestamps only");
        if self.pass.is_none() {
            let pass = self.enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("wavefront (shared)"),
                timestamp_writes: None,
            });
            self.pass = Some(pass.forget_lifetime());
            self.compute_passes += 1;
        }
        stage.dispatch(self.pass.as_mut().expect("opened above"), g, workgroups);
    }

    /// The encoder, for copies and passes of other recorders: ends the shared compute pass.
    pub fn encoder(&mut self) -> (&mut wgpu::CommandEncoder, &mut GpuTimer) {
        self.pass = None;
        (&mut self.enc, self.timer)
    }

    /// Submits what is recorded and opens a new encoder, without waiting where passes are not
    /// timed (their timestamps are read back per batch, so then it waits).
    pub fn submit(&mut self, ctx: &GpuContext) -> Result<()> {
        self.submit_ahead(ctx).map(|_| ())
    }

    /// [`Self::submit`], giving the submission's index where it did not wait (None: per-pass
    /// timestamps, read back per batch, so it waited).
    pub fn submit_ahead(&mut self, ctx: &GpuContext) -> Result<Option<wgpu::SubmissionIndex>> {
        if self.timer.times_passes() {
            self.submit_and_wait(ctx)?;
            return Ok(None);
        }
        self.pass = None;
        let enc = std::mem::replace(&mut self.enc, ctx.device.create_command_encoder(&Default::default()));
        self.timer.submit(ctx, enc).map(Some)
    }

    /// Submits what is recorded, waits for it (adding its pass times) and opens a new encoder.
    pub fn submit_and_wait(&mut self, ctx: &GpuContext) -> Result<()> {
        self.pass = None;
        let enc = std::mem::replace(&mut self.enc, ctx.device.create_command_encoder(&Default::default()));
        self.timer.submit_batch(ctx, enc)
    }
}
