//! `wavetrace render`: one scene, one method, to EXR (+ PNG preview, + JSON report).

use super::job::JobArgs;
use crate::gpu::buffers::human_bytes;
use crate::gpu::memory::{GpuMemory, MemoryCategory};
use crate::gpu::timing::{TimeSource, Timings, FRAME_LABEL};
use crate::image_io;
use crate::progress::Progress;
use crate::render_job::{self, Phase, RenderJob};
use crate::report::RunReport;
use anyhow::{Context, Result};
use std::path::PathBuf;

pub const EXAMPLES: &str = "\
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
    // The outputs first: the flattened job's last group (Wavefront) would otherwise name the
    // fields after it.
    /// Output EXR (linear RGB, f32).
    #[arg(long)]
    pub out: PathBuf,
    /// Also write an sRGB PNG preview.
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Also write a JSON record of the run.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Untimed renders before the one that is timed and written: `auto` (GPU methods: until the
    /// GPU has worked 0.5 s and two frames agree within 5%, at most 50 frames or 10 s; CPU
    /// methods: none), or a number of frames (0: time a cold first frame).
    #[arg(long, default_value = "auto", value_parser = parse_warmup)]
    pub warmup: WarmupArg,
    /// The scene, the job and the method with its options.
    #[command(flatten)]
    pub job: JobArgs,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WarmupArg {
    Auto,
    Frames(u32),
}

/// `--warmup`: `auto` or a number of frames.
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
    let (scene, settings, options) = a.job.build()?;
    let job = RenderJob {
        method: a.job.method,
        settings,
        options,
        adapter: a.job.adapter.clone(),
        warmup: match a.warmup {
            WarmupArg::Auto => None,
            WarmupArg::Frames(n) => Some(n),
        },
    };
    // The bar starts with the timed render (the warm-up's renders show none).
    let progress = std::sync::OnceLock::new();
    let what = format!("{} {}", a.job.method.name(), scene.name);
    let rendered = render_job::render(&scene, &job, &|phase, d| {
        if phase == Phase::Render {
            progress.get_or_init(|| Progress::new(job.settings.sample_count(), &what)).set(d);
        }
    })?;
    if let Some(p) = progress.get() {
        p.finish();
    }
    let RenderJob { settings, options, .. } = job;
    let (image, report, out) = (rendered.image, rendered.report, rendered.output);
    let adapter = report.adapter.as_ref().map(|a| a.is_software());
    let options = options.resolve(a.job.method, adapter);
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
        // A column per material kind, named as its shade pass.
        let kinds: String = crate::gpu::label::SHADE_BY_KIND
            .iter()
            .map(|l| format!(" {:>12}", &l["shade_".len()..]))
            .collect();
        println!("bounce {:>12}{kinds}{shadow_head}", "rays");
        for (b, rays) in h.rays.iter().enumerate() {
            let m: String =
                h.materials.iter().map(|m| format!(" {:>12}", m.get(b).copied().unwrap_or(0))).collect();
            let s = if shadow {
                format!(" {:>12}", h.shadow.get(b).copied().unwrap_or(0))
            } else {
                String::new()
            };
            println!("{b:>6} {rays:>12}{m}{s}");
        }
    }
}
