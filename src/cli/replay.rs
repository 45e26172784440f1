//! `wavetrace replay`: the lockstep SIMD replay (src/replay/) of a frame at several widths, on the
//! CPU, for each GPU method: work-weighted efficiency per block and pass, the frame's warp
//! execution efficiency and the subgroup-iterations an ideal W-lane machine issues.

use super::job::{CompactionMethod, OnOff};
use crate::chart::{LineChart, Series};
use crate::gpu::instrument::FRAME_KEY;
use crate::gpu::megakernel::{MegakernelOptions, DEFAULT_THREADS_DISCRETE};
use crate::gpu::wavefront::{Compaction, Tail, WavefrontOptions, DEFAULT_POOL};
use crate::options::Named;
use crate::options::{PoolSize, Schedule};
use crate::packed_scene::PackedScene;
use crate::replay::lockstep::SlotCounts;
use crate::replay::{megakernel, regenerate, wavefront, width, ReplayJob};
use crate::scene::Scene;
use crate::settings::{Accel, RenderSettings};
use anyhow::{anyhow, bail, Result};
use std::time::Instant;

/// The methods the replay groups lanes as.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ReplayMethod {
    /// The naive megakernel: one thread per sample (`--method megakernel --schedule waves`).
    Megakernel,
    /// The regenerating megakernel: persistent threads (`--method megakernel --schedule regenerate`).
    Regenerate,
    /// The wavefront, per pass (`--method wavefront --schedule waves`).
    Wavefront,
    /// The regenerating wavefront, per pass (`--method wavefront --schedule regenerate`).
    WavefrontRegenerate,
}

impl ReplayMethod {
    /// The label charts give it (short, so the legend needs one line for it).
    fn label(self) -> &'static str {
        match self {
            ReplayMethod::Megakernel => "megakernel (naive)",
            ReplayMethod::Regenerate => "megakernel (regen.)",
            ReplayMethod::Wavefront => "wavefront (waves)",
            ReplayMethod::WavefrontRegenerate => "wavefront (regen.)",
        }
    }

    fn name(self) -> &'static str {
        match self {
            ReplayMethod::Megakernel => "megakernel",
            ReplayMethod::Regenerate => "regenerate",
            ReplayMethod::Wavefront => "wavefront",
            ReplayMethod::WavefrontRegenerate => "wavefront-regenerate",
        }
    }
}

#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  wavetrace replay --scene rtiow-final --width 160 --height 90 --spp 64 --simd-width 8,16,32,64\n  \
                  wavetrace replay --scene cornell --nee on --width 100 --height 100 --spp 64 --methods wavefront-regenerate --pool-size 4096 --tail megakernel\n  \
                  wavetrace replay --scene spheres-8 --accel none --width 800 --height 600 --spp 16 --methods megakernel,wavefront --pool-size 65536 --every 4"
)]
pub struct ReplayArgs {
    /// Built-in scene name or path to a scene file (JSON, `.gltf`, `.glb`).
    #[arg(long)]
    pub scene: String,
    #[arg(long, default_value_t = 160)]
    pub width: u32,
    #[arg(long, default_value_t = 90)]
    pub height: u32,
    #[arg(long, default_value_t = 16)]
    pub spp: u32,
    #[arg(long, default_value_t = 50)]
    pub max_depth: u32,
    #[arg(long, default_value_t = 0)]
    pub seed: u32,
    #[arg(long, value_enum, default_value_t = OnOff::Off)]
    pub nee: OnOff,
    /// Russian roulette (pbrt-v4's rule), as `wavetrace render --roulette`: shorter paths.
    #[arg(long, value_enum, default_value_t = OnOff::Off)]
    pub roulette: OnOff,
    /// `none`: every primitive tested in one loop, as the seeds' CUDA ports did (at most 24).
    #[arg(long, value_enum, default_value_t = Accel::Bvh)]
    pub accel: Accel,
    /// The BVH layout the paths traverse, as `wavetrace render --bvh`: the traversal loop's
    /// steps, hence its lockstep efficiency, are the layout's.
    #[arg(long, value_enum, default_value_t = crate::bvh::BvhLayout::Binary)]
    pub bvh: crate::bvh::BvhLayout,
    /// With `--bvh wide`: the collapse, as `wavetrace render --collapse`.
    #[arg(long, value_enum, default_value_t = crate::bvh::collapse::Collapse::default())]
    pub collapse: crate::bvh::collapse::Collapse,
    /// Subgroup widths to replay: powers of two from 1 to 128, comma-separated.
    #[arg(long, default_value = "8,16,32,64")]
    pub simd_width: String,
    /// Methods to replay, comma-separated.
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "megakernel,regenerate,wavefront,wavefront-regenerate"
    )]
    pub methods: Vec<ReplayMethod>,
    /// Replay a sampled subset of the frame (1: all of it), drawn per method: the naive
    /// megakernel one block of 128 invocations in N and the wavefront (waves) one whole wave in
    /// N, the offset turning by one at each pass over the image; the regenerating methods the
    /// first spp/N (rounded up) samples of every pixel and twice as many, each as a job of its
    /// own, extrapolated to the frame (their difference cancels the start and the drain; the
    /// whole frame where they would cover it); the shorter must hold at least 8 pools
    /// (persistent thread sets) and N be at most the spp.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..))]
    pub every: u64,
    /// Megakernel threads per workgroup (the device's dispatch shape).
    #[arg(long, default_value_t = 64)]
    pub workgroup_size: u32,
    /// Regenerating megakernel: persistent threads (rounded up to whole workgroups).
    #[arg(long, default_value_t = DEFAULT_THREADS_DISCRETE, value_parser = clap::value_parser!(u32).range(1..))]
    pub threads: u32,
    /// Regenerating megakernel: most paths a thread starts per launch, a number or `llvmpipe`
    /// (the cap the software driver's loop limit sets); unlimited when not given.
    #[arg(long)]
    pub paths_per_thread: Option<String>,
    /// Regenerating megakernel: subgroups running at once, taking samples in turn (all when not
    /// given; llvmpipe runs one per worker thread).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub resident_subgroups: Option<u32>,
    /// Wavefront: keep queues dense (`off`: every pass runs over the whole pool), as `render`.
    #[arg(long, value_enum, default_value_t = OnOff::On)]
    pub compaction: OnOff,
    /// Wavefront: how compaction builds queues, hence their order. `atomic` is replayed in
    /// `scan` order (the atomics' order is the device's to pick).
    #[arg(long, value_enum, default_value_t = CompactionMethod::Scan)]
    pub compaction_method: CompactionMethod,
    /// The wavefront's flags, as `render`'s (the replay models the lanes' grouping: it refuses
    /// --refill-below, --compact-states and --ray-sort, which move paths in ways it does not
    /// replay; the host's batching, the compute passes and how queues are appended or scanned
    /// do not change which lanes run together in its scan order).
    #[command(flatten)]
    pub wavefront: WavefrontOptions,
    /// Write the figures as JSON here.
    #[arg(long)]
    pub json: Option<std::path::PathBuf>,
    /// Draw the frame-level warp execution efficiency against width, one line per method, as
    /// an SVG chart here.
    #[arg(long)]
    pub chart: Option<std::path::PathBuf>,
}

impl ReplayArgs {
    /// The options the paths are prepared with: the defaults but the BVH's layout and collapse.
    fn bvh_options(&self) -> crate::options::MethodOptions {
        crate::options::MethodOptions { bvh: self.bvh, collapse: self.collapse, ..Default::default() }
    }
}

pub fn run(a: ReplayArgs) -> Result<()> {
    let widths = width::parse_list(&a.simd_width)?;
    let scene = Scene::resolve(&a.scene)?;
    let settings = render_settings(&a)?;
    let wf = wavefront_options(&a)?;
    let pool = replay_pool(&wf)?;
    // The paths the GPU methods trace: the scene in their render space, the layout asked for.
    let (packed, frame) =
        crate::method::prepare(crate::method::Method::Megakernel, &scene, &settings, &a.bvh_options())?;
    // The recorder keeps a leaf's tested positions in 24 bits.
    if let Some(n) = packed.nodes.iter().map(|n| n.count).max().filter(|&n| n > 24) {
        bail!("replay: a leaf of {n} primitives (at most 24; --accel none needs a scene of 24 or fewer)");
    }
    let paths_per_thread = paths_per_thread(&a, &packed, &settings)?;
    let wavefront =
        a.methods.iter().any(|m| matches!(m, ReplayMethod::Wavefront | ReplayMethod::WavefrontRegenerate));
    if wf.compaction == Compaction::Atomic && wavefront {
        eprintln!(
            "notice: --compaction atomic leaves queue order to the device's atomics; the replay uses the scan's order"
        );
    }
    println!(
        "{} {}x{}x{} nee={} roulette={} max_depth={}",
        a.scene, a.width, a.height, a.spp, settings.nee, settings.roulette, settings.max_depth
    );
    let job = Job {
        a: &a,
        target: ReplayJob::new(&packed, &frame, &settings, &widths),
        wf: &wf,
        pool,
        paths_per_thread,
    };
    let mut methods = serde_json::Map::new();
    let mut series = Vec::new();
    let mut naive_issued: Option<Vec<u64>> = None;
    for &m in &a.methods {
        let start = Instant::now();
        let (counts, mut about) = job.replay(m)?;
        let seconds = start.elapsed().as_secs_f64();
        println!("{}: {about}, {seconds:.2} s", m.name());
        let issued: Vec<u64> = counts.iter().map(|(_, c)| issued(c)).collect();
        if m == ReplayMethod::Megakernel {
            naive_issued = Some(issued.clone());
        }
        let (line, per_width) = report_widths(m, &counts, &issued, naive_issued.as_deref())?;
        series.push(line);
        about["seconds"] = seconds.into();
        about["widths"] = per_width.into();
        methods.insert(m.name().to_string(), about);
    }
    if let Some(path) = &a.json {
        let doc = serde_json::json!({
            "commit": env!("WAVETRACE_GIT_COMMIT"), "scene": a.scene, "width": a.width, "height": a.height, "spp": a.spp,
            "max_depth": a.max_depth, "nee": settings.nee, "roulette": settings.roulette, "accel": format!("{:?}", a.accel), "bvh": a.bvh, "collapse": a.collapse, "methods": methods,
        });
        std::fs::write(path, serde_json::to_string_pretty(&doc)?)?;
    }
    if let Some(path) = &a.chart {
        std::fs::write(path, efficiency_chart(&a, &settings, series).to_svg())?;
    }
    Ok(())
}

fn render_settings(a: &ReplayArgs) -> Result<RenderSettings> {
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
    if a.workgroup_size == 0 {
        bail!("--workgroup-size must be at least 1");
    }
    Ok(settings)
}

/// The wavefront's options as the replay models them, refusing the flags it does not model.
fn wavefront_options(a: &ReplayArgs) -> Result<WavefrontOptions> {
    let regenerating_wavefront = a.methods.contains(&ReplayMethod::WavefrontRegenerate);
    let compaction = a.compaction_method.with(a.compaction);
    let schedule = if regenerating_wavefront { Schedule::Regenerate } else { Schedule::Waves };
    let wf = WavefrontOptions { compaction, schedule, ..a.wavefront };
    // The device's rules; here what needs regeneration needs the regenerating wavefront replayed.
    crate::options::check_wavefront(&wf)
        .map_err(|e| anyhow!(e.for_cli_where_regenerating_is("--methods wavefront-regenerate")))?;
    let defaults = WavefrontOptions::default();
    for (moved, flag) in [
        (wf.refill_below != defaults.refill_below, "--refill-below"),
        (wf.compact_states != defaults.compact_states, "--compact-states"),
        (wf.ray_sort != defaults.ray_sort, "--ray-sort"),
        (wf.refill != defaults.refill, "--refill in-place"),
    ] {
        if moved {
            bail!("replay: {flag} moves paths between slots or queue positions in ways the replay does not model");
        }
    }
    if wf.shadow_rays != defaults.shadow_rays {
        bail!(
            "replay: --shadow-rays inline is not modelled (the replay traces shadow rays in the shadow pass)"
        );
    }
    Ok(wf)
}

fn replay_pool(wf: &WavefrontOptions) -> Result<u32> {
    Ok(match wf.pool_size {
        None => DEFAULT_POOL,
        Some(PoolSize::Paths(n)) => n,
        Some(PoolSize::Device) => {
            bail!("replay: --pool-size device needs the device's multiprocessors; give the pool as a number")
        }
    })
}

fn paths_per_thread(a: &ReplayArgs, packed: &PackedScene, settings: &RenderSettings) -> Result<Option<u32>> {
    Ok(match a.paths_per_thread.as_deref() {
        None => None,
        Some("llvmpipe") => Some(crate::gpu::loop_limit::capped_paths_per_thread(packed, settings)),
        Some(s) => match s.parse::<u32>() {
            Ok(n) if n > 0 => Some(n),
            _ => bail!("--paths-per-thread {s:?}: expected a whole number of at least 1, or `llvmpipe`"),
        },
    })
}

/// What every method's replay reads.
struct Job<'a> {
    a: &'a ReplayArgs,
    /// The scene, camera, settings and widths every method replays.
    target: ReplayJob<'a>,
    wf: &'a WavefrontOptions,
    pool: u32,
    paths_per_thread: Option<u32>,
}

type WidthCounts = Vec<(u32, SlotCounts)>;

impl Job<'_> {
    /// Replays one method: its counts per width and what the report says of its launch.
    fn replay(&self, m: ReplayMethod) -> Result<(WidthCounts, serde_json::Value)> {
        match m {
            ReplayMethod::Megakernel => self.megakernel(),
            ReplayMethod::Regenerate => self.regenerate(),
            ReplayMethod::Wavefront => self.wavefront(Schedule::Waves),
            ReplayMethod::WavefrontRegenerate => self.wavefront(Schedule::Regenerate),
        }
    }

    fn megakernel(&self) -> Result<(WidthCounts, serde_json::Value)> {
        let a = self.a;
        let launch = megakernel::Launch {
            samples_per_dispatch: MegakernelOptions::default().samples_per_dispatch,
            max_threads: 65535u32.saturating_mul(a.workgroup_size),
            every: a.every,
        };
        let r = megakernel::replay(self.target, launch);
        let about = serde_json::json!({
            "dispatches": r.dispatches, "every": a.every, "blocks": r.blocks, "blocks_replayed": r.blocks_replayed,
        });
        Ok((r.counts, about))
    }

    fn regenerate(&self) -> Result<(WidthCounts, serde_json::Value)> {
        let a = self.a;
        let launch = regenerate::Launch {
            samples_per_dispatch: MegakernelOptions::default().samples_per_dispatch,
            threads: a.threads,
            workgroup_size: a.workgroup_size,
            paths_per_thread: self.paths_per_thread,
            resident: a.resident_subgroups,
            every: a.every,
        };
        let r = regenerate::replay(self.target, launch)?;
        let about = serde_json::json!({
            "dispatches": r.dispatches, "threads": a.threads, "paths_per_thread": self.paths_per_thread,
            "resident_subgroups": a.resident_subgroups, "every": a.every,
            "samples_replayed": r.samples_replayed,
        });
        Ok((r.counts, about))
    }

    fn wavefront(&self, schedule: Schedule) -> Result<(WidthCounts, serde_json::Value)> {
        let (a, wf) = (self.a, self.wf);
        let regenerate = schedule == Schedule::Regenerate;
        let launch = wavefront::Launch {
            pool: self.pool,
            compaction: wf.compaction,
            shade: wf.shade,
            schedule,
            queue_order: wf.queue_order,
            sync_every: wf.sync_every,
            tail: if regenerate { wf.tail } else { Tail::Off },
            tail_threshold: wf.tail_threshold,
            chunk_pools: wf.chunk_pools,
            every: a.every,
        };
        let r = wavefront::replay(self.target, launch)?;
        let mut about = serde_json::json!({
            "dispatches": r.dispatches, "shares": r.waves, "shares_replayed": r.waves_replayed,
            "samples_replayed": r.samples_replayed, "every": a.every, "pool": self.pool,
            "compaction": wf.compaction, "shade": wf.shade, "schedule": schedule,
            "queue_order": r.queue_order.name(), "iterations": r.iterations,
        });
        if regenerate {
            about["sync_every"] = wf.sync_every.into();
            about["chunk_pools"] = wf.chunk_pools.into();
            about["tail"] = serde_json::to_value(wf.tail)?;
            if wf.tail == Tail::Megakernel {
                about["tail_threshold"] = wf.tail_threshold.into();
                about["tail_passes"] = r.tail_passes.into();
                about["tail_paths"] = r.tail_paths.into();
            }
        }
        Ok((r.counts, about))
    }
}

/// Prints a method's efficiencies per width; returns its chart line and its report per width.
fn report_widths(
    m: ReplayMethod,
    counts: &WidthCounts,
    issued: &[u64],
    naive_issued: Option<&[u64]>,
) -> Result<(Series, serde_json::Map<String, serde_json::Value>)> {
    let mut per_width = serde_json::Map::new();
    let mut line =
        Series { name: m.label().to_string(), points: Vec::new(), intervals: Vec::new(), labels: Vec::new() };
    for (i, (w, c)) in counts.iter().enumerate() {
        let e = c.efficiencies()?;
        let frame_eff = e.get(FRAME_KEY).map_or(0.0, |f| f.efficiency);
        line.points.push((f64::from(*w), frame_eff * 100.0));
        // The naive megakernel's issued subgroup-iterations over this method's: the speed-up
        // an ideal W-lane machine would show, were every block equally costly.
        let speedup = naive_issued.map(|n| n[i] as f64 / issued[i].max(1) as f64);
        println!(
            "  W={w:<4} warp execution efficiency {:>6.2}%  subgroup-iterations issued {}{}",
            frame_eff * 100.0,
            issued[i],
            speedup
                .map_or(String::new(), |s| format!("  predicted speed-up over the naive megakernel {s:.2}x"))
        );
        for (k, v) in &e {
            println!("      {k:<40} {:>7.2}%  {:>12}", v.efficiency * 100.0, v.subgroups);
        }
        per_width.insert(
            w.to_string(),
            serde_json::json!({ "issued": issued[i], "predicted_speedup_over_naive": speedup, "simd": e }),
        );
    }
    Ok((line, per_width))
}

fn efficiency_chart(a: &ReplayArgs, settings: &RenderSettings, series: Vec<Series>) -> LineChart {
    let nee = match (settings.nee, settings.roulette) {
        (false, false) => "",
        (true, false) => ", NEE",
        (false, true) => ", roulette",
        (true, true) => ", NEE, roulette",
    };
    LineChart {
        title: format!(
            "{} {}x{}x{}{nee}: predicted warp execution efficiency (lockstep replay)",
            a.scene, a.width, a.height, a.spp
        ),
        x_label: "SIMD width (lanes)".into(),
        y_label: "work-weighted SIMD efficiency (%)".into(),
        x_log: true,
        series,
        ..Default::default()
    }
}

/// Subgroup-iterations issued over every slot.
fn issued(c: &SlotCounts) -> u64 {
    c.slots.iter().map(|s| s[1]).sum()
}
