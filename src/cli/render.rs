//! `wavetrace render`: one scene, one method, to EXR (+ PNG preview, + JSON report).

use crate::bvh::BvhLayout;
use crate::gpu::buffers::human_bytes;
use crate::gpu::memory::{GpuMemory, MemoryCategory};
use crate::gpu::timing::{TimeSource, Timing, Timings, FRAME_LABEL};
use crate::gpu::GpuContext;
use crate::gpu_state::GpuMonitor;
use crate::image_io::{self, RgbImage};
use crate::light_options::{LightOptions, LightSampling, LightSelect};
use crate::method;
use crate::numerics::{Fresnel, NumericOptions, RayOffset, SphereHit};
use crate::options::ShaderChecks;
use crate::options::Specialize;
use crate::options::{Compaction, MegakernelOptions, Method, MethodOptions, Schedule, WavefrontOptions};
use crate::progress::Progress;
use crate::render_space::RenderSpace;
use crate::report::RunReport;
use crate::scene::stress::StressTransform;
use crate::scene::Scene;
use crate::settings::{Accel, RenderSettings};
use crate::warmup::{self, TimedWarmup, WarmupPolicy};
use anyhow::{Context, Result};
use std::path::PathBuf;

const EXAMPLES: &str = "\
Examples:
  wavetrace render --scene rtiow-final --method megakernel --width 1200 --height 675 --spp 10 \\
      --out final.exr --png final.png
  wavetrace render --scene three-spheres --method cpu-f64 --spp 256 --out truth.exr
  wavetrace render --scene furnace --method megakernel --accel none --out f.exr --report f.json
  wavetrace render --scene experiments/scenes/mesh-room.json --method wavefront --bvh wide \
      --instrument --out w.exr --report w.json   # 8-wide compressed BVH: nodes, bytes per ray
  wavetrace render --scene cornell --method wavefront --nee on --width 300 --height 300 --spp 64 \
      --out cornell.exr --png cornell.png
  wavetrace render --scene two-lights --method cpu --nee on --light-select uniform --out before.exr
  wavetrace render --scene cornell --method wavefront --nee on --roulette on --out rr.exr \
      --report rr.json   # Russian roulette: shorter paths, fewer rays per sample, the same image
  wavetrace render --scene rtiow-final --method megakernel --schedule regenerate --instrument \
      --out regen.exr --report regen.json   # persistent threads: SIMD efficiency, memory
  wavetrace render --scene rtiow-final --method wavefront --schedule regenerate --tail megakernel \
      --refill-below 0.25 --compact-states on --out batched.exr --report batched.json  # Cycles-style refills
  wavetrace render --scene three-spheres --method cpu --scale 1e-4 --ray-offset robust \
      --out small.exr --report small.json   # the same image at 1/10000 the size: self-hits?
  wavetrace render --scene cornell --method megakernel --translate 1e5 --sphere-hit book \
      --fresnel exact --out far.exr";

#[derive(clap::Args, Debug)]
#[command(after_help = EXAMPLES)]
pub struct RenderArgs {
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
    /// Output EXR (linear RGB, f32).
    #[arg(long)]
    pub out: PathBuf,
    /// Also write an sRGB PNG preview.
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Also write a JSON record of the run.
    #[arg(long)]
    pub report: Option<PathBuf>,
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
    /// Untimed renders before the one that is timed and written: `auto` (GPU methods: until the
    /// GPU has worked 0.5 s and two frames agree within 5%, at most 50 frames or 10 s; CPU
    /// methods: none), or a number of frames (0: time a cold first frame).
    #[arg(long, default_value = "auto", value_parser = parse_warmup)]
    pub warmup: WarmupArg,
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

/// `--warmup`: `auto` or a number of frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WarmupArg {
    Auto,
    Frames(u32),
}

fn parse_warmup(s: &str) -> Result<WarmupArg, String> {
    match s {
        "auto" => Ok(WarmupArg::Auto),
        n => n
            .parse()
            .map(WarmupArg::Frames)
            .map_err(|_| format!("expected auto or a number of frames, got {n:?}")),
    }
}

pub fn run(a: RenderArgs) -> Result<()> {
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
    settings.validate().map_err(anyhow::Error::msg)?;
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
        preheat_seconds: a.preheat,
    };
    let gpu = if a.method.needs_gpu() { Some(GpuContext::new(a.adapter.as_deref())?) } else { None };

    let policy = match (a.warmup, a.method.needs_gpu()) {
        (WarmupArg::Frames(n), _) => WarmupPolicy::Frames(n),
        (WarmupArg::Auto, true) => WarmupPolicy::Timed(TimedWarmup::default()),
        (WarmupArg::Auto, false) => WarmupPolicy::Frames(0),
    };
    let monitor = gpu.as_ref().and_then(|g| GpuMonitor::open(&g.summary));
    let warm = warmup::warm_up(
        &policy,
        0.0,
        || {
            let o = method::render(a.method, &scene, &settings, &options, gpu.as_ref(), &|_| {})?;
            Ok((o.seconds(), o.preheat_seconds()))
        },
        || monitor.as_ref().map(GpuMonitor::sample),
    )?;
    if warm.frames > 0 {
        log::info!("warm-up: {} frames, {:.3} s, settled: {}", warm.frames, warm.seconds, warm.settled);
    }

    let progress = Progress::new(settings.sample_count(), &format!("{} {}", a.method.name(), scene.name));
    let out = method::render(a.method, &scene, &settings, &options, gpu.as_ref(), &|d| progress.set(d))?;
    progress.finish();

    let adapter = gpu.as_ref().map(|g| &g.summary);
    let options = options.resolve(a.method, adapter.map(|a| a.is_software()));
    let mut report = RunReport::new(&scene, a.method, &settings, adapter, &out);
    report.warmup = Some(warm);
    let image = RgbImage { width: settings.width, height: settings.height, data: out.film.mean_rgb() };
    image_io::write_exr(&a.out, &image, &report.exr_attributes())?;
    if let Some(png) = &a.png {
        image_io::write_png(png, &image)?;
    }
    if let Some(path) = &a.report {
        let json = serde_json::to_string_pretty(&report)?;
        image_io::write_file_atomically(path, json.as_bytes())
            .with_context(|| format!("writing report {}", path.display()))?;
    }

    print_summary(&report, &a.out);
    let f = &out.failures;
    println!(
        "numerics: ray offset {}, sphere hit {}, Fresnel {}, render space {}, scale {:e}, translate {:?}: {} self-hits, {} shadow self-hits, {} paths cut at depth {}",
        options.numerics.ray_offset.name(),
        options.numerics.sphere_hit.name(),
        options.numerics.fresnel.name(),
        options.numerics.render_space.name(),
        options.stress.scale,
        options.stress.translate,
        f.self_hits,
        f.shadow_self_hits,
        f.depth_cut,
        settings.max_depth
    );
    if let Some(m) = &report.memory {
        print_memory(m);
    }
    if let Some(t) = &out.timings {
        print_pass_table(t, &report);
    }
    Ok(())
}

fn print_summary(r: &RunReport, out: &std::path::Path) {
    let s = &r.settings;
    let gpu = match (r.gpu_seconds, r.frame_seconds, r.time_source) {
        (Some(g), Some(f), Some(TimeSource::Timestamps)) => format!(
            ", {f:.3} s frame with per-pass timestamps, which can slow it (--timing frame for the \
             unperturbed frame): {g:.3} s in passes, {:.3} s between passes, {:.3} s host gaps",
            r.between_passes_seconds.unwrap_or(0.0),
            r.host_gap_seconds.unwrap_or(0.0)
        ),
        (Some(_), Some(f), _) => format!(", {f:.3} s frame (wall clock: no timestamps, no time per pass)"),
        _ => String::new(),
    };
    println!(
        "{} {}x{} {} spp depth {} {}: {:.3} s wall{gpu}, {:.3} M samples/s, {:.3} M rays/s, {} NaN/Inf samples dropped -> {}",
        r.scene.name,
        s.width,
        s.height,
        s.spp,
        s.max_depth,
        r.method.name(),
        r.wall_seconds,
        r.samples_per_second / 1e6,
        r.rays_per_second / 1e6,
        r.invalid_samples,
        out.display()
    );
}

/// One line: the GPU memory the render took, peak first, then by category.
fn print_memory(m: &GpuMemory) {
    let parts: Vec<String> = MemoryCategory::ALL
        .iter()
        .filter_map(|c| {
            Some(format!("{} {}", c.key().replace('_', " "), human_bytes(*m.by_category.get(c.key())?)))
        })
        .collect();
    println!(
        "GPU memory: {} peak, {} held ({})",
        human_bytes(m.peak),
        human_bytes(m.total),
        parts.join(", ")
    );
}

/// pbrt-v4-style kernel profile: one row per pass label, with SIMD efficiency where measured;
/// then the bounce histogram of queue sizes.
pub fn print_pass_table(t: &Timings, r: &RunReport) {
    let total = t.total_seconds();
    println!("{:<24} {:>11} {:>8} {:>7} {:>6}", "pass", "GPU ms", "passes", "share", "SIMD");
    for (label, p) in &t.passes {
        let simd = r
            .simd
            .as_ref()
            .and_then(|s| s.get(*label))
            .map_or(String::new(), |e| format!("{:.1}%", 100.0 * e.efficiency));
        if !t.per_pass() && *label != FRAME_LABEL {
            // Without timestamps a pass has no time of its own: counted, not timed.
            println!("{label:<24} {:>11} {:>8} {:>7} {simd:>6}", "–", p.passes, "–");
            continue;
        }
        let share = if total > 0.0 { 100.0 * p.seconds / total } else { 0.0 };
        println!("{label:<24} {:>11.3} {:>8} {share:>6.1}% {simd:>6}", p.seconds * 1e3, p.passes);
    }
    if let Some(simd) = &r.simd {
        for (point, e) in simd.iter().filter(|(k, _)| !t.passes.contains_key(k.as_str())) {
            println!("{point:<24} {:>11} {:>8} {:>7} {:>5.1}%", "", "", "", 100.0 * e.efficiency);
        }
    }
    if let Some(c) = r.coherence.as_ref().filter(|c| !c.is_empty()) {
        // Issue 26: how scattered the intersect pass's subgroups are, by iteration.
        println!(
            "{:<24} {:>11} {:>8} {:>9} {:>12} {:>8}",
            "intersect coherence", "subgroups", "lanes", "lines", "pixel spread", "octants"
        );
        for b in c {
            println!(
                "  from iteration {:<7} {:>11} {:>8.2} {:>9.2} {:>12.1} {:>8.2}",
                b.first_iteration, b.subgroups, b.lanes, b.lines, b.pixel_spread, b.octants
            );
        }
    }
    if let Some(h) = &r.queue_histogram {
        // The shadow column only with --nee on in a scene with lights.
        let shadow = !h.shadow.is_empty();
        let shadow_head = if shadow { format!(" {:>12}", "shadow") } else { String::new() };
        println!(
            "bounce {:>12} {:>12} {:>12} {:>12} {:>12}{shadow_head}",
            "rays", "lambertian", "metal", "dielectric", "emissive"
        );
        for (b, rays) in h.rays.iter().enumerate() {
            let m = |k: usize| h.materials[k].get(b).copied().unwrap_or(0);
            let s = if shadow {
                format!(" {:>12}", h.shadow.get(b).copied().unwrap_or(0))
            } else {
                String::new()
            };
            println!("{b:>6} {rays:>12} {:>12} {:>12} {:>12} {:>12}{s}", m(0), m(1), m(2), m(3));
        }
    }
}
