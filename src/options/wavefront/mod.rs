//! The wavefront's options (`gpu/wavefront/`): one module per knob, each holding its type (a
//! clap `ValueEnum`, the one spelling, or a number with its default and range), its flag with
//! its `--help` text, its row in the config table, its rule (a knob set where it would change
//! nothing is refused) and its pipeline constant where it has one. This file lists them: the
//! options' fields in the flags' order, and the rules in the order they are checked.

pub mod append;
pub mod batches_in_flight;
pub mod chunk_pools;
pub mod compact_states;
pub mod compaction;
pub mod compute_passes;
pub mod launch;
pub mod pool_size;
pub mod queue_order;
pub mod ray_sort;
pub mod refill;
pub mod refill_below;
pub mod scan;
pub mod shade;
pub mod shadow_rays;
pub mod sync_every;
pub mod tail;
pub mod tail_threshold;

pub use self::{
    append::Append,
    batches_in_flight::{BATCHES_IN_FLIGHT, MAX_BATCHES_IN_FLIGHT},
    chunk_pools::{CHUNK_POOLS, MAX_CHUNK_POOLS},
    compact_states::CompactStates,
    compaction::Compaction,
    compute_passes::ComputePasses,
    launch::Launch,
    pool_size::PoolSize,
    queue_order::{QueueOrder, AUTO_SLOT_POOLS},
    ray_sort::RaySort,
    refill::Refill,
    refill_below::DEFAULT_REFILL_BELOW,
    scan::Scan,
    shade::ShadePasses,
    shadow_rays::ShadowRays,
    sync_every::{DEFAULT_SYNC_EVERY, MAX_SYNC_EVERY},
    tail::Tail,
    tail_threshold::DEFAULT_THRESHOLD,
};

use super::knob::{enum_values, flag, knob, Knob, KnobValue, WAVEFRONT};
use super::option_error::{fraction, in_range, OptionError, Problem};
use super::{Named, RunSchedule, Schedule};

/// `wavefront_options! { flag name: Type = default, skip name: Type = default, ... }`: the
/// options' struct, its default, and its clap `Args`: each `flag` knob's module's `Flag`
/// flattened in this order (the order `--help` lists them), each `skip` field set by a flag
/// the command line shares between methods (`cli/job.rs`).
macro_rules! wavefront_options {
    (@update flag $name:ident $o:ident $m:ident) => {
        let mut f = $name::Flag { $name: $o.$name };
        clap::FromArgMatches::update_from_arg_matches(&mut f, $m)?;
        $o.$name = f.$name;
    };
    (@update skip $name:ident $o:ident $m:ident) => {};
    (@augment flag $name:ident $cmd:ident $f:ident) => { <$name::Flag as clap::Args>::$f($cmd) };
    (@augment skip $name:ident $cmd:ident $f:ident) => { $cmd };
    ($($(#[$doc:meta])* $kind:ident $name:ident: $t:ty = $default:expr,)*) => {
        #[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
        pub struct WavefrontOptions {
            $($(#[$doc])* pub $name: $t,)*
        }

        impl Default for WavefrontOptions {
            fn default() -> Self {
                Self { $($name: $default,)* }
            }
        }

        impl clap::FromArgMatches for WavefrontOptions {
            fn from_arg_matches(m: &clap::ArgMatches) -> Result<Self, clap::Error> {
                let mut o = Self::default();
                o.update_from_arg_matches(m)?;
                Ok(o)
            }

            fn update_from_arg_matches(&mut self, m: &clap::ArgMatches) -> Result<(), clap::Error> {
                $(wavefront_options!(@update $kind $name self m);)*
                Ok(())
            }
        }

        impl clap::Args for WavefrontOptions {
            fn augment_args(cmd: clap::Command) -> clap::Command {
                let cmd = cmd.next_help_heading("Wavefront");
                $(let cmd = wavefront_options!(@augment $kind $name cmd augment_args);)*
                cmd
            }

            fn augment_args_for_update(cmd: clap::Command) -> clap::Command {
                let cmd = cmd.next_help_heading("Wavefront");
                $(let cmd = wavefront_options!(@augment $kind $name cmd augment_args_for_update);)*
                cmd
            }
        }
    };
}

wavefront_options! {
    flag pool_size: Option<PoolSize> = None,
    /// Threads per workgroup: `--workgroup-size`, which the command line sets for both GPU
    /// methods.
    skip workgroup_size: u32 = DEFAULT_WORKGROUP_SIZE,
    /// `--compaction on|off` and `--compaction-method` on the command line.
    skip compaction: Compaction = Default::default(),
    flag shade: ShadePasses = Default::default(),
    /// `--schedule`, which the command line sets for both GPU methods.
    skip schedule: Schedule = Schedule::Waves,
    flag sync_every: u32 = DEFAULT_SYNC_EVERY,
    flag batches_in_flight: u32 = BATCHES_IN_FLIGHT,
    flag tail: Tail = Default::default(),
    flag tail_threshold: f64 = DEFAULT_THRESHOLD,
    flag chunk_pools: u32 = CHUNK_POOLS,
    flag scan: Scan = Default::default(),
    flag append: Append = Default::default(),
    flag compute_passes: ComputePasses = Default::default(),
    flag launch: Launch = Default::default(),
    flag shadow_rays: ShadowRays = Default::default(),
    flag queue_order: QueueOrder = Default::default(),
    flag refill_below: f64 = DEFAULT_REFILL_BELOW,
    flag refill: Refill = Default::default(),
    flag compact_states: CompactStates = Default::default(),
    flag ray_sort: RaySort = Default::default(),
}

/// Each knob's range, checked before any rule (the first refusal is the one reported).
const RANGES: &[Range] = &[
    |o| in_range("workgroup_size", o.workgroup_size, 1, MAX_WORKGROUP_SIZE, ""),
    pool_size::range,
    sync_every::range,
    batches_in_flight::range,
    chunk_pools::range,
    tail_threshold::range,
    refill_below::range,
];

/// Every knob's rule, in the order they are checked (the first refusal is the one reported).
const RULES: &[Rule] = &[
    tail::RULE,
    tail_threshold::RULE,
    sync_every::RULE,
    batches_in_flight::RULE,
    chunk_pools::RULE,
    refill_below::RULE,
    compact_states::REGENERATING,
    compact_states::QUEUED,
    queue_order::RULE,
    scan::RULE,
    append::RULE,
    refill::RULE,
    shade::PER_TEXTURE,
    shadow_rays::RULE,
    shade::SORTED,
    ray_sort::RULE,
];

/// The wavefront's options, checked (as [`super::check`]): every range, then every rule.
pub fn check_wavefront(o: &WavefrontOptions) -> Result<(), OptionError> {
    RANGES.iter().try_for_each(|range| range(o))?;
    for rule in RULES {
        let Some((value, text)) = (rule.set)(o) else { continue };
        if let Some((other, values)) = (rule.needs)(o) {
            let problem = Problem::Needs { value, text, why: rule.why, other, values };
            return Err(OptionError { knob: rule.knob, problem });
        }
    }
    Ok(())
}

/// A knob that acts only beside other knobs' values: set away from its default (`set` gives the
/// value as written, and whether it is a name), it needs them (`needs`: the first knob and
/// values missing), or it would change nothing. One rule for every such knob, so a value that
/// does nothing is refused (a sweep drops the combination) instead of accepted.
pub struct Rule {
    knob: &'static str,
    /// What the knob does where it acts.
    why: &'static str,
    set: fn(&WavefrontOptions) -> Option<(String, bool)>,
    needs: fn(&WavefrontOptions) -> Needs,
}

/// A knob's range: the error when its value is outside it.
type Range = fn(&WavefrontOptions) -> Result<(), OptionError>;

/// The knob a rule's knob needs and its values.
type Needs = Option<(&'static str, &'static [&'static str])>;

const REGENERATE: Needs = Some(("schedule", &["regenerate"]));
const QUEUES: Needs = Some(("compaction", &["atomic", "scan"]));
const ATOMIC: Needs = Some(("compaction", &["atomic"]));

fn regenerating(o: &WavefrontOptions) -> Needs {
    if o.schedule == Schedule::Regenerate {
        None
    } else {
        REGENERATE
    }
}

fn queued(o: &WavefrontOptions) -> Needs {
    if o.compaction == Compaction::Off {
        QUEUES
    } else {
        None
    }
}

fn name(on: bool, v: impl Named) -> Option<(String, bool)> {
    on.then(|| (v.name(), true))
}

fn number(on: bool, v: impl ToString) -> Option<(String, bool)> {
    on.then(|| (v.to_string(), false))
}

/// Threads per workgroup of both GPU methods unless `--workgroup-size` says otherwise.
pub const DEFAULT_WORKGROUP_SIZE: u32 = 64;

/// Largest workgroup any knob asks for (WebGPU's limit on `maxComputeInvocationsPerWorkgroup`
/// is 256 by default; adapters allow up to 1024, checked against the device when it runs).
pub const MAX_WORKGROUP_SIZE: u32 = 1024;

impl WavefrontOptions {
    /// `--schedule auto` made concrete ([`Schedule::Auto`]): `regenerate` with the megakernel
    /// tail on a GPU, `waves` on a software adapter. Other schedules stay as given.
    pub fn resolve(mut self, software: bool) -> ResolvedWavefront {
        let schedule = match self.schedule {
            Schedule::Auto if software => RunSchedule::Waves,
            Schedule::Auto => {
                self.tail = Tail::Megakernel;
                RunSchedule::Regenerate
            }
            Schedule::Waves => RunSchedule::Waves,
            Schedule::Regenerate => RunSchedule::Regenerate,
        };
        self.schedule = schedule.into();
        ResolvedWavefront { options: self, schedule }
    }
}

/// The wavefront's options with the schedule resolved: what runs.
#[derive(Clone, Debug, PartialEq)]
pub struct ResolvedWavefront {
    /// The options, `schedule` concrete (what reports record).
    pub options: WavefrontOptions,
    pub schedule: RunSchedule,
}
