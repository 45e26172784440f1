//! The wavefront's pass graph: the one statement of what a render records. [`Plan`] turns the
//! resolved options into a [`Graph`], an ordered list of [`Pass`] specs, each with its label
//! (the pipeline's, the WGSL entry point's, the timestamp slot's and the report's), its shader
//! and pipeline constants, its launch, the bind groups it takes, the queues it consumes and
//! produces, and when in an iteration it runs. Everything that used to restate the sequence
//! reads it: the stages build a pipeline per pass (`stages.rs`), the recorder records
//! `for pass in graph` (`drive.rs`), the timer's capacity is the longest iteration's pass count,
//! `wavetrace plan` prints it, and the docs' diagram is generated from it
//! (pbrt-v4's `Render()` loop, Falcor's printable render graphs).

use super::pass::{as_map, Constants};
pub use super::pass::{Binds, Launch, Pass, Phase, Queue, Shader, When};
use super::path_state::ARGS_ACCUMULATE;
use super::plan::Plan;
use super::{
    compact, compact_states, generate, intersect, queue_setup, ray_sort, shade, shadow, slot_sweep, tail,
};
use super::{Tail, WavefrontOptions};
use crate::gpu::label;
use serde::Serialize;

/// A render's passes, in recording order.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Graph {
    /// The knobs as pipeline constants, given to every pass over the path state.
    #[serde(serialize_with = "as_map")]
    pub constants: Vec<(&'static str, f64)>,
    pub passes: Vec<Pass>,
}

impl Graph {
    /// The graph of `plan` for `opts` (resolved): `max_workgroups` is the device's limit that
    /// setup passes clamp indirect arguments to. Reads as the module's pseudocode.
    pub fn new(plan: &Plan, opts: &WavefrontOptions, max_workgroups: u32) -> Graph {
        let workgroup = ("WORKGROUP_SIZE", opts.workgroup_size as f64);
        let stats_bounces = ("STATS_BOUNCES", plan.stats_bounces as f64);
        let c = Constants {
            workgroup,
            stats_bounces,
            setup: [workgroup, stats_bounces, ("MAX_WORKGROUPS", max_workgroups as f64)],
        };
        let mut g = Graph { constants: plan.knob_constants(), passes: vec![] };
        g.passes.push(generate::start(plan, &c));
        if plan.regenerate {
            g.passes.push(queue_setup::pass(label::QUEUE_SETUP_REGENERATE, When::Refill, &c));
            if plan.compact_states {
                g.passes.extend(compact_states::passes(&c));
            }
            g.passes.push(generate::refill(&c));
        }
        g.passes.push(queue_setup::pass(label::QUEUE_SETUP_INTERSECT, When::Always, &c));
        if let Some(bits) = plan.ray_sort_cell_bits {
            g.passes.extend(ray_sort::passes(bits, &c));
        }
        g.passes.push(intersect::pass(plan, &c));
        if plan.scan_materials {
            g.passes.extend(compact::passes(plan, compact::Target::MaterialQueues));
        }
        g.passes.push(queue_setup::pass(label::QUEUE_SETUP_SHADE, When::Always, &c));
        g.passes.extend(shade::passes(plan, opts.shade, &c));
        if plan.uses_scan {
            g.passes.extend(compact::passes(plan, compact::Target::NextRayQueue));
        }
        if plan.uses_sweep {
            g.passes.push(slot_sweep::pass());
        }
        if plan.shadow_pass {
            g.passes.extend(shadow::passes(plan, &c));
        } else if plan.regenerate {
            g.passes.push(queue_setup::decide(label::SCHEDULE_DECIDE, &c));
        }
        if plan.regenerate {
            if opts.tail == Tail::Megakernel {
                g.passes.push(tail::pass(&c));
            }
            g.passes.push(accumulate_pass(
                label::ACCUMULATE_RANGE,
                Phase::Decided,
                Launch::Indirect(ARGS_ACCUMULATE),
            ));
        } else {
            g.passes.push(accumulate_pass(label::ACCUMULATE, Phase::End, Launch::Pixels));
        }
        g
    }

    /// The passes of `phase`.
    pub fn phase(&self, phase: Phase) -> impl Iterator<Item = &Pass> {
        self.passes.iter().filter(move |p| p.phase == phase)
    }

    /// The passes of an iteration that refills (`refill`) and checks (`check`), in order.
    pub fn iteration(&self, refill: bool, check: bool) -> impl Iterator<Item = &Pass> {
        self.phase(Phase::Iteration).filter(move |p| p.runs(refill, check))
    }

    /// The most dispatches any iteration records, with the passes the decision sizes (a
    /// submission's timestamp capacity).
    pub fn per_iteration(&self) -> usize {
        let decided = self.phase(Phase::Decided).count();
        [(false, false), (true, false), (false, true), (true, true)]
            .iter()
            .map(|&(r, c)| self.iteration(r, c).count() + if c { decided } else { 0 })
            .max()
            .unwrap_or(0)
    }

    /// The labels in recording order, each once.
    pub fn labels(&self) -> Vec<&'static str> {
        let mut seen = Vec::new();
        for p in &self.passes {
            if !seen.contains(&p.label) {
                seen.push(p.label);
            }
        }
        seen
    }
}

/// The film's passes (`accumulate.wgsl`, built by [`crate::gpu::accumulate::Accumulate`]): a
/// wave's radiance, or the sample ring's finished chunks.
fn accumulate_pass(label: &'static str, phase: Phase, launch: Launch) -> Pass {
    Pass::new(label, phase, Shader::Accumulate, launch, Binds::Film)
        .unbounced()
        .queues(&[Queue::Samples], &[])
}
