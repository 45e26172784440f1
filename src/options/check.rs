//! The one check of a method's options: each knob's range, and each knob that means something
//! only with another's value (the wavefront's rules are its knobs' own, `wavefront/<knob>.rs`).
//! The command line, experiment configs, the replay and the renderers themselves all ask
//! [`check`]; each words the error its own way ([`OptionError::for_cli`],
//! [`OptionError::for_config`]), naming the knob.

use super::option_error::{in_range, OptionError, Problem};
use super::{check_wavefront, MegakernelOptions, Method, MethodOptions, Named, Schedule, MAX_WORKGROUP_SIZE};

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

#[cfg(test)]
mod tests {
    use super::super::{
        Append, CompactStates, Compaction, QueueOrder, RaySort, Refill, Scan, Tail, WavefrontOptions,
        MAX_SYNC_EVERY,
    };
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
