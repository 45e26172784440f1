//! The flags that state a render job — scene, size, samples, method and every method option —
//! declared once for every command that renders or plans one (`render`, `plan`), and built into
//! the library's settings and options in one place.

use crate::bvh::collapse::Collapse;
use crate::bvh::stack::BvhStack;
use crate::bvh::BvhLayout;
use crate::light_options::{LightOptions, LightSampling, LightSelect};
use crate::numerics::{Fresnel, NumericOptions, RayOffset, SphereHit};
use crate::options::{
    Compaction, MegakernelOptions, Method, MethodOptions, Schedule, ShaderChecks, Specialize, Timing,
    WavefrontOptions,
};
use crate::render_space::RenderSpace;
use crate::scene::stress::StressTransform;
use crate::scene::Scene;
use crate::settings::{Accel, RenderSettings};
use anyhow::Result;

#[derive(clap::Args, Debug)]
pub struct JobArgs {
    /// Built-in scene name (`wavetrace scene list`) or path to a scene file: JSON, or glTF 2.0
    /// (`.gltf`, `.glb`).
    #[arg(long)]
    pub scene: String,
    /// The renderer: the CPU reference (`cpu`, `cpu-f64`: the ground truth), or a GPU method.
    #[arg(long, value_enum, default_value_t = Method::Megakernel)]
    pub method: Method,
    /// Image width in pixels.
    #[arg(long, default_value_t = 400)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 225)]
    pub height: u32,
    /// Samples per pixel.
    #[arg(long, default_value_t = 16)]
    pub spp: u32,
    /// Longest path, in rays (the book's max_depth).
    #[arg(long, default_value_t = 50)]
    pub max_depth: u32,
    /// Seed of the counter-based RNG: same seed, same paths, on every method.
    #[arg(long, default_value_t = 0)]
    pub seed: u32,
    /// `none` tests every primitive for every ray, as the seeds did.
    #[arg(long, value_enum, default_value_t = Accel::Bvh, help_heading = "Numerics and stress", hide_short_help = true)]
    pub accel: Accel,
    /// Every method: the BVH's node layout (`binary`: 32-byte nodes each with its own box;
    /// `aila-laine`: both child boxes in the parent, 64-byte nodes; `wide`: 8-wide compressed,
    /// CWBVH-style, 80-byte nodes). The films are the same; the cost differs.
    #[arg(long, value_enum, default_value_t = BvhLayout::Binary, help_heading = "Numerics and stress", hide_short_help = true)]
    pub bvh: BvhLayout,
    /// With `--bvh wide`: how the binary build is collapsed into 8-wide nodes (`sah`:
    /// SAH-optimal by dynamic programming, Ylitie et al. 2017; `greedy`: tinybvh's rule, a node
    /// adopts its largest child's children while they fit). The films are the same.
    #[arg(long, value_enum, default_value_t = Collapse::default(), help_heading = "Numerics and stress", hide_short_help = true)]
    pub collapse: Collapse,
    /// GPU methods: where the BVH traversal keeps its stack (`function`: 64 entries a thread
    /// in function memory; `workgroup`: 8 entries a thread in workgroup memory, deeper ones
    /// spilled to function memory). The films are the same; the cost differs by device.
    #[arg(long, value_enum, default_value_t = BvhStack::default(), help_heading = "Numerics and stress", hide_short_help = true)]
    pub stack: BvhStack,
    /// Next-event estimation: at each diffuse hit, a shadow ray to a point sampled on an
    /// emitter (`off`: lights are found only by bounced rays, as in the book). Both converge
    /// to the same image.
    #[arg(long, value_enum, default_value_t = OnOff::Off)]
    pub nee: OnOff,
    /// Russian roulette, pbrt-v4's rule: from the second hit on, a path whose throughput has
    /// fallen below 1 ends with probability 1 − its largest component, and a survivor is
    /// weighted up to match (`off`: every path runs to --max-depth or escape, as in the book).
    /// Both converge to the same image; `on` traces shorter paths.
    #[arg(long, value_enum, default_value_t = OnOff::Off)]
    pub roulette: OnOff,
    /// With --nee on: how a point is sampled on the chosen light. `solid-angle` samples a sphere
    /// seen from outside uniformly over the cone it subtends (none of its samples land on the
    /// hidden far side); `area`, uniformly by area (the earlier behaviour). Quads and triangles
    /// are sampled by area either way.
    #[arg(long, value_enum, default_value_t = LightSampling::SolidAngle, help_heading = "Lights (with --nee on)", hide_short_help = true)]
    pub light_sampling: LightSampling,
    /// With --nee on: how the light is chosen: in proportion to its emitted power (mean radiance
    /// × area), or `uniform`ly per emitting primitive (the earlier behaviour).
    #[arg(long, value_enum, default_value_t = LightSelect::Power, help_heading = "Lights (with --nee on)", hide_short_help = true)]
    pub light_select: LightSelect,
    /// How secondary and shadow rays leave a surface: `tmin` ignores hits nearer than the
    /// book's 1e-3 (`tmin=VALUE`: nearer than VALUE); `robust` moves the origin off the surface
    /// by a bound on the hit point's rounding error (pbrt-v4) and keeps every hit at t > 0.
    #[arg(long, default_value = "tmin", value_parser = RayOffset::parse, help_heading = "Numerics and stress", hide_short_help = true)]
    pub ray_offset: RayOffset,
    /// Ray–sphere intersection: the book's quadratic, or the numerically stable form (Ray
    /// Tracing Gems ch. 7).
    #[arg(long, value_enum, default_value_t = SphereHit::Stable, help_heading = "Numerics and stress", hide_short_help = true)]
    pub sphere_hit: SphereHit,
    /// Reflectance of glass: the book's Schlick approximation, or the exact Fresnel equations.
    #[arg(long, value_enum, default_value_t = Fresnel::Schlick, help_heading = "Numerics and stress", hide_short_help = true)]
    pub fresnel: Fresnel,
    /// Where the scene is rendered: moved in f64 so the camera is at the origin before it is
    /// stored in f32 (`camera`), or in its own coordinates (`world`). cpu-f64 always renders in
    /// camera space.
    #[arg(long, value_enum, default_value_t = RenderSpace::Camera, help_heading = "Numerics and stress", hide_short_help = true)]
    pub render_space: RenderSpace,
    /// Stress transform: scale the scene (geometry, camera, textures) about the origin by S > 0.
    /// The image is the same in exact arithmetic; what changes is numerical error.
    #[arg(long, default_value_t = 1.0, value_parser = StressTransform::parse_scale, help_heading = "Numerics and stress", hide_short_help = true)]
    pub scale: f64,
    /// Stress transform: then move it by X,Y,Z (or D for D,D,D).
    #[arg(long, default_value = "0,0,0", value_parser = StressTransform::parse_translate, help_heading = "Numerics and stress", hide_short_help = true)]
    pub translate: [f64; 3],
    /// Use the adapter whose name contains this (case-insensitive); see `wavetrace info`.
    #[arg(long)]
    pub adapter: Option<String>,
    /// Threads per workgroup for GPU methods.
    #[arg(long, default_value_t = MegakernelOptions::default().workgroup_size, help_heading = "GPU methods", hide_short_help = true)]
    pub workgroup_size: u32,
    /// Wavefront: keep queues dense (`off`: every pass runs over the whole pool).
    #[arg(long, value_enum, default_value_t = OnOff::On, help_heading = "Wavefront", hide_short_help = true)]
    pub compaction: OnOff,
    /// Wavefront: how compaction builds queues.
    #[arg(long, value_enum, default_value_t = CompactionMethod::Atomic, help_heading = "Wavefront", hide_short_help = true)]
    pub compaction_method: CompactionMethod,
    /// GPU methods: paths that start together, each thread or slot idling once its path ends
    /// (`waves`: the wavefront's waves, the megakernel's one path per thread), or threads and
    /// slots that take the next sample as soon as their path ends (`regenerate`). `auto`: what
    /// measured faster, the wavefront regenerating with --tail megakernel on a GPU and in waves
    /// on a software adapter, the megakernel in waves.
    #[arg(long, value_enum, default_value_t = Schedule::Auto)]
    pub schedule: Schedule,
    /// GPU methods: count SIMD efficiency per pass with subgroup operations (adds atomics: use
    /// separate runs for timing).
    #[arg(long, help_heading = "GPU methods", hide_short_help = true)]
    pub instrument: bool,
    /// GPU methods: timestamps around every pass (time per pass), or the host clock per
    /// submission only (`frame`: what the per-pass instrument costs shows as the difference).
    #[arg(long, value_enum, default_value_t = Timing::Passes, help_heading = "GPU methods", hide_short_help = true)]
    pub timing: Timing,
    /// GPU methods: compile the shaders with wgpu's runtime checks (bounds checks, bounded loops)
    /// or without them (`unchecked`: what the checks cost; the films are the same).
    #[arg(long, value_enum, default_value_t = ShaderChecks::Checked, help_heading = "GPU methods", hide_short_help = true)]
    pub shader_checks: ShaderChecks,
    /// GPU methods: compile the shaders with only the primitive, material and texture kinds the
    /// scene has (`scene`), or with every kind (`none`: the unspecialized baseline; the films are
    /// the same).
    #[arg(long, value_enum, default_value_t = Specialize::Scene, help_heading = "GPU methods", hide_short_help = true)]
    pub specialize: Specialize,
    /// GPU methods: seconds of busy GPU work just before each frame (warm-up and timed), so the
    /// frame starts at the clocks continuous rendering holds rather than those of a GPU idled by
    /// the host's setup (0: none; never on a software adapter).
    #[arg(long, default_value_t = crate::options::DEFAULT_PREHEAT_SECONDS, value_name = "SECONDS", value_parser = parse_preheat, help_heading = "GPU methods", hide_short_help = true)]
    pub preheat: f64,
    // Last: a flattened struct's help heading carries over to the fields after it.
    /// The megakernel's own flags (`options::MegakernelOptions`).
    #[command(flatten)]
    pub megakernel: MegakernelOptions,
    /// The wavefront's own flags (`options::WavefrontOptions`).
    #[command(flatten)]
    pub wavefront: WavefrontOptions,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum OnOff {
    On,
    Off,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum CompactionMethod {
    /// Atomic append to each queue.
    Atomic,
    /// Stable prefix-sum scan over the pool.
    Scan,
}

impl CompactionMethod {
    /// The queues `--compaction on|off` and `--compaction-method` ask for together.
    pub fn with(self, on: OnOff) -> Compaction {
        match (on, self) {
            (OnOff::Off, _) => Compaction::Off,
            (OnOff::On, CompactionMethod::Atomic) => Compaction::Atomic,
            (OnOff::On, CompactionMethod::Scan) => Compaction::Scan,
        }
    }
}

/// `--preheat`: seconds in `0..=gpu::preheat::MAX_SECONDS`.
fn parse_preheat(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|_| format!("expected seconds (a number), got {s:?}"))?;
    crate::options::check_preheat(v)?;
    Ok(v)
}

impl JobArgs {
    /// The scene (resolved and loaded), the settings and the method options the flags state
    /// (the settings are validated where they are rendered or planned, once).
    pub fn build(&self) -> Result<(Scene, RenderSettings, MethodOptions)> {
        let a = self;
        let scene = Scene::resolve(&a.scene)?;
        let settings = RenderSettings {
            width: a.width,
            height: a.height,
            spp: a.spp,
            max_depth: a.max_depth,
            seed: a.seed,
            accel: a.accel,
            nee: a.nee == OnOff::On,
            roulette: a.roulette == OnOff::On,
        };
        let compaction = a.compaction_method.with(a.compaction);
        let options = MethodOptions {
            lights: LightOptions { sampling: a.light_sampling, select: a.light_select },
            numerics: NumericOptions {
                ray_offset: a.ray_offset,
                sphere_hit: a.sphere_hit,
                fresnel: a.fresnel,
                render_space: a.render_space,
            },
            stress: StressTransform { scale: a.scale, translate: a.translate },
            megakernel: MegakernelOptions {
                workgroup_size: a.workgroup_size,
                schedule: a.schedule,
                ..a.megakernel
            },
            wavefront: WavefrontOptions {
                workgroup_size: a.workgroup_size,
                compaction,
                schedule: a.schedule,
                ..a.wavefront
            },
            instrument: a.instrument,
            timing: a.timing,
            shader_checks: a.shader_checks,
            specialize: a.specialize,
            bvh: a.bvh,
            collapse: a.collapse,
            stack: a.stack,
            preheat_seconds: a.preheat,
        };
        Ok((scene, settings, options))
    }
}
