//! `wavetrace intersect-cost`: the wavefront's intersect pass against its diagnostic twin that
//! keeps the ray in registers, over the same camera rays (issue 44, item 1b).

use anyhow::Result;

use super::measurement::Measurement;
use crate::measure::intersect_cost::{self, IntersectCost};
use crate::scene::Scene;
use crate::settings::{Accel, RenderSettings};

const EXAMPLES: &str = "\
Examples:
  wavetrace intersect-cost                                        # rtiow-final 1920x1080x64
  wavetrace intersect-cost --scene experiments/scenes/mesh-room.json --json mesh-room.json
  wavetrace intersect-cost --width 320 --height 180 --spp 4 --repetitions 3   # a software driver";

/// Times the wavefront's intersect pass over a frame's camera rays (waves at depth 1: each ray
/// read from the path state, its hit written back and queued) and `intersect_registers`, which
/// makes the same rays in place and keeps only a tally of their hits: ns per camera ray of each.
/// Fails when their hits differ.
#[derive(clap::Args, Debug)]
#[command(after_help = EXAMPLES)]
pub struct IntersectCostArgs {
    /// Built-in scene name or scene file, as `render`.
    #[arg(long, default_value = "rtiow-final")]
    pub scene: String,
    #[arg(long, default_value_t = 1920)]
    pub width: u32,
    #[arg(long, default_value_t = 1080)]
    pub height: u32,
    /// Samples per pixel: camera rays per pixel.
    #[arg(long, default_value_t = 64)]
    pub spp: u32,
    #[arg(long, default_value_t = 0)]
    pub seed: u32,
    /// Threads per workgroup of both passes.
    #[arg(long, default_value_t = 64)]
    pub workgroup_size: u32,
    /// The wavefront's paths per wave (default: the adapter's, as `render`).
    #[arg(long)]
    pub pool_size: Option<u32>,
    /// Timed rounds after one untimed round (the two passes taking turns).
    #[arg(long, default_value_t = 5)]
    pub repetitions: u32,
    #[command(flatten)]
    pub measurement: Measurement,
}

pub fn run(a: IntersectCostArgs) -> Result<()> {
    let scene = Scene::resolve(&a.scene)?;
    let ctx = a.measurement.context()?;
    let job = IntersectCost {
        settings: RenderSettings {
            width: a.width,
            height: a.height,
            spp: a.spp,
            max_depth: 1,
            seed: a.seed,
            accel: Accel::Bvh,
            nee: false,
            roulette: false,
        },
        workgroup_size: a.workgroup_size,
        pool_size: a.pool_size,
        repetitions: a.repetitions,
        preheat_seconds: crate::options::DEFAULT_PREHEAT_SECONDS,
    };
    let report = intersect_cost::measure(&ctx, &scene, &job)?;
    a.measurement.publish(&report.table(), &report)?;
    Ok(())
}
