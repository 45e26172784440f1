//! `--ray-sort`: the key the ray queue is sorted by before each intersect
//! (`gpu/wavefront/ray_sort.rs`).

use super::*;

/// The key the ray queue is sorted by before each intersect.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum RaySort {
    /// The queue keeps the order its producing passes gave it (`--queue-order`).
    #[default]
    Off,
    /// By the ray direction's octant (8 keys).
    Octant,
    /// By octant, then the ray origin's cell of a 4×4×4 grid over the scene's bounds (512 keys).
    OctantCell,
}
enum_values!(RaySort);

flag! {
    /// Wavefront: before each intersect, sort the ray queue by the ray direction's octant
    /// (`octant`), or by octant and the origin's cell of a 4x4x4 grid over the scene
    /// (`octant-cell`), so a subgroup's lanes traverse the same part of the BVH (a counting sort:
    /// three passes). Needs --compaction on.
    #[arg(long, value_enum, default_value_t, hide_short_help = true)]
    ray_sort: RaySort
}

pub const KNOB: Knob = knob!("ray_sort", "ray-sort", WAVEFRONT, RaySort, o => o.wavefront.ray_sort);

pub const RULE: Rule = Rule {
    knob: "ray_sort",
    why: "sorts the ray queue",
    set: |o| name(o.ray_sort != RaySort::Off, o.ray_sort),
    needs: queued,
};
