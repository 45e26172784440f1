//! `wavetrace replay`: the lockstep SIMD replay (src/replay/) of a frame at several widths, on the
//! CPU: work-weighted efficiency per block and pass, the frame's warp execution efficiency and
//! the subgroup-iterations an ideal W-lane machine issues.

use super::render::OnOff;
use crate::camera::CameraFrame;
use crate::packed_scene::PackedScene;
use crate::replay::megakernel::{replay, Launch};
use crate::replay::width;
use crate::scene::Scene;
use crate::settings::{Accel, RenderSettings};
use anyhow::Result;
use std::time::Instant;

#[derive(clap::Args, Debug)]
#[command(
    after_help = "Example:\n  wavetrace replay --scene rtiow-final --width 160 --height 90 --spp 64 --simd-width 8,16,32,64"
)]
pub struct ReplayArgs {
    /// Built-in scene name or path to a scene JSON file.
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
    /// `none`: every primitive tested in one loop, as the seeds' CUDA ports did (at most 32).
    #[arg(long, value_enum, default_value_t = Accel::Bvh)]
    pub accel: Accel,
    /// Subgroup widths to replay: powers of two from 1 to 128, comma-separated.
    #[arg(long, default_value = "8,16,32,64")]
    pub simd_width: String,
    /// Replay one block of 128 invocations in N (systematic sample of whole blocks; 1: all).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..))]
    pub every: u64,
    /// Megakernel threads per workgroup (the device's dispatch shape).
    #[arg(long, default_value_t = 64)]
    pub workgroup_size: u32,
    /// Write the figures as JSON here.
    #[arg(long)]
    pub json: Option<std::path::PathBuf>,
}

pub fn run(a: ReplayArgs) -> Result<()> {
    let widths = width::parse_list(&a.simd_width)?;
    let scene = Scene::resolve(&a.scene)?;
    let settings = RenderSettings {
        width: a.width,
        height: a.height,
        spp: a.spp,
        max_depth: a.max_depth,
        seed: a.seed,
        accel: a.accel,
        nee: a.nee == OnOff::On,
    };
    settings.validate().map_err(anyhow::Error::msg)?;
    let packed = PackedScene::new(&scene, settings.accel);
    // The recorder keeps a leaf's tested positions in 24 bits.
    if let Some(n) = packed.nodes.iter().map(|n| n.count).max().filter(|&n| n > 24) {
        anyhow::bail!(
            "replay: a leaf of {n} primitives (at most 24; --accel none needs a scene of 24 or fewer)"
        );
    }
    let frame = CameraFrame::new(&scene.camera, settings.width, settings.height);
    let defaults = crate::gpu::megakernel::MegakernelOptions::default();
    let launch = Launch {
        samples_per_dispatch: defaults.samples_per_dispatch,
        max_threads: 65535u32.saturating_mul(a.workgroup_size),
        every: a.every,
    };
    let start = Instant::now();
    let r = replay(&packed, &frame, &settings, &widths, launch);
    let seconds = start.elapsed().as_secs_f64();
    println!(
        "naive megakernel, {} {}x{}x{} nee={}: {} dispatches, {} of {} blocks of 128 invocations replayed, {seconds:.2} s",
        a.scene, a.width, a.height, a.spp, settings.nee, r.dispatches, r.blocks_replayed, r.blocks
    );
    let mut json = serde_json::Map::new();
    for (w, counts) in &r.counts {
        let e = counts.efficiencies()?;
        let issued: u64 = counts.slots.iter().map(|s| s[1]).sum();
        let frame = e.get(crate::gpu::instrument::FRAME_KEY).map_or(0.0, |f| f.efficiency);
        println!(
            "W={w:<4} warp execution efficiency {:>6.2}%  subgroup-iterations issued {issued}",
            frame * 100.0
        );
        for (k, v) in &e {
            println!("    {k:<40} {:>7.2}%  {:>12}", v.efficiency * 100.0, v.subgroups);
        }
        json.insert(w.to_string(), serde_json::to_value(&e)?);
    }
    if let Some(path) = &a.json {
        let doc = serde_json::json!({
            "method": "megakernel", "commit": env!("WAVETRACE_GIT_COMMIT"), "scene": a.scene, "width": a.width, "height": a.height, "spp": a.spp,
            "nee": settings.nee, "accel": format!("{:?}", a.accel), "every": a.every, "dispatches": r.dispatches, "seconds": seconds,
            "widths": json,
        });
        std::fs::write(path, serde_json::to_string_pretty(&doc)?)?;
    }
    Ok(())
}
