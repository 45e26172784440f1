//! The `wavetrace` command line.

pub mod bandwidth;
pub mod compare;
pub mod dispatch_cost;
pub mod experiment;
pub mod info;
pub mod intersect_cost;
pub mod job;
pub mod measurement;
pub mod plan;
pub mod render;
pub mod replay;
pub mod scene;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};

const EXAMPLES: &str = "\
Examples:
  wavetrace render --scene rtiow-final --method megakernel --width 1200 --height 675 --spp 10 \\
      --out final.exr --png final.png
  wavetrace render --scene three-spheres --method cpu --spp 64 --out cpu.exr --report cpu.json
  wavetrace render --scene my_scene.json --method megakernel --adapter nvidia --out gpu.exr
  wavetrace plan --scene rtiow-final --method wavefront --nee on   # the passes a render records
  wavetrace info
  wavetrace scene list
  wavetrace scene export rtiow-final > final.json
  wavetrace compare test.exr reference.exr --json
  wavetrace experiment run experiments/quick.json     # -> out/quick/report.html
  wavetrace dispatch-cost --json cost.json            # what one dispatch costs on this GPU
  wavetrace intersect-cost --json intersect.json      # intersect: traversal or state traffic?

Environment (docs/cli-and-configs.md#environment-variables has the full table):
  RUST_LOG=info|debug                 logging (info: adapter choice, warm-up, llvmpipe loop cap)
  WGPU_BACKEND=vulkan                 consider only this backend's adapters (vulkan, metal, dx12, gl)
  NODEVICE_SELECT=1                   turn Mesa's Vulkan device-selection layer off (set for you
                                      where XDG_RUNTIME_DIR is unset: headless machines)
  WGPU_VALIDATION_INDIRECT_CALL=1     turn wgpu's indirect-dispatch validation back on (off by
                                      default; reports record it as indirect_validation)
  WAVETRACE_CACHE=DIR                 experiment run: where rendered references are cached (--cache)
Tests, benches and scripts:
  WAVETRACE_REQUIRE_GPU=1             GPU tests fail instead of skipping without an adapter (CI=1 too)
  WAVETRACE_ADAPTER=SUBSTR            the adapter the tests and benches open
  WAVETRACE_BENCH_SCENE, WAVETRACE_BENCH_NEE=on     cargo bench --features bench --bench gpu_frame's scene and NEE
  WAVETRACE_DEVICE_BUDGET=SECONDS     scripts/device_figures.sh: time this call may spend [540]
  WAVETRACE_DEVICE_WORK=DIR           scripts/device_figures.sh: reports kept between calls
  WAVETRACE_DEVICE_ALLOW_SOFTWARE=1   scripts/device_figures.sh: accept a software adapter
  WAVETRACE_DEVICE_LOADER=skip        scripts/device_prepare.sh: do not download the Vulkan loader";

#[derive(Parser, Debug)]
#[command(name = "wavetrace", version, about = "Megakernel vs wavefront GPU path tracing: a research testbed", after_help = EXAMPLES)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a scene with one method to EXR (and optionally PNG and a JSON report).
    Render(render::RenderArgs),
    /// Print the wavefront's pass graph for a job without rendering: each pass, when it runs,
    /// its launch, queues and pipeline constants (`--json` for scripts).
    Plan(plan::PlanArgs),
    /// List GPU adapters, the one chosen and why, and the features and limits that matter.
    Info(info::InfoArgs),
    /// List the built-in scenes, describe any scene (glTF: what was mapped), export a built-in one.
    #[command(subcommand, after_help = scene::EXAMPLES)]
    Scene(scene::SceneCommand),
    /// Error metrics (MSE, relMSE, SMAPE, MAPE, FLIP) of a test EXR against a reference EXR.
    Compare(compare::CompareArgs),
    /// Run experiment configs into JSON reports, EXRs, charts and HTML; merge shards; re-draw.
    #[command(subcommand, after_help = experiment::EXAMPLES)]
    Experiment(experiment::ExperimentCommand),
    /// Replay a frame's paths in SIMD lockstep at several widths (no GPU): predicted efficiency.
    Replay(replay::ReplayArgs),
    /// Time a chain of tiny dispatches recorded six ways: what a dispatch costs by itself.
    DispatchCost(dispatch_cost::DispatchCostArgs),
    /// What this GPU's memory delivers to a pass streaming 16-byte elements: GB/s of a compute
    /// copy, a compute read and a buffer copy.
    Bandwidth(bandwidth::BandwidthArgs),
    /// Time the wavefront's intersect of a frame's camera rays against a twin that keeps each ray
    /// in registers and writes no path state: traversal apart from state traffic.
    IntersectCost(intersect_cost::IntersectCostArgs),
}

/// The command line as the binary parses it: clap's definition, with `render -h` naming the
/// option groups it hides and every flag in each (generated from the definition, so it cannot
/// fall behind it); `render --help` shows them all.
pub fn command() -> clap::Command {
    Cli::command().mut_subcommand("render", |c| {
        let groups = hidden_groups(&c);
        c.after_help(format!("{groups}\n{}", render::EXAMPLES)).after_long_help(render::EXAMPLES)
    })
}

/// Parses the process's arguments with [`command`] (exits with clap's message on bad ones).
pub fn parse() -> Cli {
    Cli::from_arg_matches(&command().get_matches()).unwrap_or_else(|e| e.exit())
}

/// `More options, by group (wavetrace render --help shows them):` then each group's heading and
/// its flags, for the flags a short help hides.
fn hidden_groups(c: &clap::Command) -> String {
    let mut groups: Vec<(String, Vec<String>)> = Vec::new();
    for a in c.get_arguments().filter(|a| a.is_hide_short_help_set() && !a.is_hide_set()) {
        let (Some(heading), Some(long)) = (a.get_help_heading(), a.get_long()) else { continue };
        match groups.iter_mut().find(|(h, _)| h == heading) {
            Some((_, flags)) => flags.push(format!("--{long}")),
            None => groups.push((heading.to_string(), vec![format!("--{long}")])),
        }
    }
    let mut out = format!("More options, by group (`wavetrace {} --help` shows them all):\n", c.get_name());
    for (heading, flags) in groups {
        let mut line = format!("  {heading}:");
        for f in flags {
            if line.len() + f.len() + 1 > 100 {
                out.push_str(&line);
                out.push('\n');
                line = "     ".to_string();
            }
            line.push(' ');
            line.push_str(&f);
        }
        out.push_str(&line);
        out.push('\n');
    }
    out
}

pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Render(a) => render::run(a),
        Command::Plan(a) => plan::run(a),
        Command::Info(a) => info::run(a),
        Command::Scene(c) => scene::run(c),
        Command::Compare(a) => compare::run(a),
        Command::Experiment(c) => experiment::run(c),
        Command::Replay(a) => replay::run(a),
        Command::DispatchCost(a) => dispatch_cost::run(a),
        Command::Bandwidth(a) => bandwidth::run(a),
        Command::IntersectCost(a) => intersect_cost::run(a),
    }
}

/// Writes a command's report as pretty JSON to `path`, whole or not at all (the
/// microbenchmarks' `--json FILE`).
pub(crate) fn write_json(path: &std::path::Path, report: &impl serde::Serialize) -> anyhow::Result<()> {
    use anyhow::Context;
    let json = serde_json::to_string_pretty(report)?;
    crate::image_io::write_file_atomically(path, json.as_bytes())
        .with_context(|| format!("writing {}", path.display()))
}
