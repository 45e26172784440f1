//! `wavetrace plan`: the wavefront's pass graph for a job, printed without rendering — each pass
//! with when it runs, its shader, launch, queues and pipeline constants — or as JSON for
//! scripts. What a researcher reads before an experiment; the docs' diagram is made by it.

use super::job::JobArgs;
use crate::gpu::wavefront::graph::{Launch, Pass, Phase, When};
use crate::gpu::wavefront::{self, Explained};
use crate::gpu::GpuContext;
use crate::method;
use crate::options::{knobs, Method, Named};
use anyhow::{bail, Result};
use std::fmt::Write;
use std::path::PathBuf;

const EXAMPLES: &str = "\
Examples:
  wavetrace plan --scene rtiow-final --method wavefront --width 1920 --height 1080 --spp 64 --nee on
  wavetrace plan --scene rtiow-kinds-8 --method wavefront --schedule regenerate --tail megakernel \\
      --shade sorted --queue-order slot
  wavetrace plan --scene cornell --method wavefront --compaction-method scan --json plan.json";

#[derive(clap::Args, Debug)]
#[command(after_help = EXAMPLES)]
pub struct PlanArgs {
    /// The job, as `wavetrace render` takes it (`--method wavefront`).
    #[command(flatten)]
    pub job: JobArgs,
    /// Write the plan as JSON to this file (`-` for standard output) instead of the table.
    #[arg(long, help_heading = "Output")]
    pub json: Option<PathBuf>,
}

pub fn run(a: PlanArgs) -> Result<()> {
    if a.job.method != Method::Wavefront {
        bail!("wavetrace plan shows the wavefront's pass graph: use --method wavefront");
    }
    let (scene, settings, options) = a.job.build()?;
    settings.validate().map_err(anyhow::Error::msg)?;
    crate::options::check(Method::Wavefront, &options).map_err(|e| anyhow::anyhow!(e.for_cli()))?;
    let ctx = GpuContext::new(a.job.adapter.as_deref())?;
    let (packed, _) = method::prepare(Method::Wavefront, &scene, &settings, &options)?;
    let e = wavefront::explain(&ctx, &packed, &settings, &options.wavefront, options.timing)?;
    match &a.json {
        Some(p) if p.as_os_str() == "-" => println!("{}", serde_json::to_string_pretty(&e)?),
        Some(p) => super::write_json(p, &e)?,
        None => {
            let job = format!(
                "{} {}x{}x{} spp, max depth {}, NEE {}, on {}",
                scene.name,
                settings.width,
                settings.height,
                settings.spp,
                settings.max_depth,
                if settings.nee { "on" } else { "off" },
                ctx.summary.name
            );
            print!("{}", table(&job, &e));
        }
    }
    Ok(())
}

/// The plan as text: the job and resolved knobs, the graph's constants, then each phase's passes.
pub fn table(job: &str, e: &Explained) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "wavefront plan: {job}");
    let o = crate::options::MethodOptions { wavefront: e.options, ..Default::default() };
    let knobs: Vec<String> = knobs::KNOBS
        .iter()
        .filter(|k| k.methods == [Method::Wavefront])
        .map(|k| k.label(&o, Method::Wavefront))
        .collect();
    let _ = writeln!(s, "options as they run: schedule={} {}", e.schedule.name(), knobs.join(" "));
    let _ = writeln!(s, "pool: {} paths, {} bytes a path; {} share(s)", e.pool, e.bytes_per_path, e.shares);
    let c: Vec<String> = e.graph.constants.iter().map(|(n, v)| format!("{n}={v}")).collect();
    let _ = writeln!(s, "pipeline constants of every pass over the path state: {}", c.join(" "));
    for (phase, title) in [
        (Phase::Start, "at a share's start"),
        (Phase::Iteration, "each iteration"),
        (Phase::Decided, "after an iteration that checks (the passes its decision sizes)"),
        (Phase::End, "at a wave's end"),
    ] {
        let passes: Vec<&Pass> = e.graph.phase(phase).collect();
        if passes.is_empty() {
            continue;
        }
        let _ = writeln!(s, "\n{title}:");
        let _ = writeln!(
            s,
            "  {:<27} {:<9} {:<22} {:<26} {:<16} {:<22} constants",
            "pass", "runs", "shader", "launch", "consumes", "produces"
        );
        for p in passes {
            let _ = writeln!(s, "  {}", row(p));
        }
    }
    let _ = writeln!(s, "\nat most {} dispatches an iteration", e.graph.per_iteration());
    s
}

fn row(p: &Pass) -> String {
    let when = match p.when {
        When::Always => "always",
        When::Refill => "refill",
        When::Check => "check",
        When::NoCheck => "no check",
    };
    let launch = match p.launch {
        Launch::Single => "1 thread".to_string(),
        Launch::Queue(slot) => format!("queue (args {slot})"),
        Launch::Indirect(slot) => format!("indirect (args {slot})"),
        Launch::Direct(n) => format!("{n} workgroup(s)"),
        Launch::Paths => "a thread a path".to_string(),
        Launch::Pixels => "a thread a pixel".to_string(),
    };
    let queues = |q: &[crate::gpu::wavefront::graph::Queue]| {
        if q.is_empty() {
            "-".to_string()
        } else {
            q.iter().map(|q| format!("{q:?}").to_lowercase()).collect::<Vec<_>>().join(",")
        }
    };
    let c: Vec<String> = p.constants.iter().map(|(n, v)| format!("{n}={v}")).collect();
    format!(
        "{:<27} {:<9} {:<22} {:<26} {:<16} {:<22} {}",
        p.label,
        when,
        p.shader.file().trim_start_matches("wavefront/"),
        launch,
        queues(&p.consumes),
        queues(&p.produces),
        c.join(" ")
    )
}
