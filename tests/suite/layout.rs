//! Every Rust struct shared with WGSL has the size and field offsets naga computes for its twin.

use std::mem::{offset_of, size_of};
use wavetrace::gpu::shaders;
use wavetrace::layout::*;

/// (size, [(member, offset)]) of WGSL struct `name` in `source`, as naga lays it out.
fn wgsl_layout(source: &str, name: &str) -> (u32, Vec<(String, u32)>) {
    let module = naga::front::wgsl::parse_str(source).expect("shader parses");
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).unwrap();
    let (handle, ty) = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("WGSL struct {name} not found"));
    let naga::TypeInner::Struct { members, span } = &ty.inner else { panic!("{name} is not a struct") };
    assert_eq!(layouter[handle].size, *span);
    (*span, members.iter().map(|m| (m.name.clone().unwrap(), m.offset)).collect())
}

macro_rules! check {
    ($rust:ty, $wgsl:literal, [$($field:ident),*]) => {
        check!($rust, $wgsl, shaders::MEGAKERNEL.plain(), [$($field),*])
    };
    ($rust:ty, $wgsl:literal, $source:expr, [$($field:ident),*]) => {{
        let (size, members) = wgsl_layout($source, $wgsl);
        assert_eq!(size as usize, size_of::<$rust>(), "size of {}", $wgsl);
        let rust: Vec<(String, u32)> = vec![$((stringify!($field).to_string(), offset_of!($rust, $field) as u32)),*];
        assert_eq!(members, rust, "members of {}", $wgsl);
    }};
}

#[test]
fn primitive() {
    check!(PrimitiveRecord, "Primitive", [a, kind, b, radius, c, material]);
}

#[test]
fn material() {
    check!(MaterialRecord, "Material", [color, param, kind, texture, octaves, scale, color2]);
}

#[test]
fn uv_record() {
    check!(UvRecord, "UvRecord", [uv0, du, dv]);
}

#[test]
fn bvh_node() {
    check!(BvhNode, "BvhNode", [min, left_or_first, max, count]);
}

#[test]
fn frame() {
    check!(
        FrameUniform,
        "Frame",
        [
            camera_center,
            has_defocus,
            pixel00_offset,
            width,
            pixel_delta_u,
            height,
            pixel_delta_v,
            max_depth,
            defocus_disk_u,
            seed,
            defocus_disk_v,
            background_kind,
            background_color,
            light_count,
            light_power,
            t_min,
            texture_origin,
            texture_inv_scale
        ]
    );
}

#[test]
fn dispatch() {
    check!(DispatchParams, "Dispatch", [pixel_offset, pixel_count, sample_start, sample_count]);
}

#[test]
fn film_pixel() {
    check!(
        FilmPixel,
        "FilmPixel",
        shaders::ACCUMULATE,
        [sum_hi, invalid, sum_lo, rays_lo, sum_sq_hi, rays_hi, sum_sq_lo, zero]
    );
}

/// The wavefront's knobs reach WGSL as pipeline constants whose values are the options' enum
/// discriminants (`Plan::knob_constants`): each value's name in path_state.wgsl must mean it.
#[test]
fn wavefront_knob_values_match() {
    use wavetrace::options::{Compaction, QueueOrder, ShadePasses};
    let src = shaders::INTERSECT.plain();
    for (name, value) in [
        ("COMPACTION_OFF", Compaction::Off as u32),
        ("COMPACTION_ATOMIC", Compaction::Atomic as u32),
        ("COMPACTION_SCAN", Compaction::Scan as u32),
        ("SHADE_PER_MATERIAL", ShadePasses::PerMaterial as u32),
        ("SHADE_PER_TEXTURE", ShadePasses::PerTexture as u32),
        ("SHADE_SINGLE", ShadePasses::Single as u32),
        ("SHADE_SORTED", ShadePasses::Sorted as u32),
        ("ORDER_ARRIVAL", QueueOrder::Arrival.word()),
        ("ORDER_SLOT", QueueOrder::Slot.word()),
        ("ORDER_SLOT_DEPTH", QueueOrder::SlotDepth.word()),
    ] {
        assert!(src.contains(&format!("const {name}: u32 = {value}u;")), "{name} = {value} in WGSL");
    }
}

#[test]
fn light_entry() {
    check!(LightEntry, "LightEntry", [slot, other, threshold]);
}

#[test]
fn material_kinds_match() {
    let src = shaders::MEGAKERNEL.plain();
    for (name, value) in [
        ("MATERIAL_LAMBERTIAN", material_kind::LAMBERTIAN),
        ("MATERIAL_METAL", material_kind::METAL),
        ("MATERIAL_DIELECTRIC", material_kind::DIELECTRIC),
        ("MATERIAL_EMISSIVE", material_kind::EMISSIVE),
        ("MATERIAL_KIND_COUNT", material_kind::COUNT as u32),
        ("BACKGROUND_SKY", background_kind::SKY),
        ("BACKGROUND_CONSTANT", background_kind::CONSTANT),
    ] {
        assert!(src.contains(&format!("const {name}: u32 = {value}u;")), "{name} = {value} in WGSL");
    }
}

#[test]
fn wave() {
    check!(WaveUniform, "Wave", shaders::INTERSECT.plain(), [pool, chunk, ring, refill_live]);
}

#[test]
fn accumulate_range() {
    check!(AccumulateRange, "Range", shaders::ACCUMULATE, [first, count, ring, pad]);
}

/// The value of WGSL `const name: u32` in `source`, as naga folds it.
fn wgsl_u32(source: &str, name: &str) -> u64 {
    wgsl_u32s(source, &[name])[0]
}

/// The values of WGSL `const`s `names: u32` in `source` (parsed once), as naga folds them.
fn wgsl_u32s(source: &str, names: &[&str]) -> Vec<u64> {
    let module = naga::front::wgsl::parse_str(source).expect("shader parses");
    let value = |name: &str| {
        let (_, c) = module
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("WGSL const {name} not found"));
        match module.global_expressions[c.init] {
            naga::Expression::Literal(naga::Literal::U32(v)) => v as u64,
            ref e => panic!("{name} = {e:?}: not a folded u32"),
        }
    };
    names.iter().map(|n| value(n)).collect()
}

/// Asserts that `regions` (start, length) follow one another from 0 and fill `total`.
fn tiles(what: &str, regions: &[(u64, u64)], total: u64) {
    let mut end = 0;
    for &(start, len) in regions {
        assert_eq!(start, end, "{what}: a region starts where the last ended");
        end = start + len;
    }
    assert_eq!(end, total, "{what}: the regions fill the buffer");
}

/// Adding a material kind renumbers nothing (docs/architecture-and-file-map.md): the queue,
/// counter and argument layout is a function of the kind count, in Rust (`QueueLayout`) and in
/// WGSL (from `MATERIAL_KIND_COUNT`) alike. With this build's kinds and with one more (the WGSL
/// recompiled with the count raised), every slot the shaders fold equals the Rust layout's, the
/// regions still tile their buffers, and each earlier kind keeps its queue and argument slot.
#[test]
fn queue_layout_follows_the_kind_count() {
    use wavetrace::gpu::wavefront::path_state::{self as ps, QueueLayout};
    let count = material_kind::COUNT as u64;
    let declared = format!("const MATERIAL_KIND_COUNT: u32 = {count}u;");
    assert!(shaders::QUEUE_SETUP.contains(&declared), "WGSL counts the kind table's kinds");
    assert_eq!(ps::LAYOUT, QueueLayout::new(count));
    let names = [
        "QUEUE_MATERIAL_0",
        "QUEUE_SHADOW",
        "QUEUE_FREE",
        "QUEUE_COUNT",
        "QUEUE_PATTERN_0",
        "COUNTER_STATS",
        "COUNTER_SHADE_BASE",
        "COUNTER_NEXT_SAMPLE",
        "COUNTER_RING_0",
        "COUNTER_PATTERN_0",
        "ARGS_SHADE_0",
        "ARGS_COMPACT",
        "ARGS_ACCUMULATE",
        "ARGS_PATTERN_0",
    ];
    for kinds in [count, count + 1] {
        let src =
            shaders::QUEUE_SETUP.replace(&declared, &format!("const MATERIAL_KIND_COUNT: u32 = {kinds}u;"));
        let l = QueueLayout::new(kinds);
        let rust = [
            ps::QUEUE_MATERIAL_0,
            l.queue_shadow,
            l.queue_free,
            l.queue_count,
            l.queue_count,
            l.counter_stats,
            l.counter_shade_base,
            l.counter_schedule,
            l.counter_ring,
            l.counter_pattern,
            ps::ARGS_SHADE_0,
            l.args_compact,
            l.args_pattern_0 - 1,
            l.args_pattern_0,
        ];
        for ((name, wgsl), rust) in names.iter().zip(wgsl_u32s(&src, &names)).zip(rust) {
            assert_eq!(wgsl, rust, "{name} with {kinds} material kinds");
        }
        // Queue ids: the ray queues, the material queues, the shadow and free queues.
        tiles("queues", &[(0, 2), (ps::QUEUE_MATERIAL_0, kinds), (l.queue_shadow, 2)], l.queue_count);
        let counters = [
            (0, l.queue_count + 2), // queue counts, the iteration, the scan's positions
            (l.counter_stats, ps::MAX_STATS_BOUNCES * l.queue_count),
            (l.counter_shade_base, kinds),
            (l.counter_schedule, ps::schedule_word::WORDS),
            (l.counter_ring, ps::MAX_RING_CHUNKS),
            (l.counter_pattern, ps::PATTERN_QUEUES),
        ];
        tiles("counters", &counters, l.counter_words);
        // Intersect, the shade passes, the seven fixed slots, the patterns'.
        let args =
            [(0, 1), (ps::ARGS_SHADE_0, kinds), (l.args_compact, 7), (l.args_pattern_0, ps::PATTERN_QUEUES)];
        tiles("arguments", &args, l.args_slots);
    }
    let (now, more) = (QueueLayout::new(count), QueueLayout::new(count + 1));
    assert_eq!(more.queue_count, now.queue_count + 1, "one queue more");
    assert_eq!(more.args_slots, now.args_slots + 1, "one argument slot more");
    assert_eq!(
        more.counter_words,
        now.counter_words + 2 + ps::MAX_STATS_BOUNCES,
        "one queue count, one shade position and a histogram column more"
    );
}

/// The counter words the host reads and writes, and the indirect-argument slots it dispatches
/// from, are where the shaders keep them (shaders/wavefront/shared/path_state.wgsl).
#[test]
fn path_state_counters_and_arguments() {
    use wavetrace::gpu::wavefront::path_state::{self as ps, schedule_word as w};
    let src = shaders::QUEUE_SETUP;
    for (name, word) in [
        ("COUNTER_NEXT_SAMPLE", w::NEXT_SAMPLE),
        ("COUNTER_EMPTY", w::EMPTY),
        ("COUNTER_INDIRECT", w::INDIRECT),
        ("COUNTER_INTERSECTED", w::INTERSECTED),
        ("COUNTER_IDLE", w::IDLE),
        ("COUNTER_FILL_LIMIT", w::FILL_LIMIT),
        ("COUNTER_TAIL_BOUND", w::TAIL_BOUND),
        ("COUNTER_CLAMPED", w::CLAMPED),
        ("COUNTER_STATES_MOVED", w::STATES_MOVED),
        ("COUNTER_COMPACTIONS", w::COMPACTIONS),
        ("COUNTER_COMPACT_FREE", w::COMPACT_FREE),
        ("COUNTER_COMPACT_MISMATCH", w::COMPACT_MISMATCH),
        ("COUNTER_OLDEST", w::OLDEST),
        ("COUNTER_FAILED", w::FAILED),
        ("COUNTER_CLAIMS", w::CLAIMS),
        ("COUNTER_REFILLED_INTERSECT", w::REFILLED_INTERSECT),
        ("COUNTER_REFILLED_SHADE", w::REFILLED_SHADE),
    ] {
        assert_eq!(wgsl_u32(src, name), ps::COUNTER_SCHEDULE + word as u64, "{name}");
    }
    assert_eq!(wgsl_u32(src, "COUNTER_RING_0"), ps::COUNTER_RING, "COUNTER_RING_0");
    assert_eq!(wgsl_u32(src, "COUNTER_STATS"), ps::COUNTER_STATS);
    assert_eq!(wgsl_u32(src, "QUEUE_COUNT"), ps::QUEUE_COUNT);
    assert_eq!(wgsl_u32(src, "QUEUE_SHADOW"), ps::QUEUE_SHADOW);
    assert_eq!(wgsl_u32(src, "QUEUE_MATERIAL_0"), ps::QUEUE_MATERIAL_0);
    assert_eq!(wgsl_u32(src, "SCAN_WG"), ps::SCAN_WG, "the scan's and the sweep's workgroups");
    for (name, slot) in [
        ("ARGS_INTERSECT", ps::ARGS_INTERSECT),
        ("ARGS_SHADE_0", ps::ARGS_SHADE_0),
        ("ARGS_COMPACT", ps::ARGS_COMPACT),
        ("ARGS_SHADOW", ps::ARGS_SHADOW),
        ("ARGS_REGENERATE", ps::ARGS_REGENERATE),
        ("ARGS_TAIL", ps::ARGS_TAIL),
        ("ARGS_COMPACT_STATES_FIND", ps::ARGS_COMPACT_STATES_FIND),
        ("ARGS_COMPACT_STATES_MOVE", ps::ARGS_COMPACT_STATES_MOVE),
        ("ARGS_ACCUMULATE", ps::ARGS_ACCUMULATE),
        ("ARGS_PATTERN_0", ps::ARGS_PATTERN_0),
    ] {
        assert_eq!(wgsl_u32(src, name), slot, "{name}");
    }
}
