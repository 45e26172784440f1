//! "× megakernel": each run against the fastest megakernel variant of the same job, the figure
//! the results pages, the HTML report and the crossover chart divide by. A job is the scene, the
//! image, its samples, depth, NEE and roulette, and the numerical knobs and stress transform
//! (what is computed, not how it is scheduled): a wavefront with robust ray offsets is measured
//! against the fastest megakernel with robust ray offsets.

use std::collections::BTreeMap;

use serde_json::Value;

use super::report::{ExperimentReport, RunRecord, RunStatus};
use super::stability;

/// The fastest megakernel variant of a job: what "× megakernel" divides by.
#[derive(Clone, Debug, PartialEq)]
pub struct Baseline {
    pub seconds: f64,
    /// The interval of its median (its median where it has none).
    pub interval: (f64, f64),
    /// Its time is not a steady figure ([`stability::Stability::flagged`]).
    pub flagged: bool,
}

/// Job → the fastest megakernel variant's time for that job.
pub fn fastest_megakernel(report: &ExperimentReport) -> BTreeMap<String, Baseline> {
    let threshold = stability::threshold_of(&report.config);
    let mut best: BTreeMap<String, Baseline> = BTreeMap::new();
    for r in report.runs.iter().filter(|r| r.method == "megakernel" && r.status == RunStatus::Ok) {
        if let Some(t) = r.seconds.filter(|t| *t > 0.0) {
            let st = stability::of_run(r, threshold);
            let b = Baseline { seconds: t, interval: st.interval_or(t), flagged: st.flagged() };
            match best.get(&job_key(r)) {
                Some(e) if e.seconds <= t => {}
                _ => {
                    best.insert(job_key(r), b);
                }
            }
        }
    }
    best
}

/// A run against its job's fastest megakernel: the speed-up, its interval, and whether either
/// time is flagged.
#[derive(Clone, Debug, PartialEq)]
pub struct Versus {
    pub ratio: f64,
    pub interval: (f64, f64),
    pub flagged: bool,
}

pub fn versus_megakernel(
    r: &RunRecord,
    fastest: &BTreeMap<String, Baseline>,
    threshold: f64,
) -> Option<Versus> {
    let b = fastest.get(&job_key(r))?;
    let t = r.seconds.filter(|&t| t > 0.0 && r.status == RunStatus::Ok)?;
    let st = stability::of_run(r, threshold);
    Some(Versus {
        ratio: b.seconds / t,
        interval: stability::ratio_interval(b.interval, st.interval_or(t)),
        flagged: b.flagged || st.flagged(),
    })
}

/// A run's job, as a key.
pub fn job_key(r: &RunRecord) -> String {
    let knobs = ["ray_offset", "sphere_hit", "fresnel", "render_space", "scale", "translate"]
        .map(|k| r.options.get(k).map_or(String::new(), Value::to_string))
        .join("|");
    format!("{}|{}x{}|{}|{}|{}|{}|{knobs}", r.scene, r.width, r.height, r.spp, r.max_depth, r.nee, r.roulette)
}
