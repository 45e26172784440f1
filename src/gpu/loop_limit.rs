//! A limit of the software driver that both GPU methods must respect.

use super::context::GpuContext;
use crate::packed_scene::PackedScene;
use crate::settings::RenderSettings;
use anyhow::{bail, Result};

/// llvmpipe (Mesa's software driver) ends all loops of a shader invocation after 65535
/// iterations in total, silently. One path visits at most `max_depth` leaves; refuse renders
/// whose worst case exceeds the cap rather than return a wrong image.
pub fn check_loop_limit(ctx: &GpuContext, scene: &PackedScene, settings: &RenderSettings) -> Result<()> {
    const LLVMPIPE_LOOP_LIMIT: u64 = 65_535;
    // With next-event estimation each bounce also traverses for its shadow ray.
    let traversals = if settings.nee && !scene.lights.is_empty() { 2 } else { 1 };
    let worst =
        traversals * settings.max_depth as u64 * (scene.largest_leaf() as u64 + crate::bvh::MAX_DEPTH as u64);
    if ctx.summary.name.contains("llvmpipe") && worst > LLVMPIPE_LOOP_LIMIT {
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
