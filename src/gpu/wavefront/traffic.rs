//! Bytes of path state each wavefront pass reads and writes (issue 44, item 1c): a model of what
//! the shaders name, per item a pass handles (a queued ray, a hit, a shadow ray, a sample), times
//! the item counts the render's queue counters give. Divided by a pass's time it is the pass's
//! achieved bandwidth; per sample, what the wavefront streams that a megakernel keeps in
//! registers.
//!
//! Counted at the granularity the shader code names (a `.xyz` read is 12 bytes, a `.w` write
//! 4), for the common path of each item: a GPU moves whole 32-byte sectors, so this is a lower
//! bound on the memory traffic, and exact for what the layout asks of it. The film and the
//! scene (BVH, primitives, materials) are not path state and are not counted; neither are the
//! single-thread queue-setup passes, nor the state compaction's passes (`--compact-states on`,
//! counted as not modelled) and the ray sort's (`--ray-sort`). The unit test at the end checks
//! every modelled pass against the path-state variables its entry point reaches (naga), so a
//! shader that starts touching a field the model does not know fails it.

use super::path_state::PoolLayout;
use crate::gpu::label;

/// The item counts a render's counters give (summed over its shares).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Items {
    /// Samples (paths started).
    pub samples: u64,
    /// Rays queued for intersect.
    pub rays: u64,
    /// Hits queued for shading, by material kind (`layout::material_kind` order).
    pub hits: [u64; crate::layout::material_kind::COUNT],
    /// Shadow rays queued.
    pub shadow: u64,
    /// Paths the megakernel tail finished.
    pub tail_paths: u64,
    /// Slot visits of the passes that run over every slot of the pool (slot order's sweep, the
    /// slot-order scan): iterations × pool when regenerating, bounces × paths in waves.
    pub slot_visits: u64,
    /// Slots emptied at a regenerating share's start (`regenerate_init`): pool × shares.
    pub init_slots: u64,
    /// Camera rays that hit, and paths that go on from their camera ray's hit (rays traced at
    /// bounce 1): known per bounce in waves (the queue histogram); `None` when regenerating,
    /// whose queues mix bounces, and the model then charges an upper bound (every escape and
    /// hit as a later bounce's, every path as going on from bounce 0).
    pub first_bounce: Option<(u64, u64)>,
    /// (`--refill in-place`) Samples started in the slot of a path that ended in intersect and
    /// in shade, not by the refill pass.
    pub refilled: (u64, u64),
}

/// How the render was configured, as far as the traffic depends on it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shape {
    pub layout: PoolLayout,
    /// `--schedule regenerate`.
    pub regenerate: bool,
    /// Queues appended atomically (`false`: the scan method).
    pub atomic: bool,
    /// Slot order (`--queue-order slot` / `slot-depth`).
    pub slot_order: bool,
    /// Slot order with atomic appends: the sweep after shade.
    pub sweep: bool,
    /// Camera rays made where they are used, not stored (`WaveUniform::camera_in_place`).
    pub camera_in_place: bool,
    /// `--shadow-rays inline`: shade traces each shadow ray it samples and adds what it finds
    /// to the radiance; no shadow pass, nothing else stored.
    pub inline_shadow: bool,
}

/// One pass's modelled traffic.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PassTraffic {
    pub label: String,
    /// Items it handled (rays, hits, shadow rays, samples or slots, per the pass).
    pub items: u64,
    pub bytes_read: u64,
    pub bytes_written: u64,
    /// With per-pass timestamps: the GPU seconds of the passes this entry covers, and the bytes
    /// moved per second over them (the achieved bandwidth, a lower bound as the bytes are).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seconds: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bytes_per_second: Option<f64>,
}

impl PassTraffic {
    /// The GPU passes (labels) this entry's bytes are charged to: one pass, or the shade passes
    /// together (one per material kind, or the single one) and the scan's three.
    pub fn labels(&self) -> Vec<&'static str> {
        match self.label.as_str() {
            "shade" => label::SHADE_BY_KIND
                .iter()
                .chain(&label::SHADE_BY_PATTERN)
                .copied()
                .chain([label::SHADE, label::SHADE_SORTED])
                .collect(),
            "compact" => vec![label::COMPACT_SCAN, label::COMPACT_BLOCKS, label::COMPACT_SCATTER],
            other => [
                label::GENERATE,
                label::REGENERATE,
                label::REGENERATE_INIT,
                label::INTERSECT,
                label::SLOT_SWEEP,
                label::SHADOW,
                label::TAIL,
                label::ACCUMULATE,
                label::ACCUMULATE_RANGE,
            ]
            .into_iter()
            .filter(|l| *l == other)
            .collect(),
        }
    }
}

/// A render's modelled path-state traffic.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StateTraffic {
    /// Bytes read and written per sample, all passes together.
    pub bytes_per_sample: f64,
    pub passes: Vec<PassTraffic>,
    /// The camera rays that hit and the paths that went on from them, as counted
    /// ([`Items::first_bounce`]); absent where they were not, and the figures are upper bounds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub first_bounce: Option<[u64; 2]>,
}

// Bytes of the fields, as the shaders access them.
const VEC4: u64 = 16;
const XYZ: u64 = 12;
const WORD: u64 = 4;
const PATH_SAMPLE: u64 = 8;

impl Shape {
    /// Bytes to put a path on a queue: an atomic append writes its entry; the scan marks its
    /// target (and, in arrival order, its slot) for the scatter pass; in slot order the pass
    /// after shade reads the mark instead.
    fn enqueue(&self) -> u64 {
        match (self.atomic, self.slot_order) {
            (_, true) => WORD,
            (true, false) => WORD,
            (false, false) => 2 * WORD,
        }
    }

    /// Bytes to mark an ended path for the scans (`retire`).
    fn retire(&self) -> u64 {
        if self.slot_order || !self.atomic {
            WORD
        } else {
            0
        }
    }

    /// A path ends (`finish_path`) with its radiance in registers, written once: when
    /// regenerating into the sample ring (its sample index read) and its slot onto the free
    /// list; in waves into `radiance`.
    fn finish(&self) -> (u64, u64) {
        if self.regenerate {
            (PATH_SAMPLE, VEC4 + if self.slot_order { 0 } else { WORD })
        } else {
            (0, VEC4)
        }
    }
}

impl StateTraffic {
    /// Adds each entry's pass time and achieved bandwidth from a render's `timings`, where they
    /// are per pass (timestamps).
    pub fn add_times(&mut self, timings: &crate::gpu::timing::Timings) {
        if !timings.per_pass() {
            return;
        }
        for p in &mut self.passes {
            let seconds: f64 =
                p.labels().iter().filter_map(|l| timings.passes.get(l)).map(|t| t.seconds).sum();
            if seconds > 0.0 {
                p.seconds = Some(seconds);
                p.bytes_per_second = Some((p.bytes_read + p.bytes_written) as f64 / seconds);
            }
        }
    }

    /// The model for a render of `shape` with `items`.
    pub fn model(shape: &Shape, items: &Items) -> Self {
        let (s, n) = (shape, items);
        let f = Flow::new(n);
        let mut passes = Vec::new();
        let mut add = |label: &str, items: u64, read: u64, written: u64| {
            passes.push(PassTraffic {
                label: label.to_string(),
                items,
                bytes_read: read,
                bytes_written: written,
                seconds: None,
                bytes_per_second: None,
            })
        };
        s.start(n, &mut add);
        s.intersect(n, &f, &mut add);
        s.shade(n, &f, &mut add);
        s.compaction(n, &f, &mut add);
        if s.layout.shadow {
            // shadow: the queue entry, weight and light, ray, origin, the primitive it left, and
            // the radiance, which gets the unblocked light and the ray's count.
            let r = WORD + VEC4 + VEC4 + XYZ + WORD + VEC4;
            add(label::SHADOW, n.shadow, n.shadow * r, n.shadow * VEC4);
        }
        if n.tail_paths > 0 {
            // The tail reads the whole path (queue entry, ray, throughput, radiance, sample) and
            // writes the flushed mark and the finished sample into the ring.
            let r = WORD + 4 * VEC4 + PATH_SAMPLE;
            let w = WORD + VEC4;
            add(label::TAIL, n.tail_paths, n.tail_paths * r, n.tail_paths * w);
        }
        // The film's input: each sample's radiance (regenerate: from the ring).
        let label = if s.regenerate { label::ACCUMULATE_RANGE } else { label::ACCUMULATE };
        add(label, n.samples, n.samples * VEC4, 0);

        let total: u64 = passes.iter().map(|p| p.bytes_read + p.bytes_written).sum();
        Self {
            bytes_per_sample: total as f64 / n.samples.max(1) as f64,
            passes,
            first_bounce: n.first_bounce.map(|(h, c)| [h, c]),
        }
    }
}

/// How the counted items divide among the passes' cases.
struct Flow {
    hits: u64,
    escapes: u64,
    /// Paths that end in shade, and those that go on from it.
    shade_ends: u64,
    continuing: u64,
    /// Camera rays that escape and that hit, and paths that go on from a camera ray's hit
    /// (from bounce 0), and those that end there.
    camera_escapes: u64,
    camera_hits: u64,
    first_continuing: u64,
    first_ends: u64,
}

impl Flow {
    fn new(n: &Items) -> Self {
        let hits: u64 = n.hits.iter().sum();
        let escapes = n.rays.saturating_sub(hits);
        // Every sample ends once: escaping in intersect, in shade, or in the tail.
        let shade_ends = n.samples.saturating_sub(escapes + n.tail_paths).min(hits);
        let continuing = hits - shade_ends;
        // Camera rays' escapes and hits read no radiance or throughput (none is stored yet);
        // the paths going on from bounce 0 write their first radiance.
        // Without the per-bounce counts: no camera ray's escape or hit spared a read, and every
        // path charged a first radiance.
        let (camera_escapes, camera_hits, first_continuing) = match n.first_bounce {
            Some((h, c)) => (n.samples.saturating_sub(h).min(escapes), h.min(hits), c.min(continuing)),
            None => (0, 0, continuing.min(n.samples)),
        };
        let first_ends = camera_hits.saturating_sub(first_continuing).min(shade_ends);
        Self {
            hits,
            escapes,
            shade_ends,
            continuing,
            camera_escapes,
            camera_hits,
            first_continuing,
            first_ends,
        }
    }
}

type Add<'a> = dyn FnMut(&str, u64, u64, u64) + 'a;

impl Shape {
    /// Bytes a camera ray's start writes: origin and direction (unless made in place), the
    /// slot's sample and bounce (regenerate).
    fn start_written(&self) -> u64 {
        let camera_ray = if self.camera_in_place { 0 } else { 2 * VEC4 };
        camera_ray + if self.regenerate { PATH_SAMPLE } else { 0 }
    }

    /// (--refill in-place) Bytes a sample started where a path ended writes: its start and queue
    /// entry, written by intersect or shade, instead of the slot's free-list entry (written
    /// there, read by the refill pass).
    fn restart_written(&self) -> u64 {
        let free_w = if self.regenerate && !self.slot_order { WORD } else { 0 };
        (self.start_written() + WORD).saturating_sub(free_w)
    }

    /// Camera rays started by the generate (or refill) pass, and (regenerate) the slots emptied
    /// at a share's start.
    fn start(&self, n: &Items, add: &mut Add) {
        // The queue entry (waves: written, and the slot-order mark; regenerate: the free slot
        // read and the ray queue entry written). (A wave's camera rays made in place need no
        // queue: intersect takes its slots in order.)
        let (start_qr, start_qw) = match (self.regenerate, self.camera_in_place) {
            (true, _) => (WORD, WORD),
            (false, true) => (0, 0),
            (false, false) => (0, WORD),
        };
        let slot_mark = if self.slot_order && !self.regenerate { WORD } else { 0 };
        let label = if self.regenerate { label::REGENERATE } else { label::GENERATE };
        let (refilled_i, refilled_s) = n.refilled;
        let started = n.samples.saturating_sub(refilled_i + refilled_s);
        let written = self.start_written() + start_qw + slot_mark;
        add(label, started, started * start_qr, started * written);
        if self.regenerate {
            // Every slot freed: its queue entry, dead direction word and slot-order mark.
            let w = WORD + WORD + if self.slot_order { WORD } else { 0 };
            add(label::REGENERATE_INIT, n.init_slots, 0, n.init_slots * w);
        }
    }

    /// intersect: the queue entry, the ray (origin.xyz, direction with the primitive it left; a
    /// camera ray made in place reads only, when regenerating, its sample); a hit writes its
    /// distance and primitive and queues the material; an escape adds the background to the
    /// radiance (past bounce 0: read with the throughput) and ends.
    fn intersect(&self, n: &Items, f: &Flow, add: &mut Add) {
        let (finish_r, finish_w) = self.finish();
        let hit_w = 2 * WORD + self.enqueue();
        let later_escapes = f.escapes - f.camera_escapes;
        // (In place: regenerating, the marked queue entry and the sample; a wave's, nothing.)
        let (camera_rays, camera_read) = match (self.camera_in_place, self.regenerate) {
            (false, _) => (0, 0),
            (true, true) => (n.samples.min(n.rays), WORD + PATH_SAMPLE),
            (true, false) => (n.samples.min(n.rays), 0),
        };
        let read = camera_rays * camera_read
            + (n.rays - camera_rays) * (WORD + XYZ + VEC4)
            + later_escapes * (XYZ + VEC4)
            + f.escapes * finish_r;
        let written = f.hits * hit_w
            + f.escapes * (WORD + self.retire() + finish_w)
            + n.refilled.0 * self.restart_written();
        add(label::INTERSECT, n.rays, read, written);
    }

    /// shade: the queue entry, the ray with its hit, the throughput and MIS density (past bounce
    /// 0), the slot's sample and bounce; a path going on writes its next ray and throughput (and
    /// bounce; from bounce 0 its first radiance) and queues it, and at a diffuse hit with NEE its
    /// shadow ray and weight; an ending path adds what it found to its radiance (past bounce 0:
    /// read) and ends.
    fn shade(&self, n: &Items, f: &Flow, add: &mut Add) {
        let (finish_r, finish_w) = self.finish();
        let shade_r = WORD + 2 * VEC4 + if self.regenerate { PATH_SAMPLE } else { 0 };
        // A camera hit made in place reads its hit's distance and primitive, not the ray.
        let camera_spared = if self.camera_in_place { 2 * VEC4 - 2 * WORD } else { 0 };
        let go_w = 3 * VEC4 + if self.regenerate { WORD } else { 0 } + self.enqueue();
        let end_w = WORD + self.retire() + finish_w;
        // A shadow ray queued: its ray and weight (and queue entry) written for the shadow pass;
        // traced inline: the radiance read and written with what it found (an upper bound: from
        // bounce 0 no radiance is read, and the write repeats the first one).
        let (shadow_r, shadow_w) = if self.inline_shadow {
            (VEC4, VEC4)
        } else {
            (0, 2 * VEC4 + if self.atomic && !self.slot_order { WORD } else { 0 })
        };
        let read = n.shadow * shadow_r
            + f.hits * shade_r
            + (f.hits - f.camera_hits) * VEC4
            + f.shade_ends * finish_r
            + (f.shade_ends - f.first_ends) * VEC4
            - f.camera_hits * camera_spared;
        let written = f.continuing * go_w
            + f.first_continuing * VEC4
            + f.shade_ends * end_w
            + n.shadow * shadow_w
            + n.refilled.1 * self.restart_written();
        add("shade", f.hits, read, written);
    }

    /// The pass that builds the next queues from marks: slot order's sweep, or the scan.
    fn compaction(&self, n: &Items, f: &Flow, add: &mut Add) {
        if self.sweep {
            // Every slot's mark read; continuing rays, shadow rays and (regenerate) ended paths'
            // slots appended.
            let queued_shadow = if self.inline_shadow { 0 } else { n.shadow };
            let appends = f.continuing + queued_shadow + if self.regenerate { n.samples } else { 0 };
            add(label::SLOT_SWEEP, n.slot_visits, n.slot_visits * WORD, appends * WORD);
        } else if !self.atomic || self.slot_order {
            // The scan: each position's mark read by the scan and the scatter, its offset written
            // and read, its slot read (arrival order), its queue entry written; after intersect
            // (scan method: the material queues) and after shade (the next ray queue).
            let per = 2 * WORD + 2 * WORD + if self.slot_order { 0 } else { WORD };
            let after_shade = if self.slot_order { n.slot_visits } else { f.hits };
            let positions = after_shade + if self.atomic { 0 } else { n.rays };
            let entries = f.continuing + if self.atomic { 0 } else { f.hits };
            add("compact", positions, positions * (per - WORD), positions * WORD + entries * WORD);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    fn shape(regenerate: bool, atomic: bool, slot_order: bool, nee: bool) -> Shape {
        let sweep = slot_order && atomic;
        Shape {
            layout: PoolLayout {
                targets: slot_order || !atomic,
                scan: !atomic || (slot_order && !sweep),
                shadow: nee,
                ring_samples: regenerate.then_some(1 << 20),
                pattern_queues: false,
            },
            regenerate,
            atomic,
            slot_order,
            sweep,
            camera_in_place: false,
            inline_shadow: false,
        }
    }

    /// A wave of 100 samples: 100 camera rays, 60 hit (40 escape); 50 of the hits go on and are
    /// traced at bounce 1 (all escape), 10 end; 20 shadow rays. Every sample ends once.
    fn small_wave() -> Items {
        Items {
            samples: 100,
            rays: 150,
            hits: [40, 20, 0, 0],
            shadow: 20,
            first_bounce: Some((60, 50)),
            ..Default::default()
        }
    }

    #[test]
    fn the_model_adds_up_a_small_wave() {
        let items = small_wave();
        let t = StateTraffic::model(&shape(false, true, false, true), &items);
        let pass = |l: &str| t.passes.iter().find(|p| p.label == l).unwrap().clone();
        // generate: origin and direction, and the queue entry, per sample.
        assert_eq!(pass("generate").bytes_written, 100 * (2 * 16 + 4));
        // intersect: 150 rays read (entry, origin.xyz, direction); the 50 escapes past bounce 0
        // read throughput.xyz and radiance; 60 hits write 12 bytes; 90 escapes write the dead
        // word and the radiance.
        assert_eq!(pass("intersect").bytes_read, 150 * 32 + 50 * 28);
        assert_eq!(pass("intersect").bytes_written, 60 * 12 + 90 * 20);
        // shade: 60 camera hits read 36 bytes (no throughput); 50 go on (52 bytes and their
        // first radiance), 10 end (dead word and radiance); 20 shadow rays and weights queued.
        assert_eq!(pass("shade").bytes_read, 60 * 36);
        assert_eq!(pass("shade").bytes_written, 50 * (52 + 16) + 10 * 20 + 20 * 36);
        assert_eq!(pass("shadow").bytes_read, 20 * 68);
        assert_eq!(pass("shadow").bytes_written, 20 * 16);
        let total: u64 = t.passes.iter().map(|p| p.bytes_read + p.bytes_written).sum();
        assert_eq!(t.bytes_per_sample, total as f64 / 100.0);
        // Camera rays made in place: generate writes nothing (a wave's queue is its slots),
        // intersect reads nothing for its 100 camera rays, shade 24 bytes less per camera hit.
        let in_place = Shape { camera_in_place: true, ..shape(false, true, false, true) };
        let t2 = StateTraffic::model(&in_place, &items);
        let pass2 = |l: &str| t2.passes.iter().find(|p| p.label == l).unwrap().clone();
        assert_eq!(pass2("generate").bytes_written, 0);
        assert_eq!(pass2("intersect").bytes_read, 50 * 32 + 50 * 28);
        assert_eq!(pass2("shade").bytes_read, 60 * (36 - 24));
        assert_eq!(pass2("shade").bytes_written, pass("shade").bytes_written);
        // Without the per-bounce counts (regenerating) the model charges at least as much.
        let bound =
            StateTraffic::model(&shape(false, true, false, true), &Items { first_bounce: None, ..items });
        assert!(bound.bytes_per_sample > t.bytes_per_sample);
    }

    /// A regenerating render's samples started in place (`--refill in-place`) move their start
    /// from the refill pass to intersect and shade, and skip the free list: 8 bytes less each
    /// (the free entry written and read), the rest of the model unchanged. (The small wave's
    /// counts, regenerating: its queues mix bounces, so no first-bounce counts.)
    #[test]
    fn refills_in_place_skip_the_free_list() {
        let items = Items { slot_visits: 1000, init_slots: 10, first_bounce: None, ..small_wave() };
        let s = Shape { camera_in_place: true, ..shape(true, true, false, true) };
        let pass = StateTraffic::model(&s, &items);
        let fused = StateTraffic::model(&s, &Items { refilled: (30, 25), ..items });
        let get = |t: &StateTraffic, l: &str| t.passes.iter().find(|p| p.label == l).unwrap().clone();
        let regen = (get(&pass, "regenerate"), get(&fused, "regenerate"));
        assert_eq!(regen.1.items, 45);
        // The refill pass: a free entry read, the sample (8) and a queue entry written each.
        assert_eq!(regen.0.bytes_read - regen.1.bytes_read, 55 * 4);
        assert_eq!(regen.0.bytes_written - regen.1.bytes_written, 55 * 12);
        // Where the paths end: the sample and the queue entry, not the free entry.
        assert_eq!(get(&fused, "intersect").bytes_written - get(&pass, "intersect").bytes_written, 30 * 8);
        assert_eq!(get(&fused, "shade").bytes_written - get(&pass, "shade").bytes_written, 25 * 8);
        let total = |t: &StateTraffic| t.passes.iter().map(|p| p.bytes_read + p.bytes_written).sum::<u64>();
        assert_eq!(total(&pass) - total(&fused), 55 * 8);
    }

    /// Every entry of the model is charged to passes that exist (their static labels), so its
    /// time can be found.
    #[test]
    fn every_entry_names_its_passes() {
        for regenerate in [false, true] {
            for (atomic, slot_order) in [(true, false), (true, true), (false, false), (false, true)] {
                let items = Items { samples: 10, rays: 10, tail_paths: 1, ..Default::default() };
                let t = StateTraffic::model(&shape(regenerate, atomic, slot_order, true), &items);
                for p in &t.passes {
                    assert!(!p.labels().is_empty(), "{}: no pass label", p.label);
                }
            }
        }
    }

    /// Path-state variables, as `shaders/wavefront/shared/path_state.wgsl` names them.
    const STATE: [&str; 12] = [
        "path_origin",
        "path_dir",
        "path_throughput",
        "radiance",
        "queues",
        "next_queue",
        "scan_offset",
        "scan_slot",
        "shadow_ray",
        "shadow_weight",
        "path_sample",
        "samples",
    ];

    /// The path-state variables an entry point of `source` reaches (through the functions it
    /// calls), read or written.
    fn reached(source: &str, entry: &str) -> BTreeSet<String> {
        let module = naga::front::wgsl::parse_str(source).expect("the composed shader parses");
        let m = crate::gpu::stage_cache::reached(&module, entry).expect("entry point");
        let names = m.global_variables.iter().filter_map(|(_, g)| g.name.clone());
        names.filter(|n| STATE.contains(&n.as_str())).collect()
    }

    /// The fields the model charges a pass with, under any of the shapes.
    fn modelled(label: &str) -> BTreeSet<String> {
        // What intersect and shade both reach.
        let path =
            "queues path_origin path_dir path_throughput radiance next_queue scan_slot path_sample samples";
        let fields: String = match label {
            // shadow_weight: cleared without queues only, where the model does not apply.
            "generate" => "path_origin path_dir shadow_weight queues next_queue path_sample".into(),
            "regenerate" => "path_origin path_dir shadow_weight queues path_sample".into(),
            "regenerate_init" => "queues path_dir next_queue shadow_weight".into(),
            // shadow_weight: reached through a refill in place's `start_path`, which clears it
            // without queues only (a refill in place needs them).
            "intersect" => format!("{path} shadow_weight"),
            "shade" => format!("{path} shadow_ray shadow_weight"),
            "shadow" => "queues shadow_weight shadow_ray path_origin path_dir radiance".into(),
            "tail" => "queues path_origin path_dir path_throughput radiance path_sample samples".into(),
            "slot_sweep" => "next_queue queues".into(),
            other => panic!("no model for {other}"),
        };
        fields.split_whitespace().map(str::to_string).collect()
    }

    /// Each modelled pass's shader reaches exactly the path-state variables the model charges it
    /// with: a field added to a pass, or dropped from it, must be added to (or dropped from) the
    /// model too.
    #[test]
    fn the_model_names_what_each_pass_reaches() {
        use crate::gpu::shaders;
        let cases = [
            (shaders::GENERATE.plain(), "generate"),
            (shaders::GENERATE.plain(), "regenerate"),
            (shaders::GENERATE.plain(), "regenerate_init"),
            (shaders::INTERSECT.plain(), "intersect"),
            (shaders::SHADE.plain(), "shade"),
            (shaders::SHADE.plain(), "shade_sorted"),
            (shaders::SHADE.plain(), "shade_lambertian"),
            (shaders::SHADE.plain(), "shade_noise"),
            (shaders::SHADOW.plain(), "shadow"),
            (shaders::TAIL.plain(), "tail"),
            (shaders::SLOT_SWEEP.plain(), "slot_sweep"),
        ];
        let mut wrong = Vec::new();
        for (source, entry) in cases {
            let model = modelled(if entry.starts_with("shade") { "shade" } else { entry });
            let shader = reached(source, entry);
            if shader != model {
                wrong.push(format!("{entry}: the shader reaches {shader:?}, the model charges {model:?}"));
            }
        }
        assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    }
}
