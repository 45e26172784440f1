//! One pass of the wavefront's pass graph ([`super::graph`]): its label, when it runs, its
//! shader and pipeline constants, its launch, the bind groups it takes and the queues it
//! consumes and produces. Each stage's file states its passes with these.

use serde::Serialize;

/// Where in a share a pass runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Phase {
    /// Once at a share's start.
    Start,
    /// In every iteration (a bounce in waves), subject to [`When`].
    Iteration,
    /// (regenerate) After an iteration that ends with the decision pass: the passes it sizes.
    Decided,
    /// Once at a wave's end.
    End,
}

/// Which iterations a pass of [`Phase::Iteration`] runs in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum When {
    Always,
    /// (regenerate) The iterations that refill the pool: the first, and every one unless the
    /// first refill starts every sample.
    Refill,
    /// (regenerate) The iterations that end with the schedule's decision (every one with the
    /// tail, else every `--sync-every`).
    Check,
    /// The iterations that do not.
    NoCheck,
}

/// How a pass is launched.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case", tag = "kind", content = "slot")]
pub enum Launch {
    /// One thread: a setup pass that writes indirect arguments from queue counters.
    Single,
    /// Over a queue: the indirect arguments at this slot, or the pool's size with
    /// `--launch pool` (threads past the queue return).
    Queue(u64),
    /// The indirect arguments at this slot, always.
    Indirect(u64),
    /// A fixed number of workgroups.
    Direct(u32),
    /// A thread per path of the share (waves) or slot of the pool (regenerate).
    Paths,
    /// A thread per pixel of the share.
    Pixels,
}

/// The bind groups a pass takes after the scene (0) and the path state (1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Binds {
    /// Scene and path state.
    State,
    /// And the SIMD counters with `--instrument`.
    Instrumented,
    /// And the indirect arguments (setup passes).
    Indirect,
    /// And the indirect arguments and the film range (the decision pass).
    Decide,
    /// And the ray sort's buckets.
    RaySort,
    /// The film accumulation's own group.
    Film,
}

/// The WGSL file a pass's pipeline comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Shader {
    Generate,
    QueueSetup,
    CompactStates,
    RaySort,
    Intersect,
    Compact,
    Shade,
    SlotSweep,
    Shadow,
    Tail,
    Accumulate,
}

impl Shader {
    /// The file under `shaders/`.
    pub fn file(self) -> &'static str {
        match self {
            Shader::Generate => "wavefront/generate.wgsl",
            Shader::QueueSetup => "wavefront/queue_setup.wgsl",
            Shader::CompactStates => "wavefront/compact_states.wgsl",
            Shader::RaySort => "wavefront/ray_sort.wgsl",
            Shader::Intersect => "wavefront/intersect.wgsl",
            Shader::Compact => "wavefront/compact.wgsl",
            Shader::Shade => "wavefront/shade.wgsl",
            Shader::SlotSweep => "wavefront/slot_sweep.wgsl",
            Shader::Shadow => "wavefront/shadow.wgsl",
            Shader::Tail => "wavefront/tail.wgsl",
            Shader::Accumulate => "accumulate.wgsl",
        }
    }
}

/// The path queues passes consume and produce.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Queue {
    /// The ray queue of this iteration (and the next's, produced).
    Rays,
    /// The material queues (one with `--shade single`).
    Materials,
    /// A costly pattern's queue (`--shade per-texture`).
    Patterns,
    Shadow,
    /// (regenerate) The slots whose path ended.
    Free,
    /// Every slot of the pool.
    Slots,
    /// The finished samples of the sample ring, or the wave's radiance.
    Samples,
}

/// One pass of the graph.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Pass {
    pub label: &'static str,
    pub phase: Phase,
    pub when: When,
    pub shader: Shader,
    pub launch: Launch,
    pub binds: Binds,
    /// The pass's own pipeline constants (the graph's [`Graph::constants`] and the scene's are
    /// added to every pass over the path state).
    #[serde(serialize_with = "as_map")]
    pub constants: Vec<(&'static str, f64)>,
    /// Whether it takes the scene's specialization constants (`PRIM_KINDS`, ...).
    pub scene_constants: bool,
    /// Timed per bounce in waves (not the share's start, the tail or accumulation).
    pub per_bounce: bool,
    pub consumes: Vec<Queue>,
    pub produces: Vec<Queue>,
}

impl Pass {
    /// A pass of `phase` with no constants or queues yet, run always, timed per bounce in an
    /// iteration.
    pub(super) fn new(
        label: &'static str,
        phase: Phase,
        shader: Shader,
        launch: Launch,
        binds: Binds,
    ) -> Self {
        Pass {
            label,
            phase,
            when: When::Always,
            shader,
            launch,
            binds,
            constants: vec![],
            scene_constants: false,
            per_bounce: phase == Phase::Iteration,
            consumes: vec![],
            produces: vec![],
        }
    }

    /// A pass of an iteration over a queue or the pool, with the scene's constants, the
    /// instrument counters and a workgroup size.
    pub(super) fn over_paths(label: &'static str, shader: Shader, launch: Launch, c: &Constants) -> Self {
        Pass::new(label, Phase::Iteration, shader, launch, Binds::Instrumented).with(&[c.workgroup]).scene()
    }

    pub(super) fn when(mut self, w: When) -> Self {
        self.when = w;
        self
    }

    pub(super) fn with(mut self, constants: &[(&'static str, f64)]) -> Self {
        self.constants.extend_from_slice(constants);
        self
    }

    pub(super) fn scene(mut self) -> Self {
        self.scene_constants = true;
        self
    }

    pub(super) fn binds(mut self, binds: Binds) -> Self {
        self.binds = binds;
        self
    }

    /// Timed as a whole, not per bounce.
    pub(super) fn unbounced(mut self) -> Self {
        self.per_bounce = false;
        self
    }

    pub(super) fn queues(mut self, consumes: &[Queue], produces: &[Queue]) -> Self {
        self.consumes = consumes.to_vec();
        self.produces = produces.to_vec();
        self
    }

    /// Whether it runs in an iteration that refills (`refill`) and decides (`check`).
    pub fn runs(&self, refill: bool, check: bool) -> bool {
        match self.when {
            When::Always => true,
            When::Refill => refill,
            When::Check => check,
            When::NoCheck => !check,
        }
    }
}

/// The constants many passes share.
pub(super) struct Constants {
    pub(super) workgroup: (&'static str, f64),
    pub(super) stats_bounces: (&'static str, f64),
    /// A setup pass's: the workgroup size, the histogram's rows and the device's limit it
    /// clamps indirect arguments to.
    pub(super) setup: [(&'static str, f64); 3],
}

/// Pipeline constants as a JSON object, name to value.
pub(super) fn as_map<S: serde::Serializer>(c: &[(&'static str, f64)], s: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeMap;
    let mut m = s.serialize_map(Some(c.len()))?;
    for (n, v) in c {
        m.serialize_entry(n, v)?;
    }
    m.end()
}
