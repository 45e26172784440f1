//! The `wavetrace` command line.

pub mod compare;
pub mod experiment;
pub mod info;
pub mod render;
pub mod replay;
pub mod scene;

use clap::{Parser, Subcommand};

const EXAMPLES: &str = "\
Examples:
  wavetrace render --scene rtiow-final --method megakernel --width 1200 --height 675 --spp 10 \\
      --out final.exr --png final.png
  wavetrace render --scene three-spheres --method cpu --spp 64 --out cpu.exr --report cpu.json
  wavetrace render --scene my_scene.json --method megakernel --adapter nvidia --out gpu.exr
  wavetrace info
  wavetrace scene list
  wavetrace scene export rtiow-final > final.json
  wavetrace compare test.exr reference.exr --json
  wavetrace experiment run experiments/quick.json     # -> out/quick/report.html

Environment:
  RUST_LOG=info|debug    logging (e.g. adapter choice, dispatch plan)
  WGPU_BACKEND=vulkan    restrict the adapters considered to one backend";

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
    /// List GPU adapters, the one chosen and why, and the features and limits that matter.
    Info(info::InfoArgs),
    /// List or export the built-in scenes.
    #[command(subcommand)]
    Scene(scene::SceneCommand),
    /// Error metrics (MSE, relMSE, SMAPE, MAPE, FLIP) of a test EXR against a reference EXR.
    Compare(compare::CompareArgs),
    /// Run experiment configs into JSON reports, EXRs, charts and HTML; merge shards; re-draw.
    #[command(subcommand)]
    Experiment(experiment::ExperimentCommand),
    /// Replay a frame's paths in SIMD lockstep at several widths (no GPU): predicted efficiency.
    Replay(replay::ReplayArgs),
}

pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Render(a) => render::run(a),
        Command::Info(a) => info::run(a),
        Command::Scene(c) => scene::run(c),
        Command::Compare(a) => compare::run(a),
        Command::Experiment(c) => experiment::run(c),
        Command::Replay(a) => replay::run(a),
    }
}
