//! Every rule between a method's options, stated once: each knob's range, and each knob that
//! means something only with another's value. The command line, experiment configs, the replay
//! and the renderers themselves all ask [`check`]; each words the error its own way
//! ([`OptionError::for_cli`], [`OptionError::for_config`]), naming the knob.

use super::{
    Append, CompactStates, Compaction, Method, MethodOptions, QueueOrder, RaySort, Scan, Schedule,
    ShadePasses, Tail, BATCHES_IN_FLIGHT, CHUNK_POOLS, DEFAULT_REFILL_BELOW, DEFAULT_SYNC_EVERY,
    DEFAULT_THRESHOLD, MAX_BATCHES_IN_FLIGHT, MAX_CHUNK_POOLS, MAX_SYNC_EVERY,
};
use super::{MegakernelOptions, Named, PoolSize, Refill, ShadowRays, WavefrontOptions};

/// Largest workgroup any knob asks for (WebGPU's limit on `maxComputeInvocationsPerWorkgroup`
/// is 256 by default; adapters allow up to 1024, checked against the device when it runs).
pub const MAX_WORKGROUP_SIZE: u32 = 1024;

/// A knob set to a value its method cannot run.
#[derive(Clone, Debug, PartialEq)]
pub struct OptionError {
    /// The knob at fault, as configs and reports spell it (`tail`; the flag is `--tail`).
    pub knob: &'static str,
    pub problem: Problem,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Problem {
    /// Outside the knob's range: what it must be.
    Range(String),
    /// The value (as written, quoted in configs when `text`) means something only when `other`
    /// is one of `values`: `why` says what it does.
    Needs {
        value: String,
        text: bool,
        why: &'static str,
        other: &'static str,
        values: &'static [&'static str],
    },
}

impl OptionError {
    fn range(knob: &'static str, reason: String) -> Self {
        Self { knob, problem: Problem::Range(reason) }
    }

    /// As the command line says it: `--tail megakernel finishes regenerated paths: it needs
    /// --schedule regenerate`.
    pub fn for_cli(&self) -> String {
        self.for_cli_where_regenerating_is("--schedule regenerate")
    }

    /// As [`Self::for_cli`], for a command whose flag for regenerating is another (the replay's
    /// `--methods wavefront-regenerate`).
    pub fn for_cli_where_regenerating_is(&self, regenerating: &str) -> String {
        let flag = |k: &str| format!("--{}", k.replace('_', "-"));
        match &self.problem {
            Problem::Range(r) => format!("{} {r}", flag(self.knob)),
            Problem::Needs { value, why, other, values, .. } => {
                let want = match *other {
                    "schedule" => regenerating.to_owned(),
                    // The command line turns queues on and off with --compaction on|off, and
                    // chooses how they are built with --compaction-method.
                    "compaction" if values == &["atomic"] => {
                        "--compaction on and --compaction-method atomic".to_owned()
                    }
                    "compaction" if values == &["scan"] => {
                        "--compaction on and --compaction-method scan (or --queue-order slot-depth)"
                            .to_owned()
                    }
                    "compaction" => "--compaction on".to_owned(),
                    _ => format!("{} {}", flag(other), values.join(" or ")),
                };
                format!("{} {value} {why}: it needs {want}", flag(self.knob))
            }
        }
    }

    /// As a config says it, at `methods[i].<knob>`: `"megakernel" finishes regenerated paths:
    /// it needs "schedule": "regenerate"`.
    pub fn for_config(&self) -> String {
        match &self.problem {
            Problem::Range(r) => r.clone(),
            Problem::Needs { value, text, why, other, values } => {
                let value = if *text { format!("{value:?}") } else { value.clone() };
                // A number as JSON writes it, a name quoted.
                let want: Vec<String> = values
                    .iter()
                    .map(|v| if v.parse::<f64>().is_ok() { v.to_string() } else { format!("{v:?}") })
                    .collect();
                format!("{value} {why}: it needs \"{other}\": {}", want.join(" or "))
            }
        }
    }

    /// Whether the value is wrong in itself (not only beside another knob's).
    pub fn is_range(&self) -> bool {
        matches!(self.problem, Problem::Range(_))
    }
}

impl std::fmt::Display for OptionError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.for_cli())
    }
}

impl std::error::Error for OptionError {}

/// The options `method` would run with, checked: every range first, then every rule between
/// knobs. `schedule: auto` counts as not regenerating (a config cannot know what it resolves
/// to); the renderers check after resolving it.
pub fn check(method: Method, o: &MethodOptions) -> Result<(), OptionError> {
    check_bvh(o)?;
    match method {
        Method::Cpu | Method::CpuF64 => Ok(()),
        Method::Megakernel => check_megakernel(&o.megakernel),
        Method::Wavefront => check_wavefront(&o.wavefront),
    }
}

/// Every method's BVH knobs: `collapse` acts only on the wide layout.
pub fn check_bvh(o: &MethodOptions) -> Result<(), OptionError> {
    use crate::bvh::{collapse::Collapse, BvhLayout};
    if o.collapse != Collapse::default() && o.bvh != BvhLayout::Wide {
        let value = o.collapse.name();
        let why = "collapses the binary build into 8-wide nodes";
        let problem = Problem::Needs { value, text: true, why, other: "bvh", values: &["wide"] };
        return Err(OptionError { knob: "collapse", problem });
    }
    Ok(())
}

/// The megakernel's options, checked (as [`check`]).
pub fn check_megakernel(o: &MegakernelOptions) -> Result<(), OptionError> {
    in_range("workgroup_size", o.workgroup_size, 1, MAX_WORKGROUP_SIZE, "")?;
    if o.samples_per_dispatch == 0 {
        return Err(OptionError::range("samples_per_dispatch", "must be at least 1".into()));
    }
    if o.threads == Some(0) {
        return Err(OptionError::range("threads", "must be at least 1".into()));
    }
    if let Some(t) = o.threads {
        needs_regenerate(
            "threads",
            t.to_string(),
            false,
            "sets the regenerating megakernel's persistent threads",
            o.schedule,
        )?;
    }
    Ok(())
}

/// The wavefront's options, checked (as [`check`]).
pub fn check_wavefront(o: &WavefrontOptions) -> Result<(), OptionError> {
    in_range("workgroup_size", o.workgroup_size, 1, MAX_WORKGROUP_SIZE, "")?;
    if o.pool_size == Some(PoolSize::Paths(0)) {
        return Err(OptionError::range("pool_size", "must be at least 1".into()));
    }
    in_range("sync_every", o.sync_every, 1, MAX_SYNC_EVERY, " iterations")?;
    in_range("batches_in_flight", o.batches_in_flight, 1, MAX_BATCHES_IN_FLIGHT, " batches")?;
    in_range("chunk_pools", o.chunk_pools, 1, MAX_CHUNK_POOLS, " pools")?;
    fraction("tail_threshold", o.tail_threshold, "a fraction of the pool")?;
    fraction("refill_below", o.refill_below, "a live fraction of the pool")?;

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
/// The knob a rule's knob needs and its values.
type Needs = Option<(&'static str, &'static [&'static str])>;

struct Rule {
    knob: &'static str,
    /// What the knob does where it acts.
    why: &'static str,
    set: fn(&WavefrontOptions) -> Option<(String, bool)>,
    needs: fn(&WavefrontOptions) -> Needs,
}

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

/// Every such knob, in the order they are checked (the first refusal is the one reported).
const RULES: &[Rule] = &[
    Rule {
        knob: "tail",
        why: "finishes regenerated paths",
        set: |o| name(o.tail == Tail::Megakernel, o.tail),
        needs: regenerating,
    },
    Rule {
        knob: "tail_threshold",
        why: "sets when the megakernel tail takes over",
        set: |o| number(o.tail_threshold != DEFAULT_THRESHOLD, o.tail_threshold),
        needs: |o| {
            regenerating(o).or(if o.tail == Tail::Megakernel {
                None
            } else {
                Some(("tail", &["megakernel"]))
            })
        },
    },
    Rule {
        knob: "sync_every",
        why: "sets the iterations between the regenerating schedule's checks",
        set: |o| number(o.sync_every != DEFAULT_SYNC_EVERY, o.sync_every),
        needs: regenerating,
    },
    Rule {
        knob: "batches_in_flight",
        why: "sets the regenerating schedule's batches in flight",
        set: |o| number(o.batches_in_flight != BATCHES_IN_FLIGHT, o.batches_in_flight),
        needs: regenerating,
    },
    Rule {
        knob: "chunk_pools",
        why: "sizes the regenerating sample ring",
        set: |o| number(o.chunk_pools != CHUNK_POOLS, o.chunk_pools),
        needs: regenerating,
    },
    Rule {
        knob: "refill_below",
        why: "batches the refills of regenerated paths",
        set: |o| number(o.refill_below != DEFAULT_REFILL_BELOW, o.refill_below),
        needs: regenerating,
    },
    Rule {
        knob: "compact_states",
        why: "compacts the pool before refills",
        set: |o| name(o.compact_states == CompactStates::On, o.compact_states),
        needs: regenerating,
    },
    Rule {
        knob: "compact_states",
        why: "rewrites the ray queue's entries of the paths it moves",
        set: |o| name(o.compact_states == CompactStates::On, o.compact_states),
        needs: queued,
    },
    Rule {
        knob: "queue_order",
        why: "orders the queues",
        set: |o| name(o.queue_order.is_slot(), o.queue_order),
        needs: queued,
    },
    Rule {
        knob: "scan",
        why: "sets how the scan compaction (and slot-depth order's scan) scans",
        set: |o| name(o.scan != Scan::Auto, o.scan),
        needs: |o| {
            let scans = o.compaction == Compaction::Scan
                || (o.compaction != Compaction::Off && o.queue_order == QueueOrder::SlotDepth);
            (!scans).then_some(("compaction", &["scan"]))
        },
    },
    Rule {
        knob: "append",
        why: "sets how paths are appended to queues",
        set: |o| name(o.append != Append::Auto, o.append),
        needs: queued,
    },
    Rule {
        knob: "refill",
        why: "starts samples where paths end, appending their camera rays",
        set: |o| name(o.refill == Refill::InPlace, o.refill),
        needs: |o| {
            regenerating(o)
                .or(if o.compaction == Compaction::Atomic { None } else { ATOMIC })
                .or(if o.refill_below == DEFAULT_REFILL_BELOW {
                    None
                } else {
                    Some(("refill_below", &["1"]))
                })
                .or(if o.compact_states == CompactStates::Off {
                    None
                } else {
                    Some(("compact_states", &["off"]))
                })
        },
    },
    Rule {
        knob: "shade",
        why: "queues each pattern's hits by atomic appends",
        set: |o| name(o.shade == ShadePasses::PerTexture, o.shade),
        needs: |o| if o.compaction == Compaction::Atomic { None } else { ATOMIC },
    },
    Rule {
        knob: "shadow_rays",
        why: "traces shadow rays from the queued hits",
        set: |o| name(o.shadow_rays == ShadowRays::Inline, o.shadow_rays),
        needs: queued,
    },
    Rule {
        knob: "shade",
        why: "shades the material queues end to end",
        set: |o| name(o.shade == ShadePasses::Sorted, o.shade),
        needs: queued,
    },
    Rule {
        knob: "ray_sort",
        why: "sorts the ray queue",
        set: |o| name(o.ray_sort != RaySort::Off, o.ray_sort),
        needs: queued,
    },
];

fn needs_regenerate(
    knob: &'static str,
    value: String,
    text: bool,
    why: &'static str,
    schedule: Schedule,
) -> Result<(), OptionError> {
    if schedule == Schedule::Regenerate {
        return Ok(());
    }
    Err(OptionError {
        knob,
        problem: Problem::Needs { value, text, why, other: "schedule", values: &["regenerate"] },
    })
}

fn in_range(knob: &'static str, v: u32, min: u32, max: u32, unit: &str) -> Result<(), OptionError> {
    if !(min..=max).contains(&v) {
        return Err(OptionError::range(knob, format!("must be in {min}..={max}{unit}, got {v}")));
    }
    Ok(())
}

fn fraction(knob: &'static str, v: f64, what: &str) -> Result<(), OptionError> {
    if !(v > 0.0 && v <= 1.0) {
        return Err(OptionError::range(knob, format!("must be {what} in (0, 1], got {v}")));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wavefront_with(f: impl FnOnce(&mut WavefrontOptions)) -> MethodOptions {
        let mut o = MethodOptions::default();
        f(&mut o.wavefront);
        o
    }

    /// `collapse` acts on the wide layout only, for every method.
    #[test]
    fn collapse_needs_the_wide_layout() {
        use crate::bvh::{collapse::Collapse, BvhLayout};
        let other = if Collapse::default() == Collapse::Sah { Collapse::Greedy } else { Collapse::Sah };
        let o = MethodOptions { collapse: other, ..Default::default() };
        for method in [Method::Cpu, Method::Megakernel] {
            let e = check(method, &o).unwrap_err();
            assert_eq!(e.knob, "collapse");
            assert!(e.for_cli().contains("it needs --bvh wide"), "{}", e.for_cli());
            assert!(e.for_config().contains(r#"it needs "bvh": "wide""#), "{}", e.for_config());
        }
        check(Method::Cpu, &MethodOptions { bvh: BvhLayout::Wide, ..o }).unwrap();
    }

    #[test]
    fn each_rule_names_its_knob_on_the_command_line_and_in_configs() {
        let o = wavefront_with(|w| w.tail = Tail::Megakernel);
        let e = check(Method::Wavefront, &o).unwrap_err();
        assert_eq!(e.knob, "tail");
        assert_eq!(
            e.for_cli(),
            "--tail megakernel finishes regenerated paths: it needs --schedule regenerate"
        );
        assert_eq!(
            e.for_config(),
            "\"megakernel\" finishes regenerated paths: it needs \"schedule\": \"regenerate\""
        );
        let o = wavefront_with(|w| {
            w.compaction = Compaction::Off;
            w.ray_sort = RaySort::Octant;
        });
        let e = check(Method::Wavefront, &o).unwrap_err();
        assert_eq!(e.for_cli(), "--ray-sort octant sorts the ray queue: it needs --compaction on");
        assert_eq!(
            e.for_config(),
            "\"octant\" sorts the ray queue: it needs \"compaction\": \"atomic\" or \"scan\""
        );
        let o = wavefront_with(|w| w.sync_every = 0);
        let e = check(Method::Wavefront, &o).unwrap_err();
        assert!(e.is_range());
        assert_eq!(e.for_cli(), format!("--sync-every must be in 1..={MAX_SYNC_EVERY} iterations, got 0"));
    }

    #[test]
    fn a_rule_is_met_by_its_other_knob_and_auto_never_meets_one() {
        let mut o = wavefront_with(|w| {
            w.tail = Tail::Megakernel;
            w.refill_below = 0.5;
            w.compact_states = CompactStates::On;
            w.schedule = Schedule::Regenerate;
        });
        assert_eq!(check(Method::Wavefront, &o), Ok(()));
        o.wavefront.schedule = Schedule::Auto;
        assert_eq!(check(Method::Wavefront, &o).unwrap_err().knob, "tail");
        // The megakernel's knobs are not the wavefront's business, nor the other way round.
        o.megakernel.threads = Some(0);
        o.wavefront.schedule = Schedule::Regenerate;
        assert_eq!(check(Method::Wavefront, &o), Ok(()));
        assert_eq!(check(Method::Megakernel, &o).unwrap_err().knob, "threads");
        assert_eq!(check(Method::Cpu, &o), Ok(()));
    }

    /// `--refill in-place` needs regeneration, the atomic method, refills at every iteration and
    /// no state compaction: each refusal names
    /// the knob it needs, as the command line and a config say it.
    #[test]
    fn refills_in_place_name_what_they_need() {
        let fused = |f: fn(&mut WavefrontOptions)| {
            wavefront_with(|w| {
                w.refill = Refill::InPlace;
                w.schedule = Schedule::Regenerate;
                f(w);
            })
        };
        assert_eq!(check(Method::Wavefront, &fused(|_| {})), Ok(()));
        let e = check(Method::Wavefront, &fused(|w| w.refill_below = 0.5)).unwrap_err();
        assert_eq!(e.knob, "refill");
        assert!(e.for_cli().ends_with("it needs --refill-below 1"), "{}", e.for_cli());
        assert!(e.for_config().ends_with("it needs \"refill_below\": 1"), "{}", e.for_config());
        for (f, cli) in [
            (
                (|w: &mut WavefrontOptions| w.schedule = Schedule::Waves) as fn(&mut WavefrontOptions),
                "--schedule regenerate",
            ),
            (|w| w.compaction = Compaction::Scan, "--compaction on and --compaction-method atomic"),
            (|w| w.compact_states = CompactStates::On, "--compact-states off"),
        ] {
            let e = check(Method::Wavefront, &fused(f)).unwrap_err();
            assert!(e.for_cli().ends_with(&format!("it needs {cli}")), "{}", e.for_cli());
        }
    }

    /// A knob set where it changes nothing is refused, naming what it needs: the regenerating
    /// schedule's batching, the tail's threshold, the scan's and the appends' ways.
    #[test]
    fn a_knob_is_accepted_only_where_it_acts() {
        for (f, cli) in [
            (
                (|w: &mut WavefrontOptions| w.sync_every = 2) as fn(&mut WavefrontOptions),
                "--sync-every 2 sets the iterations between the regenerating schedule's checks: it needs --schedule regenerate",
            ),
            (|w| w.batches_in_flight = 1, "--batches-in-flight 1 sets the regenerating schedule's batches in flight: it needs --schedule regenerate"),
            (|w| w.tail_threshold = 0.5, "--tail-threshold 0.5 sets when the megakernel tail takes over: it needs --schedule regenerate"),
            (
                |w| {
                    w.schedule = Schedule::Regenerate;
                    w.tail_threshold = 0.5;
                },
                "--tail-threshold 0.5 sets when the megakernel tail takes over: it needs --tail megakernel",
            ),
            (|w| w.scan = Scan::Workgroup, "it needs --compaction on and --compaction-method scan (or --queue-order slot-depth)"),
            (
                |w| {
                    w.compaction = Compaction::Off;
                    w.append = Append::Lane;
                },
                "--append lane sets how paths are appended to queues: it needs --compaction on",
            ),
        ] {
            let e = check(Method::Wavefront, &wavefront_with(f)).unwrap_err().for_cli();
            assert!(e.ends_with(cli), "{e}");
        }
        // Where they act, they are accepted.
        for f in [
            (|w: &mut WavefrontOptions| {
                w.schedule = Schedule::Regenerate;
                w.sync_every = 2;
                w.batches_in_flight = 1;
            }) as fn(&mut WavefrontOptions),
            |w| {
                w.schedule = Schedule::Regenerate;
                w.tail = Tail::Megakernel;
                w.tail_threshold = 0.5;
            },
            |w| {
                w.compaction = Compaction::Scan;
                w.scan = Scan::Workgroup;
            },
            |w| {
                w.queue_order = QueueOrder::SlotDepth;
                w.scan = Scan::Workgroup;
            },
            |w| {
                w.compaction = Compaction::Scan;
                w.append = Append::Lane;
            },
        ] {
            assert_eq!(check(Method::Wavefront, &wavefront_with(f)), Ok(()));
        }
    }

    #[test]
    fn refill_knobs_are_checked_with_the_reason() {
        let (regen, waves, on, off) =
            (Schedule::Regenerate, Schedule::Waves, CompactStates::On, CompactStates::Off);
        let with = |below, compact, schedule, compaction| {
            wavefront_with(|w| {
                w.refill_below = below;
                w.compact_states = compact;
                w.schedule = schedule;
                w.compaction = compaction;
            })
        };
        assert!(check(Method::Wavefront, &with(0.5, on, regen, Compaction::Atomic)).is_ok());
        assert!(check(Method::Wavefront, &with(1.0, off, waves, Compaction::Off)).is_ok());
        for (below, compact, schedule, compaction, says) in [
            (
                0.0,
                off,
                regen,
                Compaction::Atomic,
                "--refill-below must be a live fraction of the pool in (0, 1], got 0",
            ),
            (1.5, off, regen, Compaction::Atomic, "in (0, 1], got 1.5"),
            (f64::NAN, off, regen, Compaction::Atomic, "got NaN"),
            (0.5, off, waves, Compaction::Atomic, "--refill-below 0.5 batches"),
            (
                1.0,
                on,
                waves,
                Compaction::Atomic,
                "--compact-states on compacts the pool before refills: it needs --schedule regenerate",
            ),
            (1.0, on, regen, Compaction::Off, "it needs --compaction on"),
        ] {
            let e =
                check(Method::Wavefront, &with(below, compact, schedule, compaction)).unwrap_err().for_cli();
            assert!(e.contains(says), "{e}");
        }
    }
}
