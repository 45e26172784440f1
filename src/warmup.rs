//! Warm-up before timing: untimed renders until the device is in the state it will be timed in.
//!
//! A GPU's clocks, power and temperature move under load (and a driver compiles and caches on
//! first use), so a first frame is not a steady one. The timed warm-up renders until the device
//! has done `min_seconds` of work *and* two consecutive frames agree within `agree`, bounded by
//! `max_frames` and `max_seconds`; what it did is recorded ([`WarmupLog`]), so a report says how
//! warm its timings were. Used by `wavetrace render` and by every run of an experiment.

use std::time::Instant;

use anyhow::Result;
use serde::{Deserialize, Serialize};

use crate::gpu::state::GpuState;

/// The timed warm-up's bounds and targets.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TimedWarmup {
    /// Seconds of work (frame time) the device must have done before timing starts.
    pub min_seconds: f64,
    /// Two consecutive frames must agree within this fraction of the smaller one.
    pub agree: f64,
    /// Give up after this many frames, settled or not.
    pub max_frames: u32,
    /// Give up after this many seconds of warm-up (host clock), settled or not.
    pub max_seconds: f64,
}

impl Default for TimedWarmup {
    /// 0.5 s of work and two frames within 5% (the spread above which a run is flagged
    /// unstable), within 50 frames and 10 s.
    fn default() -> Self {
        Self { min_seconds: 0.5, agree: 0.05, max_frames: 50, max_seconds: 10.0 }
    }
}

/// How a run warms up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WarmupPolicy {
    /// Exactly this many untimed renders; 0 starts the timed renders cold.
    Frames(u32),
    /// Until the device is warm and its frames agree (the default for GPU methods).
    Timed(TimedWarmup),
}

impl WarmupPolicy {
    /// How the report spells it: `frames=1`, `none`, or `timed`.
    pub fn name(&self) -> String {
        match self {
            WarmupPolicy::Frames(0) => "none".into(),
            WarmupPolicy::Frames(n) => format!("frames={n}"),
            WarmupPolicy::Timed(_) => "timed".into(),
        }
    }

    /// Renders a progress bar can plan for (a timed warm-up's count is not known before).
    pub fn planned_frames(&self) -> u32 {
        match self {
            WarmupPolicy::Frames(n) => *n,
            WarmupPolicy::Timed(_) => 0,
        }
    }
}

/// One warm-up frame: when it ended, how long it took, and the GPU's state after it (where
/// NVML reads it).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WarmupFrame {
    /// Host seconds from the start of the warm-up to the end of this frame.
    pub at: f64,
    /// The frame's time: frame time for GPU methods (first submission to last completion),
    /// wall time for CPU methods.
    pub seconds: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gpu_state: Option<GpuState>,
}

/// What a run's warm-up did.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WarmupLog {
    /// `none`, `frames=N` or `timed`.
    pub policy: String,
    /// The timed warm-up's targets (timed only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub timed: Option<TimedWarmup>,
    /// Warm-up renders done.
    pub frames: u32,
    /// Their frame times added up.
    pub seconds: f64,
    /// The preheats before them added up (`preheat_seconds`; GPU work that counts towards
    /// `min_seconds` too). Absent in reports from before the preheat.
    #[serde(default)]
    pub preheat_seconds: f64,
    /// Seconds of warm-up work other runs of the same interleaved job did just before on the
    /// same device, which count towards `min_seconds`.
    pub shared_seconds: f64,
    /// Timed: the targets were met before a bound stopped it. Frames: true.
    pub settled: bool,
    /// Every frame, in order.
    pub trace: Vec<WarmupFrame>,
}

impl WarmupLog {
    /// The GPU work this warm-up did: its frames and the preheats before them.
    pub fn work_seconds(&self) -> f64 {
        self.seconds + self.preheat_seconds
    }

    /// A warm-up that rendered nothing.
    pub fn none() -> Self {
        WarmupLog {
            policy: WarmupPolicy::Frames(0).name(),
            timed: None,
            frames: 0,
            seconds: 0.0,
            preheat_seconds: 0.0,
            shared_seconds: 0.0,
            settled: true,
            trace: Vec::new(),
        }
    }
}

/// Warms up with `policy`: `frame` renders once and returns its time and the seconds of preheat
/// before it (GPU work that counts towards `min_seconds` like the frame's); `sample` reads the GPU's
/// state (None where it cannot). `shared_seconds` is warm-up work done just before on the same
/// device (by other runs of an interleaved job), which counts towards `min_seconds`.
pub fn warm_up(
    policy: &WarmupPolicy,
    shared_seconds: f64,
    mut frame: impl FnMut() -> Result<(f64, f64)>,
    sample: impl Fn() -> Option<GpuState>,
) -> Result<WarmupLog> {
    let start = Instant::now();
    let mut log = WarmupLog {
        policy: policy.name(),
        timed: match policy {
            WarmupPolicy::Timed(t) => Some(*t),
            WarmupPolicy::Frames(_) => None,
        },
        frames: 0,
        seconds: 0.0,
        preheat_seconds: 0.0,
        shared_seconds,
        settled: false,
        trace: Vec::new(),
    };
    let mut step = |log: &mut WarmupLog| -> Result<()> {
        let (seconds, preheat) = frame()?;
        log.frames += 1;
        log.seconds += seconds;
        log.preheat_seconds += preheat;
        log.trace.push(WarmupFrame { at: start.elapsed().as_secs_f64(), seconds, gpu_state: sample() });
        Ok(())
    };
    match policy {
        WarmupPolicy::Frames(n) => {
            for _ in 0..*n {
                step(&mut log)?;
            }
            log.settled = true;
        }
        WarmupPolicy::Timed(t) => loop {
            if settled(t, &log) {
                log.settled = true;
                break;
            }
            if log.frames >= t.max_frames || start.elapsed().as_secs_f64() >= t.max_seconds {
                break;
            }
            step(&mut log)?;
        },
    }
    Ok(log)
}

/// The timed warm-up's targets: enough work, and the last two frames within `agree`.
fn settled(t: &TimedWarmup, log: &WarmupLog) -> bool {
    let n = log.trace.len();
    if n < 2 || log.work_seconds() + log.shared_seconds < t.min_seconds {
        return false;
    }
    let (a, b) = (log.trace[n - 2].seconds, log.trace[n - 1].seconds);
    (a - b).abs() <= t.agree * a.min(b)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(policy: WarmupPolicy, shared: f64, times: &[f64]) -> WarmupLog {
        let mut i = 0;
        warm_up(
            &policy,
            shared,
            || {
                let t = times[i.min(times.len() - 1)];
                i += 1;
                Ok((t, 0.0))
            },
            || None,
        )
        .unwrap()
    }

    /// The preheat before each frame is GPU work too: it counts towards `min_seconds`.
    #[test]
    fn preheats_count_towards_the_work() {
        let t = TimedWarmup { min_seconds: 0.5, agree: 0.05, max_frames: 50, max_seconds: 60.0 };
        let frames =
            |preheat: f64| warm_up(&WarmupPolicy::Timed(t), 0.0, || Ok((0.02, preheat)), || None).unwrap();
        let (with, without) = (frames(0.2), frames(0.0));
        assert!(with.settled && without.settled);
        assert_eq!(with.frames, 3, "0.66 s of work after three preheated frames");
        assert_eq!(without.frames, 25, "0.5 s of 0.02 s frames");
        assert!((with.preheat_seconds - 0.6).abs() < 1e-9);
    }

    #[test]
    fn fixed_frames_render_exactly_that_many() {
        let log = run(WarmupPolicy::Frames(3), 0.0, &[1.0, 2.0, 3.0]);
        assert_eq!((log.frames, log.seconds, log.settled), (3, 6.0, true));
        assert_eq!(log.policy, "frames=3");
        assert_eq!(run(WarmupPolicy::Frames(0), 0.0, &[1.0]).frames, 0);
    }

    #[test]
    fn timed_warm_up_waits_for_work_and_agreement() {
        let t = TimedWarmup { min_seconds: 0.5, agree: 0.05, max_frames: 50, max_seconds: 60.0 };
        // A cold first frame, a ramp, then steady 0.1 s frames: settles when 0.5 s of work is
        // done and the last two agree.
        let log = run(WarmupPolicy::Timed(t), 0.0, &[0.3, 0.2, 0.15, 0.1, 0.1, 0.1]);
        assert!(log.settled);
        assert_eq!(log.frames, 5, "{:?}", log.trace);
        // Work done by the job's other runs counts: two agreeing frames suffice.
        let log = run(WarmupPolicy::Timed(t), 1.0, &[0.1, 0.1]);
        assert!(log.settled && log.frames == 2);
        // Frames that never agree stop at the bound, unsettled.
        let t = TimedWarmup { max_frames: 7, ..t };
        let log = run(WarmupPolicy::Timed(t), 0.0, &[0.1, 0.2, 0.1, 0.2, 0.1, 0.2, 0.1, 0.2]);
        assert!(!log.settled);
        assert_eq!(log.frames, 7);
    }
}
