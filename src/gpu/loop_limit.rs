//! A limit of the software driver that the GPU methods must respect.
//!
//! llvmpipe (Mesa's software driver) ends all loops of a shader invocation after 65535
//! iterations in total, silently: the counter is shared by every loop of the invocation and
//! runs once per trip of its SIMD group, whichever lanes are active.

use super::context::GpuContext;
use crate::layout::texture_kind;
use crate::packed_scene::PackedScene;
use crate::settings::RenderSettings;
use anyhow::{bail, Result};

pub const LLVMPIPE_LOOP_LIMIT: u64 = 65_535;

/// Whether `ctx` ends loops after [`LLVMPIPE_LOOP_LIMIT`] iterations.
pub fn has_loop_limit(ctx: &GpuContext) -> bool {
    ctx.summary.name.contains("llvmpipe")
}

/// Loop iterations one bounce may take: a traversal (two with next-event estimation) visits at
/// most the BVH's depth of nodes and one leaf, and a noise texture loops over its octaves.
pub fn per_bounce(scene: &PackedScene, settings: &RenderSettings) -> u64 {
    // With next-event estimation each bounce also traverses for its shadow ray.
    let traversals = if settings.nee && !scene.lights.is_empty() { 2 } else { 1 };
    let traversal = scene.largest_leaf() as u64 + crate::bvh::MAX_DEPTH as u64;
    traversals * traversal + texture_loops(scene)
}

/// Loop trips of the costliest texture lookup: turbulence() takes one per octave, each with
/// perlin()'s 8 corners.
fn texture_loops(scene: &PackedScene) -> u64 {
    scene
        .materials
        .iter()
        .filter(|m| texture_kind::is_procedural(m.texture))
        .map(|m| 9 * m.octaves as u64)
        .max()
        .unwrap_or(0)
}

/// Refuses renders whose one path may exceed the cap rather than return a wrong image.
pub fn check_loop_limit(ctx: &GpuContext, scene: &PackedScene, settings: &RenderSettings) -> Result<()> {
    let worst = settings.max_depth as u64 * per_bounce(scene, settings);
    if has_loop_limit(ctx) && worst > LLVMPIPE_LOOP_LIMIT {
        bail!(
            "on {} a path may need {worst} loop iterations (max depth {} x a leaf of {} primitives), \
             past llvmpipe's limit of {LLVMPIPE_LOOP_LIMIT} per shader invocation, which would \
             silently truncate paths; use --accel bvh or a smaller --max-depth",
            ctx.summary.name,
            settings.max_depth,
            scene.largest_leaf()
        );
    }
    Ok(())
}

/// Most paths one thread of the regenerating megakernel may start in one dispatch where loops
/// are capped (None: no cap). Its subgroup loops once per bounce while any lane is busy, so it
/// takes at most `paths × max_depth + 1` outer trips, each with one bounce's inner loops. A
/// persistent thread adds up many paths' loops, so the estimate of a bounce's loops matters
/// more than for one path: it takes the scene's own BVH depth, with a traversal visiting up to
/// twice as many nodes, rather than the deepest BVH the builder allows. The shader reports a
/// thread the cap ended anyway (`WORK_CUT`), and the render fails rather than return it.
pub fn paths_per_thread(ctx: &GpuContext, scene: &PackedScene, settings: &RenderSettings) -> Option<u32> {
    has_loop_limit(ctx).then(|| capped_paths_per_thread(scene, settings))
}

/// [`paths_per_thread`] on a driver that caps loops: also the SIMD replay's model of llvmpipe.
pub fn capped_paths_per_thread(scene: &PackedScene, settings: &RenderSettings) -> u32 {
    let traversals = if settings.nee && !scene.lights.is_empty() { 2 } else { 1 };
    let depth = scene.bvh_depth();
    let traversal = 2 * depth as u64 + scene.largest_leaf() as u64;
    let per_bounce = traversals * traversal + texture_loops(scene);
    let paths = paths_within(LLVMPIPE_LOOP_LIMIT, settings.max_depth, per_bounce);
    log::info!(
        "llvmpipe loop cap: BVH depth {}, largest leaf {}, {per_bounce} loop trips a bounce at most: {paths} paths per thread per dispatch",
        depth,
        scene.largest_leaf()
    );
    paths
}

/// The largest `paths` with `(paths × max_depth + 1) × (1 + per_bounce) ≤ limit`, at least 1.
fn paths_within(limit: u64, max_depth: u32, per_bounce: u64) -> u32 {
    let trips = limit / (1 + per_bounce);
    (trips.saturating_sub(1) / max_depth.max(1) as u64).clamp(1, u32::MAX as u64) as u32
}

#[cfg(test)]
mod tests {
    use super::paths_within;

    #[test]
    fn paths_within_keeps_the_worst_case_under_the_limit() {
        for (depth, per_bounce) in [(1u32, 0u64), (50, 68), (50, 136), (5, 10), (1000, 64)] {
            let p = paths_within(65_535, depth, per_bounce) as u64;
            let worst = |p: u64| (p * depth as u64 + 1) * (1 + per_bounce);
            assert!(worst(p) <= 65_535 || p == 1, "{depth} {per_bounce}: {p}");
            assert!(worst(p + 1) > 65_535, "{depth} {per_bounce}: {p} is not the largest");
        }
    }
}
