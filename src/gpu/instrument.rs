//! SIMD efficiency (`--instrument`): per pass slot, subgroup lanes active at the instrumented
//! point over lanes available (the sum of each arriving subgroup's own `subgroup_size`, so the
//! figure is right on drivers that pick the width per pipeline). Shaders write the counters
//! in their `.instrumented` variants (`shaders/shared/instrument_on.wgsl`); timing runs use the
//! plain variants and carry no counters.
//!
//! Two kinds of slot. The *entry points* (the first [`FIRST_STEP_SLOT`]: a pass's body after its early returns,
//! the top of a megakernel bounce, a material branch) count each subgroup once per arrival. The
//! *traversal steps* (`*_traverse_{inner,leaf,primitive}`) count inside the BVH loop, once per
//! iteration, so a lane whose ray finished early counts idle for every step its neighbours
//! still take. [`work_weighted`] pools them per pass (`work:<pass>`) and over the frame
//! ([`FRAME_KEY`]): active lane-iterations ÷ (width × subgroup-iterations issued), every
//! instrumented block weighted by how often it ran. That frame figure is the counterpart of
//! nvprof's `warp_execution_efficiency` (Nsight Compute: average active threads per warp ÷
//! warp size), which weights by executed *instructions*: ours weights by executed blocks, and
//! the traversal blocks dominate both.

use super::buffers::{read_back, storage_entry, storage_zeroed};
use super::context::GpuContext;
use super::memory::{MemoryCategory, MemoryLedger};
use anyhow::{bail, Result};
use std::collections::BTreeMap;

/// Slot names, in the order of `shaders/shared/instrument_ids.wgsl`: a megakernel branch and a
/// shade pass per material kind (`layout::material_kind` order).
pub const SLOTS: [&str; FIRST_STEP_SLOT + 12] = [
    "megakernel_bounce",
    "megakernel_material",
    "megakernel_lambertian",
    "megakernel_metal",
    "megakernel_dielectric",
    "megakernel_emissive",
    "generate",
    "intersect",
    "shade_lambertian",
    "shade_metal",
    "shade_dielectric",
    "shade_emissive",
    "shade",
    "megakernel_shadow",
    "shadow",
    "megakernel_traverse_inner",
    "megakernel_traverse_leaf",
    "megakernel_traverse_primitive",
    "megakernel_shadow_traverse_inner",
    "megakernel_shadow_traverse_leaf",
    "megakernel_shadow_traverse_primitive",
    "intersect_traverse_inner",
    "intersect_traverse_leaf",
    "intersect_traverse_primitive",
    "shadow_traverse_inner",
    "shadow_traverse_leaf",
    "shadow_traverse_primitive",
];

/// Slots before this one are entry points, counted once per arrival; from it on, traversal
/// steps counted per loop iteration.
pub const FIRST_STEP_SLOT: usize = 7 + 2 * crate::layout::material_kind::COUNT;

/// The frame-level work-weighted figure's key: the counterpart of nvprof's warp execution
/// efficiency.
pub const FRAME_KEY: &str = "warp_execution_efficiency";

/// The prefix of a pass's work-weighted figure (`work:intersect`).
pub const WORK_PREFIX: &str = "work:";

/// The pass a slot's work belongs to: `megakernel` (in the wavefront, its tail), `generate`,
/// `intersect`, `shade` (all material passes) or `shadow`.
pub fn pass_of(slot: &str) -> &'static str {
    if slot.starts_with("megakernel") {
        "megakernel"
    } else if slot.starts_with("shade") {
        "shade"
    } else if slot.starts_with("shadow") {
        "shadow"
    } else if slot.starts_with("intersect") {
        "intersect"
    } else {
        "generate"
    }
}

/// Words per slot in the counter buffer: active lanes, subgroups and available lanes, each a
/// 64-bit count in two words (low, high), as `shaders/shared/instrument_on.wgsl` writes them.
const SLOT_WORDS: usize = 6;

/// Iteration buckets of the coherence counters (`shaders/wavefront/shared/coherence_on.wgsl`): iterations
/// 0..7 one each, then one per power of two from 8 on, the last open-ended.
pub const COHERENCE_BUCKETS: usize = 16;
/// Words per coherence bucket: subgroups, lanes, lines, spread, octants; each 64-bit (low, high).
const COHERENCE_WORDS: usize = 10;
const BUFFER_BYTES: u64 = ((SLOTS.len() * SLOT_WORDS + COHERENCE_BUCKETS * COHERENCE_WORDS) * 4) as u64;

/// Memory and image coherence of the intersect pass's subgroups over a range of iterations
/// (issue 26): with waves the iteration is the bounce; regenerating, refills happen every
/// iteration, so late buckets show what many refills did to the pool's order.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Coherence {
    /// First iteration of the bucket.
    pub first_iteration: u32,
    pub subgroups: u64,
    /// Mean active lanes per subgroup.
    pub lanes: f64,
    /// Mean distinct 64-byte lines per subgroup load of a 16-byte-per-slot path array (1 when
    /// four consecutive slots share a line; one per lane when scattered).
    pub lines: f64,
    /// Mean half-perimeter, in pixels, of the box around a subgroup's lanes' pixels.
    pub pixel_spread: f64,
    /// Mean distinct direction octants of a subgroup's rays (1 when all leave the same way; the
    /// key `--ray-sort` orders by). Absent from reports made before it.
    #[serde(default)]
    pub octants: f64,
}

/// First iteration of coherence bucket `b`.
pub fn coherence_bucket_start(b: usize) -> u32 {
    if b < 8 {
        b as u32
    } else {
        1 << (b - 5)
    }
}

/// The buckets reached, from the coherence counter words.
pub fn decode_coherence(raw: &[u32]) -> Vec<Coherence> {
    let word = |i: usize| raw[i] as u64 | (raw[i + 1] as u64) << 32;
    (0..COHERENCE_BUCKETS)
        .filter_map(|b| {
            let base = b * COHERENCE_WORDS;
            let groups = word(base);
            (groups > 0).then(|| Coherence {
                first_iteration: coherence_bucket_start(b),
                subgroups: groups,
                lanes: word(base + 2) as f64 / groups as f64,
                lines: word(base + 4) as f64 / groups as f64,
                pixel_spread: word(base + 6) as f64 / groups as f64,
                octants: word(base + 8) as f64 / groups as f64,
            })
        })
        .collect()
}

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SimdEfficiency {
    /// Active lanes / available lanes, in [0, 1].
    pub efficiency: f64,
    /// Subgroups that reached the point.
    pub subgroups: u64,
}

pub struct SimdCounters {
    pub layout: wgpu::BindGroupLayout,
    pub bind_group: wgpu::BindGroup,
    buffer: wgpu::Buffer,
}

impl SimdCounters {
    pub fn new(ctx: &GpuContext, memory: &mut MemoryLedger) -> Result<Self> {
        if !ctx.summary.subgroups {
            bail!(
                "--instrument counts lanes with subgroup operations, which {} does not offer",
                ctx.summary.name
            );
        }
        let buffer = memory.track(
            MemoryCategory::Instrumentation,
            storage_zeroed(ctx, "simd counters", BUFFER_BYTES, wgpu::BufferUsages::COPY_SRC)?,
        );
        let layout = ctx.bind_group_layout("simd counters", &[storage_entry(0, false)]);
        let bind_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("simd counters"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() }],
        });
        Ok(Self { layout, bind_group, buffer })
    }

    /// Efficiency of every slot that was reached.
    pub fn read(&self, ctx: &GpuContext) -> Result<BTreeMap<String, SimdEfficiency>> {
        let raw: Vec<u32> = read_back(ctx, &self.buffer, BUFFER_BYTES)?;
        let slots = &raw[..SLOTS.len() * SLOT_WORDS];
        let mut out = decode(slots)?;
        out.extend(work_weighted(slots));
        Ok(out)
    }

    /// The coherence counters of the wavefront's intersect pass, per iteration bucket reached.
    pub fn read_coherence(&self, ctx: &GpuContext) -> Result<Vec<Coherence>> {
        let raw: Vec<u32> = read_back(ctx, &self.buffer, BUFFER_BYTES)?;
        Ok(decode_coherence(&raw[SLOTS.len() * SLOT_WORDS..]))
    }
}

/// Per pass (`work:<pass>`) and over the frame ([`FRAME_KEY`]): active lane-iterations over
/// available lanes of every instrumented point, entry points and traversal steps pooled;
/// `subgroups` is the subgroup-iterations issued. Only passes that ran appear.
pub fn work_weighted(raw: &[u32]) -> BTreeMap<String, SimdEfficiency> {
    let word = |i: usize| raw[i] as u64 | (raw[i + 1] as u64) << 32;
    let mut pools: BTreeMap<String, (u64, u64, u64)> = BTreeMap::new();
    for (i, name) in SLOTS.iter().enumerate() {
        let base = i * SLOT_WORDS;
        let (lanes, groups, available) = (word(base), word(base + 2), word(base + 4));
        if groups == 0 {
            continue;
        }
        for key in [format!("{WORK_PREFIX}{}", pass_of(name)), FRAME_KEY.to_string()] {
            let p = pools.entry(key).or_default();
            p.0 += lanes;
            p.1 += groups;
            p.2 += available;
        }
    }
    pools
        .into_iter()
        .filter(|(_, p)| p.2 > 0)
        .map(|(k, (lanes, groups, available))| {
            (k, SimdEfficiency { efficiency: lanes as f64 / available as f64, subgroups: groups })
        })
        .collect()
}

/// Efficiency of every slot that was reached, from the counter words.
pub fn decode(raw: &[u32]) -> Result<BTreeMap<String, SimdEfficiency>> {
    let word = |i: usize| raw[i] as u64 | (raw[i + 1] as u64) << 32;
    let mut out = BTreeMap::new();
    for (i, name) in SLOTS.iter().enumerate() {
        let base = i * SLOT_WORDS;
        let (lanes, groups, available) = (word(base), word(base + 2), word(base + 4));
        if groups == 0 {
            continue;
        }
        if available == 0 || lanes > available {
            bail!(
                "SIMD counters of {name}: {lanes} active lanes of {available} available in {groups} subgroups \
                 (an entry point that does not hand its subgroup width to instrument_begin?)"
            );
        }
        out.insert(
            name.to_string(),
            SimdEfficiency { efficiency: lanes as f64 / available as f64, subgroups: groups },
        );
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Counts past 2^32 carry into the high word; each subgroup's own width is what is
    /// available, so subgroups of 32 and of 64 lanes count as such.
    #[test]
    fn counters_are_64_bit_and_widths_per_subgroup() {
        let mut raw = vec![0u32; SLOTS.len() * SLOT_WORDS];
        let set = |raw: &mut Vec<u32>, i: usize, v: u64| {
            raw[i] = v as u32;
            raw[i + 1] = (v >> 32) as u32;
        };
        // "intersect" (slot 7): 3·10⁹ subgroups of 32 and 10⁹ of 64 lanes, 75% active.
        let base = 7 * SLOT_WORDS;
        let available = 3_000_000_000u64 * 32 + 1_000_000_000 * 64;
        set(&mut raw, base, available / 4 * 3);
        set(&mut raw, base + 2, 4_000_000_000);
        set(&mut raw, base + 4, available);
        let e = decode(&raw).unwrap();
        assert_eq!(e.len(), 1);
        assert_eq!(e["intersect"], SimdEfficiency { efficiency: 0.75, subgroups: 4_000_000_000 });
        // A slot reached with no width recorded is refused, not divided by zero.
        set(&mut raw, 0, 10);
        set(&mut raw, 2, 1);
        assert!(decode(&raw).unwrap_err().to_string().contains("megakernel_bounce"));
    }

    /// The pooled figures add lanes and widths, not efficiencies: a pass whose traversal runs
    /// many half-empty steps weighs by them, beside its entry point's single full arrival.
    #[test]
    fn work_weighted_pools_points_by_iterations() {
        let mut raw = vec![0u32; SLOTS.len() * SLOT_WORDS];
        let mut put = |slot: &str, lanes: u32, groups: u32, width: u32| {
            let base = SLOTS.iter().position(|s| *s == slot).unwrap() * SLOT_WORDS;
            raw[base] = lanes;
            raw[base + 2] = groups;
            raw[base + 4] = groups * width;
        };
        put("intersect", 8, 1, 8); // entry: full
        put("intersect_traverse_inner", 12, 3, 8); // 3 steps, half empty
        put("shade_metal", 2, 1, 8);
        let w = work_weighted(&raw);
        assert_eq!(w["work:intersect"], SimdEfficiency { efficiency: 20.0 / 32.0, subgroups: 4 });
        assert_eq!(w["work:shade"], SimdEfficiency { efficiency: 0.25, subgroups: 1 });
        assert_eq!(w[FRAME_KEY], SimdEfficiency { efficiency: 22.0 / 40.0, subgroups: 5 });
        assert!(!w.contains_key("work:megakernel"));
    }

    /// The slot order here is the one the shaders index: every `PASS_*` constant of
    /// instrument_ids.wgsl names the slot at its index, and traversals take three slots in
    /// `TRAVERSE_*` order.
    #[test]
    fn slots_match_the_shader_ids() {
        // The ids as naga folds them (computed from the kind count) in a shader that includes them.
        let module = naga::front::wgsl::parse_str(crate::gpu::shaders::MEGAKERNEL.plain()).unwrap();
        let consts: BTreeMap<&str, usize> = module
            .constants
            .iter()
            .filter_map(|(_, c)| match module.global_expressions[c.init] {
                naga::Expression::Literal(naga::Literal::U32(v)) => Some((c.name.as_deref()?, v as usize)),
                _ => None,
            })
            .filter(|(n, _)| n.starts_with("PASS_") || n.starts_with("TRAVERSE_"))
            .collect();
        assert_eq!(consts["PASS_SLOTS"], SLOTS.len());
        let mut checked = 0;
        for (name, &i) in &consts {
            let Some(pass) = name.strip_prefix("PASS_").filter(|p| *p != "SLOTS") else { continue };
            let pass = pass.to_lowercase();
            match pass.strip_suffix("_traverse") {
                Some(t) => {
                    for (k, kind) in ["inner", "leaf", "primitive"].iter().enumerate() {
                        let kind_const = format!("TRAVERSE_{}", kind.to_uppercase());
                        assert_eq!(consts[kind_const.as_str()], k);
                        assert_eq!(SLOTS[i + k], format!("{t}_traverse_{kind}"), "{name}");
                    }
                    assert!(i >= FIRST_STEP_SLOT);
                }
                None => {
                    assert_eq!(SLOTS[i], pass, "{name}");
                    assert!(i < FIRST_STEP_SLOT);
                }
            }
            checked += 1;
        }
        assert_eq!(checked, FIRST_STEP_SLOT + (SLOTS.len() - FIRST_STEP_SLOT) / 3);
    }

    /// Bucket starts match the shader's buckets (8..15 is bucket 8, 1024.. is bucket 15), and
    /// means divide by the bucket's own subgroups.
    #[test]
    fn coherence_buckets_and_means() {
        let starts: Vec<u32> = (0..COHERENCE_BUCKETS).map(coherence_bucket_start).collect();
        assert_eq!(starts, [0, 1, 2, 3, 4, 5, 6, 7, 8, 16, 32, 64, 128, 256, 512, 1024]);
        let mut raw = vec![0u32; COHERENCE_BUCKETS * COHERENCE_WORDS];
        let b = 9 * COHERENCE_WORDS;
        raw[b] = 4;
        raw[b + 2] = 32;
        raw[b + 4] = 12;
        raw[b + 6] = 2;
        raw[b + 7] = 1; // 2^32 + 2 pixels of spread
        raw[b + 8] = 6;
        let c = decode_coherence(&raw);
        assert_eq!(c.len(), 1);
        assert_eq!((c[0].first_iteration, c[0].subgroups, c[0].lanes, c[0].lines), (16, 4, 8.0, 3.0));
        assert_eq!(c[0].pixel_spread, ((1u64 << 32) + 2) as f64 / 4.0);
        assert_eq!(c[0].octants, 1.5);
    }
}
